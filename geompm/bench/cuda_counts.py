"""What one CUDA step asks of the host: kernel launches, copies each way and blocking synchronisations.

``counting()`` wraps, for the duration of a ``with`` block, numba-cuda's kernel launch, its explicit copies
(``cuda.to_device``, a device array's ``copy_to_device`` and ``copy_to_host``) and ``cuda.synchronize``, on a
device or under the simulator (NUMBA_ENABLE_CUDASIM=1), and counts them; a numpy array handed to a kernel is
counted apart (``implicit``: numba copies it to the device and back around the launch, a blocking round trip; the
copy back goes through ``copy_to_host`` and is counted there too). ``blocking`` counts what makes the host wait for
the device to finish the work launched before: a copy to the host, a synchronisation, and a copy from the host's
(pageable) memory to the device, before which the driver synchronises the stream (CUDA Driver API, "API
synchronization behavior", docs.nvidia.com/cuda/cuda-driver-api/api-sync-behavior.html). Device functions called
inside a kernel are not launches (the simulator runs them through the same class; they are told apart by its kernel
context); the time spent inside launches is summed (``launch_seconds``). ``allocs`` counts new device arrays
(``cuda.device_array``, ``cuda.to_device``): each is a cuMemAlloc, and numba-cuda frees them in batches of more
than ``NUMBA_CUDA_MAX_PENDING_DEALLOCS_COUNT`` (10), each cuMemFree of such memory "may perform implicit
synchronization" (CUDA Driver API, cuMemFree), a wait the count of synchronisations does not see; and a CUDA
graph replays the pointers it was captured with, so a step that puts its values in new arrays cannot be replayed
(bench/cuda_replay.py). ``step_counts`` runs a scene's steps under
it: the table of docs/performance.md (benchmarks/device/count_launches.py).
"""

from __future__ import annotations

import contextlib
import time
from collections import Counter

import numpy as np

from geompm.bench.cuda_replay import REPLAY, compare, describe

KINDS = ("launches", "implicit", "h2d", "d2h", "syncs", "blocking", "allocs")
#: seconds spent inside kernel launches (under the simulator: the kernels themselves, run as Python)
INSIDE = "launch_seconds"


def _targets():
    """(launch class and method, device-array class) of the running numba-cuda: its simulator's or the
    driver's."""
    from numba import config

    if config.ENABLE_CUDASIM:
        from numba.cuda.simulator import kernel
        from numba.cuda.simulator.cudadrv.devicearray import FakeCUDAArray

        return kernel.FakeCUDAKernel, FakeCUDAArray, kernel
    from numba.cuda.cudadrv.devicearray import DeviceNDArray
    from numba.cuda.dispatcher import _LaunchConfiguration

    return _LaunchConfiguration, DeviceNDArray, None


def _caller() -> str:
    """'module.py:line' of geompm's frame nearest the wrapped call."""
    import sys

    frame = sys._getframe(2)
    while frame is not None and "/geompm/" not in frame.f_code.co_filename.replace("\\", "/"):
        frame = frame.f_back
    if frame is None:
        return "?"
    return f"{frame.f_code.co_filename.replace(chr(92), '/').split('/geompm/')[-1]}:{frame.f_lineno}"


@contextlib.contextmanager
def counting(sites: Counter | None = None, launches: list | None = None):
    """A Counter of KINDS, filled while the block runs; every wrapped function is restored after it.  With
    ``sites`` each event is also counted there by (kind, geompm's calling line); with ``launches`` each launch is
    appended there as bench/cuda_replay.describe gives it."""
    from numba import cuda

    counts = Counter({k: 0 for k in KINDS})
    counts[INSIDE] = 0.0
    launcher, array, sim = _targets()
    saved = []

    def wrap(owner, name, count):
        original = getattr(owner, name)

        def wrapper(*args, **kwargs):
            counted = count(args)
            if counted and sites is not None:
                sites[(name, _caller())] += 1
            if not (counted and name == "__call__"):
                return original(*args, **kwargs)
            t0 = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                counts[INSIDE] += time.perf_counter() - t0

        saved.append((owner, name, original))
        setattr(owner, name, wrapper)

    def launch(args):
        this = args[0]
        if sim is not None and (this._device or sim._kernel_context):
            return False  # a device function inside a kernel
        counts["launches"] += 1
        if launches is not None:
            launches.append(describe(this, args[1:]))
        counts["implicit"] += sum(isinstance(a, np.ndarray) for a in args[1:])
        return True

    def add(*kinds):
        def count(args):
            for k in kinds:
                counts[k] += 1
            return True
        return count

    wrap(launcher, "__call__", launch)
    wrap(array, "copy_to_host", add("d2h", "blocking"))
    wrap(array, "copy_to_device", add("h2d", "blocking"))
    wrap(cuda, "to_device", add("h2d", "blocking", "allocs"))
    wrap(cuda, "device_array", add("allocs"))
    wrap(cuda, "synchronize", add("syncs", "blocking"))
    try:
        yield counts
    finally:
        for owner, name, original in reversed(saved):
            setattr(owner, name, original)


def step_counts(sim, steps: int, sites: Counter | None = None, reasons: Counter | None = None) -> dict:
    """Per step, over at least ``steps`` steps of ``sim`` (a Simulation on the cuda backend) after one untimed step
    or held batch (two where the scene sorts every step: backend/cuda_scratch.py), the steps taken as `geompm run`
    takes them (engine/runner.Runner.advance: the time step, the step or a held batch of them, the health and domain
    checks): each count of KINDS, the wall time [s] and the host's own time [s], the wall time less the time inside
    kernel launches (under the simulator those run the kernels as Python; on a device a launch is asynchronous and
    the difference is the host's work plus its waits at blocking copies); the steps and held batches counted;
    ``sites`` as in ``counting``; ``replay``: per step (or held batch) after the first counted, REPLAY's counts of
    its launches against the previous one's and against the one before it (``previous``, ``two_back``:
    bench/cuda_replay.compare), the arguments that differ from the previous one's counted in ``reasons``; only with
    ``reasons`` (else None: describing each launch adds to the host's time)."""
    import math

    from geompm.engine.runner import Runner

    runner = Runner(sim, None, [], progress=False)
    runner.start()
    runner.advance(math.inf)  # the first step allocates and uploads
    if sim.scene.sort_interval == 1:  # a scene that sorts every step: its second sort makes the last spares
        runner.advance(math.inf)
    first, batches = sim.step_count, runner.held_batches
    launches: list | None = [] if reasons is not None else None
    bounds = [0]
    with counting(sites, launches) as counts:
        t0 = time.perf_counter()
        while sim.step_count - first < steps:
            runner.advance(math.inf)
            bounds.append(len(launches or ()))
        wall = time.perf_counter() - t0
    taken = sim.step_count - first
    replay = None
    if launches is not None:
        groups = [launches[a:b] for a, b in zip(bounds, bounds[1:])]
        replay = {}
        for lag, key in ((1, "previous"), (2, "two_back")):  # two back: the sort's spares alternate (two graphs)
            pairs = [compare(a, b, reasons if lag == 1 else None) for a, b in zip(groups, groups[lag:])]
            replay[key] = {k: sum(p[k] for p in pairs) / len(pairs) for k in REPLAY} if pairs else None
    return {**{k: counts[k] / taken for k in KINDS}, "wall_per_step": wall / taken,
            "host_per_step": (wall - counts[INSIDE]) / taken, "steps": taken,
            "batches": runner.held_batches - batches, "replay": replay}
