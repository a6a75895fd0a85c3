"""The host's own time a CUDA step takes, measured under numba-cuda's simulator without the simulator's work.

Under the simulator a kernel runs as Python inside its launch, and the wall time less the time inside launches
(cuda_counts.step_counts' ``host_per_step``) still carries the simulator's costs outside them: the objects its
threads and arrays leave are collected by Python's garbage collector wherever a collection falls, mostly in the
host's code.  ``host_only`` takes the host's part alone: after one real step (or held batch), every kernel launch
returns at once and the tally's read (still made: that copy is the host's) hands back the real step's values, so
each later step takes an ordinary step's path on the host (the same time step, window, stage arguments, launches
configured and argued, checks) with nothing computed.  On a device the wall time per step is the measure itself
(a launch returns at once there), and this returns None.
"""

from __future__ import annotations

import math
import time

import numpy as np


def host_only(sim, steps: int, repeats: int = 3) -> float | None:
    """The median over ``repeats`` runs of at least ``steps`` steps each (after ``steps`` untimed) of the host's
    time a step [s] of ``sim`` (a Simulation on the cuda backend, under the simulator), the steps taken as
    `geompm run` takes them (engine/runner.Runner.advance); the simulation's particles no longer advance."""
    from numba import config

    if not config.ENABLE_CUDASIM:
        return None
    from numba.cuda.simulator.kernel import FakeCUDAKernel

    from geompm.backend.cuda_tally import DeviceTally
    from geompm.engine.runner import Runner

    runner = Runner(sim, None, [], progress=False)
    runner.start()
    kept: list = []
    read, launch = DeviceTally.read, FakeCUDAKernel.__call__

    def keep(tally):
        kept[:] = [read(tally).copy()]
        return kept[0].copy()

    def replay(tally):
        read(tally)
        return kept[0].copy()

    def skip(kernel, *args):
        return launch(kernel, *args) if kernel._device else None

    DeviceTally.read = keep
    try:
        runner.advance(math.inf)
        DeviceTally.read, FakeCUDAKernel.__call__ = replay, skip
        for _ in range(steps):
            runner.advance(math.inf)
        times = []
        for _ in range(repeats):
            first, t0 = sim.step_count, time.perf_counter()
            while sim.step_count - first < steps:
                runner.advance(math.inf)
            times.append((time.perf_counter() - t0) / (sim.step_count - first))
    finally:
        DeviceTally.read, FakeCUDAKernel.__call__ = read, launch
    return float(np.median(times))
