"""What the held step (solver.held_step, engine/held_step.py) costs and keeps, on the CPU: for each case and each
fraction f, the steps taken, the batches (each one read of the device on backend 'cuda'), the steps per batch,
the largest step over the stable step of the state it starts from (at most 1 by construction), the wall time, and
the result's distance (the front's position and the kinetic energy at the end) from the ordinary run's, and from
that of an ordinary run whose CFL number is f times the case's (the same step size, every step adapted: what
the holding itself changes).

    python benchmarks/held_step_trade.py [--steps 20] [--fractions 1.0 0.95 0.9 0.8] [CASE ...]

Cases (coarsened so that each run takes seconds): the granular column collapse (Drucker-Prager, its stable step
set by the elastic wave speed) and the dam break (a weakly compressible Newtonian fluid whose wave speed follows
its density and whose speeds grow). Prints one table row and one JSON line per run."""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

CASES = {
    "column_collapse": (ROOT / "cases" / "column_collapse.json", ["grid.cell_size=0.02"], 0.3),
    "dam_break": (ROOT / "cases" / "dam_break.json", ["grid.cell_size=0.02"], 0.15),
}


def run(path, sets, until, held, cfl_factor=1.0):
    from geompm.api import scene_from_dict
    from geompm.engine.runner import Runner
    from geompm.engine.scheduler import Simulation

    raw = json.loads(Path(path).read_text())
    raw["outputs"] = []
    if held is not None:
        raw.setdefault("solver", {})["held_step"] = held
    raw["time"]["cfl"] = raw["time"].get("cfl", 0.4) * cfl_factor
    folder = Path(tempfile.mkdtemp())
    sim = Simulation(scene_from_dict(raw, Path(path).parent, sets))
    ratio = [0.0]
    step = sim.step

    def checked(dt):
        ratio[0] = max(ratio[0], dt / sim.backend.stable_dt())
        step(dt)

    sim.step = checked
    runner = Runner(sim, folder, [], progress=False)
    t0 = time.perf_counter()
    runner.run(until=until)
    wall = time.perf_counter() - t0
    st = sim.state
    front = float(st.p_x[:, 0].max())
    ek = float(0.5 * (st.p_mass * (st.p_v ** 2).sum(axis=1)).sum())
    return {"steps": sim.step_count, "batches": runner.held_batches or sim.step_count, "worst_ratio": ratio[0],
            "wall_s": wall, "front_m": front, "kinetic_J": ek, "h": sim.scene.grid.h}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="*")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--fractions", type=float, nargs="*", default=[1.0, 0.95, 0.9, 0.8])
    args = ap.parse_args(argv)
    print(f"{'case':<18}{'fraction':>9}{'steps':>7}{'batches':>9}{'per batch':>10}{'max dt/stable':>15}"
          f"{'front diff/h':>14}{'Ek diff':>10}{'same-cfl front/h':>18}{'same-cfl Ek':>13}{'wall s':>8}")
    for name in args.cases or list(CASES):
        path, sets, until = CASES[name]
        base = run(path, sets, until, None)
        rows = [("ordinary", base, base)]
        rows += [(f, run(path, sets, until, {"steps": args.steps, "fraction": f}), run(path, sets, until, None, f))
                 for f in args.fractions]
        for label, r, same in rows:
            front = abs(r["front_m"] - base["front_m"]) / r["h"]
            ek = abs(r["kinetic_J"] - base["kinetic_J"]) / max(base["kinetic_J"], 1e-30)
            front_same = abs(r["front_m"] - same["front_m"]) / r["h"]
            ek_same = abs(r["kinetic_J"] - same["kinetic_J"]) / max(same["kinetic_J"], 1e-30)
            print(f"{name:<18}{str(label):>9}{r['steps']:>7}{r['batches']:>9}{r['steps'] / r['batches']:>10.2f}"
                  f"{r['worst_ratio']:>15.6f}{front:>14.4f}{ek:>10.2e}{front_same:>18.4f}{ek_same:>13.2e}"
                  f"{r['wall_s']:>8.1f}")
            print(json.dumps({"case": name, "fraction": label, "held_steps": args.steps, **r,
                              "front_diff_cells": front, "kinetic_rel_diff": ek, "same_cfl_steps": same["steps"],
                              "same_cfl_front_diff_cells": front_same, "same_cfl_kinetic_rel_diff": ek_same}),
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
