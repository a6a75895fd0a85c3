"""Time spent in the stage passes (grid and particle) per step, against the whole step.

    python benchmarks/stage_passes.py benchmarks/fluid3d.json [--steps 20]

Steps the case through the Python API (3 warm-up steps for compilation), wraps the backend's
``grid_stage`` and ``particle_stage`` with timers, and prints the step time and the time of each
kind of pass, in ms per step.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--steps", type=int, default=20)
    a = ap.parse_args()
    sim = Simulation(scene_from_file(a.case, ["outputs=[]"]))
    be = sim.backend
    spent = {"grid": 0.0, "particle": 0.0}

    def timed(kind, inner):
        def run(*args):
            t = time.perf_counter()
            inner(*args)
            spent[kind] += time.perf_counter() - t
        return run
    be.grid_stage = timed("grid", be.grid_stage)
    be.particle_stages = timed("particle", be.particle_stages)  # all of a step's, skipped ones included
    for _ in range(3):
        sim.step(sim.stable_dt())
    spent.update(grid=0.0, particle=0.0)
    t0 = time.perf_counter()
    for _ in range(a.steps):
        sim.step(sim.stable_dt())
    per = 1e3 / a.steps
    print(f"{a.case}: {sim.state.n} particles, {len(sim.grid_stages)} grid and {len(sim.particle_stages)} particle "
          f"stages; step {(time.perf_counter() - t0) * per:.2f} ms, grid passes {spent['grid'] * per:.3f} ms, "
          f"particle passes {spent['particle'] * per:.3f} ms")


if __name__ == "__main__":
    main()
