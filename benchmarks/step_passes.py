"""The step's time pass by pass, in ns per particle-step: the per-pass table of issue 38 (docs/performance.md).

    python benchmarks/step_passes.py benchmarks/fluid3d.json [--set solver.transfer=mls] [--steps 20] [--rounds 5]

Steps the case through the Python API (3 warm-up steps compile everything), wraps each of the backend's passes
(window, p2g, grid_update, grid_stage, g2p, particle_stages, update_stress, sort_particles and, for MUSL,
remap_velocity) with a timer, and runs ``--rounds`` rounds of ``--steps`` steps.  Prints one JSON object: the
particles, threads, each pass's median over the rounds and the whole step's (Simulation.step, so without the
runner's health checks and outputs), all in ns per particle-step, and the median's spread (largest / smallest
round) so a noisy machine shows itself.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402

PASSES = ("window", "p2g", "grid_update", "grid_stage", "remap_velocity", "g2p", "particle_stages",
          "update_stress", "sort_particles")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    sim = Simulation(scene_from_file(a.case, ["outputs=[]", *a.set]))
    be = sim.backend
    spent = dict.fromkeys(PASSES, 0.0)

    def timed(name, inner):
        def run(*args, **kw):
            t = time.perf_counter()
            out = inner(*args, **kw)
            spent[name] += time.perf_counter() - t
            return out
        return run

    for name in PASSES:
        setattr(be, name, timed(name, getattr(be, name)))
    for _ in range(3):
        sim.step(sim.stable_dt())
    rounds = []
    for _ in range(a.rounds):
        for k in spent:
            spent[k] = 0.0
        t0 = time.perf_counter()
        for _ in range(a.steps):
            sim.step(sim.stable_dt())
        rounds.append({"step": time.perf_counter() - t0, **spent})
    scale = 1e9 / (sim.state.n * a.steps)
    out = {"case": a.case, "sets": a.set, "particles": int(sim.state.n), "threads": _threads(), "steps": a.steps,
           "rounds": a.rounds}
    for k in ("step", *PASSES):
        vals = np.array([r[k] for r in rounds]) * scale
        if vals.max() > 0.0:
            out[f"{k}_ns"] = round(float(np.median(vals)), 2)
    steps = np.array([r["step"] for r in rounds])
    out["step_spread"] = round(float(steps.max() / steps.min()), 3)
    print(json.dumps(out))
    return 0


def _threads() -> int:
    import numba

    return numba.get_num_threads()


if __name__ == "__main__":
    sys.exit(main())
