"""Why the psi = 0 infinite slope lost strength as the grid was refined (docs/slope-stability.md, The cause).

    python benchmarks/slope_stability/psi0_cause.py OUT_FOLDER [--figure docs/figures/psi0-bands.png]

Runs single strength-reduction trials of the infinite slope (geompm/testing/verification/slopes.py, psi = 0,
phi = 30 deg, beta = 20 deg, T = 2 s, the search's own trial: stability/trial.py) and prints for each the
increment ratio the search judges by (failed at >= 0.5), against the one-dimensional column's (slope_column.py)
for the same trial, and the spread along the slope of the base row's stresses at each quarter of the trial
(a uniform slope has none).  Variants:

- ``none``: the law as it is (Mohr-Coulomb and Drucker-Prager);
- ``relaxed``: solver.viscoplastic_time = T/800 (kernels/viscoplastic.py), the trials' default;
- ``fbar``, ``pressure``, ``stress``: experiments run by wrapping the scheme's stress update in this script
  (not options of geompm): the volumetric strain rate tr(L) replaced by its volume-weighted mean over the
  particle's cell before the law (an F-bar of the rate, the particle volumes corrected to it: Coombs et al.
  2018's cure for volumetric locking), the mean stress, or the whole stress, replaced by its cell mean after
  the law.  The periodic axis folds the cells.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import geompm
from geompm.kernels.volume import det_increment
from geompm.materials.drucker_prager import DruckerPrager
from geompm.materials.mohr_coulomb import MohrCoulomb
from geompm.schema.load import parse_case
from geompm.schemes import base
from geompm.stability.criterion import judge
from geompm.stability.trial import trial_damping, trial_sets
from geompm.testing.verification.slope_column import column_series
from geompm.testing.verification.slopes import infinite_slope_case

TAU = 2.0 / 800.0
LAWS = {"mohr_coulomb": MohrCoulomb, "drucker_prager": DruckerPrager}
ORIGINAL = base.Scheme.stress_update


def _cells(run):
    st, g = run.backend.state, run.scene.grid
    cell = np.floor((st.p_x - g.origin[:st.dim]) / g.h).astype(np.int64)
    cell[:, 0] %= int(g.ncells[0])
    _, inv = np.unique(cell[:, 0] * (int(g.ncells[1]) + 8) + cell[:, 1], return_inverse=True)
    return inv


def _cell_mean(inv, V, f):
    return (np.bincount(inv, weights=V * f) / np.bincount(inv, weights=V))[inv]


def fbar(self, run, dt):
    st = run.backend.state
    inv = _cells(run)
    tr = st.p_L[:, 0, 0] + st.p_L[:, 1, 1]
    mean = _cell_mean(inv, st.p_vol, tr)
    for p in range(st.n):
        before = det_increment(st.p_L[p].copy(), dt)
        d = 0.5 * (mean[p] - tr[p])
        st.p_L[p, 0, 0] += d
        st.p_L[p, 1, 1] += d
        st.p_vol[p] *= det_increment(st.p_L[p].copy(), dt) / before
        st.p_rho[p] = st.p_mass[p] / st.p_vol[p]
    ORIGINAL(self, run, dt)


def pressure(self, run, dt):
    ORIGINAL(self, run, dt)
    st = run.backend.state
    m = st.p_stress[:, :3].mean(axis=1)
    st.p_stress[:, :3] += (_cell_mean(_cells(run), st.p_vol, m) - m)[:, None]


def stress(self, run, dt):
    ORIGINAL(self, run, dt)
    st = run.backend.state
    inv = _cells(run)
    for a in range(6):
        st.p_stress[:, a] = _cell_mean(inv, st.p_vol, st.p_stress[:, a].copy())


WRAPS = {"fbar": fbar, "pressure": pressure, "stress": stress}


def trial(out: Path, h: float, factor: float, model: str, variant: str) -> dict:
    raw = infinite_slope_case(h, dilation=0.0, model=model)
    loaded = parse_case(raw)
    sets = trial_sets(loaded, factor, 2.0, trial_damping(loaded, 20.0, 0.0), TAU if variant == "relaxed" else None)
    sets = [s for s in sets if not s.startswith("outputs=")] + [
        "outputs=" + json.dumps([{"writer": "series", "interval": 0.05, "displacement": True},
                                 {"writer": "vtu", "interval": 0.5}])]
    base.Scheme.stress_update = WRAPS.get(variant, ORIGINAL)
    try:
        run = geompm.run(raw, out=out / f"{model}_{variant}_h{h:g}_F{factor:g}", overwrite=True, overrides=sets,
                         progress=False, quiet=True)
    finally:
        base.Scheme.stress_update = ORIGINAL
    row = judge(run.series, 0.5, h / 1000)
    spreads = []
    for f in run.outputs["vtu"]:
        if str(f).endswith(".vtu"):
            import meshio

            m = meshio.read(f)
            y = m.points[:, 1]
            base_row = y < y.min() + h / 2
            spreads.append(float(m.point_data["stress"][base_row, 1].std()))
    row["base_syy_spread_kPa"] = [round(s / 1e3, 2) for s in spreads]
    row["folder"] = str(run.folder) if hasattr(run, "folder") else ""
    return row


def figure(out: Path, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import meshio

    panels = [("mohr_coulomb_none_h0.025_F1.3", "Mohr-Coulomb, inviscid"),
              ("drucker_prager_none_h0.025_F1.3", "Drucker-Prager, inviscid"),
              ("mohr_coulomb_relaxed_h0.025_F1.3", f"Mohr-Coulomb, tau = {TAU * 1e3:g} ms")]
    fig, ax = plt.subplots(1, 3, figsize=(9, 5.5), sharey=True)
    for a, (name, title) in zip(ax, panels):
        files = sorted((out / name / "particles").glob("*.vtu"))
        m = meshio.read(files[-1])
        sc = a.scatter(m.points[:, 0], m.points[:, 1], c=m.point_data["plastic_strain"], s=5, cmap="viridis")
        fig.colorbar(sc, ax=a, label="equivalent plastic strain [-]")
        a.set_title(title, fontsize=9)
        a.set_xlabel("x along the slope [m]")
        a.set_aspect("equal")
    ax[0].set_ylabel("height above the base [m]")
    fig.suptitle("psi = 0 infinite slope, trial F = 1.3, h = 0.025 m, t = 2 s", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--figure", default=None)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    params = dict(density=2000.0, youngs_modulus=2e6, poisson_ratio=0.3, friction_angle=30.0, dilation_angle=0.0,
                  cohesion=0.0, dilation_cutoff=1.0)
    plan = [(0.025, 1.3, "mohr_coulomb", v) for v in ("none", "relaxed", "fbar", "pressure", "stress")]
    plan += [(0.025, 1.3, "drucker_prager", "none"), (0.05, 1.3, "mohr_coulomb", "none"),
             (0.025, 1.45, "mohr_coulomb", "none"), (0.025, 1.45, "mohr_coulomb", "relaxed"),
             (0.0125, 1.45, "mohr_coulomb", "relaxed"), (0.025, 1.45, "drucker_prager", "none")]
    for h, factor, model, variant in plan:
        col = judge(column_series(LAWS[model], params, factor, elements=40,
                                  viscoplastic_time=TAU if variant == "relaxed" else None), 0.5, h / 1000)
        row = trial(out, h, factor, model, variant)
        print(f"{model:15s} {variant:8s} h = {h:<7g} F = {factor:<5g} ratio {row['ratio']:.3f} "
              f"({'failed' if row['failed'] else 'stands'}; column {col['ratio']:.3f}, "
              f"{'failed' if col['failed'] else 'stands'})  base sigma_yy spread along the slope at t = 0.5, 1, "
              f"1.5, 2 s: {row['base_syy_spread_kPa'][1:]} kPa", flush=True)
    if a.figure:
        figure(out, a.figure)
    return 0


if __name__ == "__main__":
    sys.exit(main())
