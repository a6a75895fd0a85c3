"""One benchmark measurement, in its own process so that start-up and peak memory are its own.

    python -m geompm.bench.worker CASE --steps N [--set KEY=VALUE ...] [--permute]

Prints one JSON object.  The process does what ``geompm run`` does per step
(time-step control, the step with the case's stages, health and domain checks;
no output is due in a benchmark case) through ``Runner.advance``:

- start-up: from the parent's spawn time (``GEOMPM_BENCH_SPAWN``, epoch seconds)
  to the end of the first step: interpreter, imports, case loading and
  assembly, numba compilation or cache loading, one step;
- two warm-up steps (the first is the start-up step), not timed;
- ``steps`` timed steps (or the first held batches that take at least as many: solver.held_step).

``--permute`` shuffles the particles of every material block (seed 0) before
the first step, as a long flow mixes them (the ``mixed`` scene).  The time
spent in the spatial sort (kernels/sort.py) is reported on its own:
``first_sort_ns_per_particle`` for the sort before the first step (of the
seeding or the shuffled order), ``sort_s`` and ``sort_ns_per_particle`` per
call for the sorts inside the timed steps (``sorts`` of them).
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


def permute_blocks(state, seed: int = 0) -> None:
    """Shuffle the particles inside each material block (all per-particle arrays and the state variables)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    if state.n:
        state.reorder(np.concatenate([a + rng.permutation(b - a) for a, b in state.blocks]))


def measure(case: str, steps: int, sets: list[str], permute: bool = False) -> dict:
    spawn = float(os.environ.get("GEOMPM_BENCH_SPAWN", time.time()))
    import numba
    import numpy as np

    from geompm.api import scene_from_file
    from geompm.engine.runner import Runner
    from geompm.engine.scheduler import Simulation
    from geompm.mpm.memory import peak_rss

    t_load = time.perf_counter()
    scene = scene_from_file(case, sets)
    assemble_s = time.perf_counter() - t_load
    if permute:
        permute_blocks(scene.state)
    sim = Simulation(scene)
    sort_clock = [0.0, 0]
    sort = sim.backend.sort_particles

    def timed_sort():
        t = time.perf_counter()
        sort()
        sort_clock[0] += time.perf_counter() - t
        sort_clock[1] += 1

    sim.backend.sort_particles = timed_sort
    runner = Runner(sim, None, [], progress=False)
    runner.start()
    runner.advance(math.inf)
    startup_s = time.time() - spawn
    first_sort_s = sort_clock[0]  # the sort before step 0: of the seeding (or permuted) order
    runner.advance(math.inf)
    sort_clock[:] = [0.0, 0]
    before = scene.scheme.timings(sim)
    first, batches = sim.step_count, runner.held_batches
    t0 = time.perf_counter()
    while sim.step_count - first < steps:  # a held batch (solver.held_step) takes several steps at once
        runner.advance(math.inf)
    wall = time.perf_counter() - t0
    steps = sim.step_count - first
    after = scene.scheme.timings(sim)
    n = sim.state.n
    view = sim.view
    model_bytes = sim.state.nbytes() + sim.buffers.nbytes() + _stage_bytes(sim.scene.stages)
    return {
        "case": case,
        "sets": sets,
        "dimension": scene.dim,
        "particles": n,
        "grid_cells": int(scene.grid.ncells.prod()),
        "window_nodes": int(np.prod(view.nloc)),
        "active_nodes": int((view.g_mass > 0.0).sum()),
        "steps": steps,
        "held_batches": runner.held_batches - batches,
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
        "permuted": permute,
        "sort_interval": scene.sort_interval,
        "sorts": sort_clock[1],
        "sort_s": sort_clock[0],
        "sort_ns_per_particle": sort_clock[0] / max(sort_clock[1], 1) / n * 1e9,
        "first_sort_ns_per_particle": first_sort_s / n * 1e9,
        "scheme_timings": {k: after[k] - before.get(k, 0.0) for k in after},
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m geompm.bench.worker")
    p.add_argument("case")
    p.add_argument("--steps", type=int, required=True)
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--permute", action="store_true", help="shuffle each material block before the first step")
    args = p.parse_args(argv)
    print(json.dumps(measure(args.case, args.steps, args.set, args.permute)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
