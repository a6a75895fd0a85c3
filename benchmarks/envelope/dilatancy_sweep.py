"""Dilatant soil in the column collapse: does it run, with which steps, and how much energy.

    python benchmarks/envelope/dilatancy_sweep.py OUT.csv --psi 0 5 10 20 31 --h 0.02 0.01 0.005 0.0025
        [--model mohr_coulomb] [--reference-density] [--cutoff EPS_V] [--cfl 0.4] [--end 0.8]

Runs cases/column_collapse.json with materials.soil.dilation_angle = psi and
grid.cell_size = h (nothing else changed, unless --model or --cfl), step by step
with geompm's own health check, and writes one row per run:

    model, psi, h, status (runs / exit 3 with the message), steps, t_end [s],
    dt_first, dt_min [s], max E_k / supply [-], rho_min / rho0 at the end [-],
    plastic volumetric strain max [-], deposit front L [m], wall [s]

``--reference-density`` reproduces the wave speed geompm used before issue 16,
sqrt((lambda + 2G) / rho0), to show what the current-density speed changes.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
import time
from pathlib import Path


from geompm.api import scene_from_dict
from geompm.engine.health import HealthCheck
from geompm.engine.scheduler import Simulation
from geompm.errors import SimulationError
from geompm.writers.deposit import deposit_front

CASE = Path(__file__).resolve().parents[2] / "cases" / "column_collapse.json"
FIELDS = ["model", "cutoff", "psi", "h", "status", "steps", "t_end", "dt_first", "dt_min", "energy_ratio", "rho_min_ratio",
          "eps_v_max", "front", "wall_s"]


def use_reference_density(mat) -> None:
    """Give ``mat`` the wave speed of before issue 16, sqrt((lambda + 2G) / rho0), whatever the density."""
    E = mat.layout
    c0 = math.sqrt((mat.prm[E.lam] + 2 * mat.prm[E.G]) / mat.prm[E.density])
    mat.wave_speed = lambda p_rho: c0


def run_one(model, psi, h, cfl, end, reference_density, cutoff=None):
    sets = [f"materials.soil.dilation_angle={psi}", f"grid.cell_size={h}", f"time.end={end}", f"time.cfl={cfl}"]
    if cutoff is not None:
        sets.append(f"materials.soil.dilation_cutoff={cutoff}")
    raw = json.loads(CASE.read_text())
    if model != "drucker_prager":  # the same soil under another law: drop the DP-only cone
        raw["materials"]["soil"].pop("cone", None)
        raw["materials"]["soil"]["model"] = model
    scene = scene_from_dict(raw, CASE.parent, sets)
    mat = scene.materials[0]
    rho0 = float(mat.prm[mat.layout.density])
    if reference_density:
        use_reference_density(mat)
    sim, check = Simulation(scene), HealthCheck(scene)
    st = sim.state
    dt_first = dt_min = sim.stable_dt()
    ratio, status, t0 = 0.0, "runs", time.perf_counter()
    try:
        while sim.time < end * (1 - 1e-12):
            dt = sim.stable_dt()
            dt_min = min(dt_min, dt)
            dt = min(dt, end - sim.time)
            sim.step(dt)
            check.after_step(sim)
            ratio = max(ratio, check.kinetic_energy / (check.budget0 + check.released + 1e-30))
    except SimulationError as err:
        status = "exit 3: " + str(err).split(" at step")[0]
    wall = time.perf_counter() - t0
    return {"model": model, "cutoff": cutoff, "psi": psi, "h": h, "status": status, "steps": sim.step_count,
            "t_end": round(sim.time, 4), "dt_first": f"{dt_first:.3g}", "dt_min": f"{dt_min:.3g}",
            "energy_ratio": f"{ratio:.3f}", "rho_min_ratio": f"{float(st.p_rho.min()) / rho0:.3f}",
            "eps_v_max": f"{float(st.p_state[0][:, 1].max()):.3f}",
            "front": f"{deposit_front(st.p_x, st.p_mass / rho0, 0.005, 0.001):.4f}", "wall_s": f"{wall:.1f}"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--psi", type=float, nargs="+", default=[0, 5, 10, 20, 31])
    ap.add_argument("--h", type=float, nargs="+", default=[0.02, 0.01, 0.005, 0.0025])
    ap.add_argument("--model", default="drucker_prager")
    ap.add_argument("--cfl", type=float, default=0.4)
    ap.add_argument("--end", type=float, default=0.8)
    ap.add_argument("--reference-density", action="store_true")
    ap.add_argument("--cutoff", type=float, default=None, help="materials.soil.dilation_cutoff")
    a = ap.parse_args(argv)
    out = Path(a.out)
    new = not out.exists()
    with out.open("a", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        if new:
            w.writeheader()
        for h in a.h:
            for psi in a.psi:
                row = run_one(a.model, psi, h, a.cfl, a.end, a.reference_density, a.cutoff)
                w.writerow(row)
                f.flush()
                print(row, flush=True)


if __name__ == "__main__":
    sys.exit(main())
