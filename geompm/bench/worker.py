"""One benchmark measurement, in its own process so that start-up and peak memory are its own.

    python -m geompm.bench.worker CASE --steps N [--set KEY=VALUE ...]

Prints one JSON object.  The process does what ``geompm run`` does per step
(time-step control, the step with the case's stages, health and domain checks;
no output is due in a benchmark case) through ``Runner.advance``:

- start-up: from the parent's spawn time (``GEOMPM_BENCH_SPAWN``, epoch seconds)
  to the end of the first step: interpreter, imports, case loading and
  assembly, numba compilation or cache loading, one step;
- two warm-up steps (the first is the start-up step), not timed;
- ``steps`` timed steps.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time


def _stage_bytes(stages) -> int:
    """Bytes of the numpy arrays the stages hold (obstacle signed-distance lattices, node lists)."""
    import numpy as np

    total = 0
    for stage in stages:
        for value in vars(stage).values():
            if isinstance(value, np.ndarray):
                total += value.nbytes
    return total


def measure(case: str, steps: int, sets: list[str]) -> dict:
    spawn = float(os.environ.get("GEOMPM_BENCH_SPAWN", time.time()))
    import numba
    import numpy as np

    from ..api import scene_from_file
    from ..engine.runner import Runner
    from ..engine.scheduler import Simulation
    from ..resources import peak_rss

    t_load = time.perf_counter()
    scene = scene_from_file(case, sets)
    assemble_s = time.perf_counter() - t_load
    sim = Simulation(scene)
    runner = Runner(sim, None, [], progress=False)
    runner.start()
    runner.advance(math.inf)
    startup_s = time.time() - spawn
    runner.advance(math.inf)
    t0 = time.perf_counter()
    for _ in range(steps):
        runner.advance(math.inf)
    wall = time.perf_counter() - t0
    n = sim.state.n
    view = sim.view
    model_bytes = sim.state.nbytes() + sim.buffers.nbytes() + _stage_bytes(sim.grid_stages + sim.particle_stages)
    return {
        "case": case,
        "sets": sets,
        "dimension": scene.dim,
        "particles": n,
        "grid_cells": int(scene.grid.ncells.prod()),
        "window_nodes": int(np.prod(view.nloc)),
        "active_nodes": int((view.g_mass > 0.0).sum()),
        "steps": steps,
        "sim_time": sim.time,
        "wall_s": wall,
        "particle_steps_per_s": n * steps / wall,
        "ns_per_particle_step": wall / (n * steps) * 1e9,
        "startup_s": startup_s,
        "assemble_s": assemble_s,
        "peak_rss_bytes": peak_rss(),
        "model_bytes": model_bytes,
        "bytes_per_particle": model_bytes / n,
        "threads": numba.get_num_threads(),
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m geompm.bench.worker")
    p.add_argument("case")
    p.add_argument("--steps", type=int, required=True)
    p.add_argument("--set", action="append", default=[])
    args = p.parse_args(argv)
    print(json.dumps(measure(args.case, args.steps, args.set)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
