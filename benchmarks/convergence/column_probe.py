"""Probe the DP column collapse's runout under refinement (issue 15, point 2): one line per cell size.

    python benchmarks/convergence/column_probe.py 0.02 0.01 0.005 --set KEY=VALUE ... [--end 0.8]
    python benchmarks/convergence/column_probe.py 20 40 80 --per-H0 --aspect 2 --L0 0.1

Runs cases/column_collapse.json (a = H0/L0 = 0.5, L0 = 0.2 m; or the column of ``--aspect`` and ``--L0``
in a domain long enough for its runout) through the Python API to t = end and prints the runout
(L - L0)/L0 by two metrics: the furthest particle, and the deposit front at a thickness of 0.05 H0
(geompm.writers.deposit), plus the final height / H0, steps and wall seconds.  With ``--per-H0`` the
numbers are H0/h.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402
from geompm.contract.stages import ParticleStage  # noqa: E402
from geompm.writers.deposit import deposit_front, deposit_height  # noqa: E402

RHO = 2650.0


def column_sets(aspect, L0):
    """--set overrides for a column L0 long and aspect * L0 high, in a domain 1.5 x its Lube runout long."""
    H0 = aspect * L0
    lube = 1.2 * aspect if aspect < 2.3 else 1.9 * aspect ** (2 / 3)
    return [f"bodies.0.geometry.max=[{L0},{H0}]", f"grid.extent=[{L0 * (1.5 + 2.0 * lube):.4g},{1.2 * H0:.4g}]"]


def run(h, sets, end, L0, H0, extra_stages=(), save=None):
    scene = scene_from_file(ROOT / "cases" / "column_collapse.json",
                            [f"grid.cell_size={h}", f"time.end={end}", "outputs=[]", *sets])
    hooks = []
    for stage in extra_stages:
        stage.setup(scene)
        (scene.damping if isinstance(stage, ParticleStage) else hooks).append(stage)
    sim = Simulation(scene)
    for hook in hooks:  # host passes that are no per-particle function: run just before the stress update
        def update_stress(dt, inner=sim.backend.update_stress, hook=hook):
            hook.apply(sim.state)
            inner(dt)
        sim.backend.update_stress = update_stress
    t0 = time.perf_counter()
    st = sim.state
    ke_peak = 0.0
    while sim.time < end:
        sim.step(min(sim.stable_dt(), end - sim.time))
        if sim.step_count % 20 == 0:
            ke_peak = max(ke_peak, 0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum()))
    ke_end = 0.5 * float((st.p_mass * (st.p_v ** 2).sum(axis=1)).sum()) / ke_peak
    if save:
        Path(save).mkdir(parents=True, exist_ok=True)
        np.savez(Path(save) / f"h{h:.5g}.npz", x=st.p_x, v=st.p_v, mass=st.p_mass, stress=st.p_stress)
    far = st.p_x[:, 0].max()
    area = st.p_mass / RHO  # reference (solid) areas: a particle that dilated does not thicken the deposit
    front = deposit_front(st.p_x, area, 0.05 * H0, H0 / 200)
    top = deposit_height(st.p_x, area, H0 / 200, 0.05 * H0)
    return far, front, top, sim.step_count, time.perf_counter() - t0, ke_end


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cell_sizes", nargs="+", type=float)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--end", type=float, default=0.8)
    ap.add_argument("--stage", action="append", default=[], help="module:Class of an extra particle stage")
    ap.add_argument("--aspect", type=float, help="column H0/L0 (default: the case's 0.5 with L0 = 0.2 m)")
    ap.add_argument("--L0", type=float, default=0.1, help="column length with --aspect [m]")
    ap.add_argument("--save", help="folder for the final particles of each run (npz: x, v, mass, stress)")
    ap.add_argument("--per-H0", action="store_true", help="cell sizes given as H0/h")
    a = ap.parse_args()
    L0, H0, sets = 0.2, 0.1, list(a.set)
    if a.aspect:
        L0, H0 = a.L0, a.aspect * a.L0
        sets = column_sets(a.aspect, a.L0) + sets
    import importlib

    stages = [getattr(importlib.import_module(m), c) for m, c in (x.split(":") for x in a.stage)]
    print(f"sets: {sets}, stages: {a.stage}, end {a.end} s")
    print("h [m] | far (L-L0)/L0 | front@0.05H0 (L-L0)/L0 | H/H0 | steps | wall s | KE end/peak")
    for h in a.cell_sizes:
        h = H0 / h if a.per_H0 else h
        far, front, top, steps, wall, ke_end = run(h, sets, a.end, L0, H0, [cls() for cls in stages], a.save)
        print(f"{h:.5g} | {(far - L0) / L0:.3f} | {(front - L0) / L0:.3f} | {top / H0:.3f} | {steps} | {wall:.1f} | {ke_end:.1e}",
              flush=True)


if __name__ == "__main__":
    main()
