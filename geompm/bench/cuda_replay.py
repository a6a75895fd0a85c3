"""Could a CUDA step be replayed as a captured graph?  What each launch of a step takes, against the step before.

A CUDA graph (captured with cuda.core's ``GraphBuilder``, which numba-cuda 0.30 accepts in place of a stream:
``kernel[blocks, threads, builder](...)``) fixes every launch's kernel, grid, block and arguments: device
pointers and scalar values.  Replaying it for the next step is right only where that step launches the same
kernels on the same grids with the same arguments; where only values differ a captured graph's kernel nodes can be
given new parameters (``cuGraphExecKernelNodeSetParams``, CUDA Driver API "Graph Management"), where the kernels
or grids differ it must be captured again.

``describe(launcher, args)`` turns one launch (on a device or under the simulator) into (kernel name, grid and
block, each argument's description: a device array by its pointer, shape and strides, a host array as such, a
scalar by its value); ``compare(before, after)`` counts, launch by launch, how a step's launches differ from the
previous step's, and names each differing argument by the kernel's parameter name: the numbers that say what a
graph of the step would have to update (geompm/bench/cuda_counts.step_counts, benchmarks/device/count_launches.py
``--replay``).
"""

from __future__ import annotations

import inspect
from collections import Counter

import numpy as np

#: per step: launches identical to the previous step's, differing in scalar values only, in a device array
#: (another pointer or shape), or handing a host array (never capturable); and whether the step's kernels and
#: grids are the previous step's (one graph topology)
REPLAY = ("identical", "scalars", "arrays", "host", "same_topology")


def _array(arg):
    """(pointer, shape, strides) of a device array, on a device or under the simulator; None for anything else."""
    ary = getattr(arg, "_ary", None)  # the simulator's FakeCUDAArray
    if isinstance(ary, np.ndarray):
        return ary.__array_interface__["data"][0], ary.shape, ary.strides
    pointer = getattr(arg, "device_ctypes_pointer", None)
    if pointer is not None and hasattr(arg, "shape"):
        return pointer.value or 0, tuple(arg.shape), tuple(arg.strides)
    return None


def _describe_arg(arg):
    if isinstance(arg, np.ndarray):
        return ("host",)
    if isinstance(arg, tuple):
        return ("tuple",) + tuple(_describe_arg(a) for a in arg)
    dev = _array(arg)
    if dev is not None:
        return ("array",) + dev
    if isinstance(arg, (bool, int, float, np.number, np.bool_)):
        return ("scalar", type(arg).__name__, float(arg))
    return ("other", repr(arg))


def _kernel(launcher):
    """(the kernel's Python function, its grid and block) of a launch: the simulator's configured kernel or the
    driver's launch configuration."""
    if hasattr(launcher, "dispatcher"):
        return launcher.dispatcher.py_func, (tuple(launcher.griddim), tuple(launcher.blockdim))
    return launcher.fn, (tuple(launcher.grid_dim), tuple(launcher.block_dim))


def describe(launcher, args) -> tuple:
    """(kernel name, parameter names, grid and block, argument descriptions) of one launch."""
    fn, config = _kernel(launcher)
    try:
        names = tuple(inspect.signature(fn).parameters)
    except (TypeError, ValueError):
        names = ()
    return fn.__name__, names, config, tuple(_describe_arg(a) for a in args)


def _kind(a, b) -> str:
    """How one argument's descriptions differ: 'host' (a host array either time), 'arrays' or 'scalars'."""
    if a[0] == "host" or b[0] == "host":
        return "host"
    if a[0] == "tuple" and b[0] == "tuple" and len(a) == len(b):
        kinds = {_kind(x, y) for x, y in zip(a[1:], b[1:]) if x != y}
        return "host" if "host" in kinds else "arrays" if "arrays" in kinds else "scalars"
    return "scalars" if a[0] == b[0] == "scalar" else "arrays"


def compare(before: list, after: list, reasons: Counter | None = None) -> dict:
    """How the launches of one step (``after``, each ``describe``'s tuple) differ from the previous step's
    (``before``), position by position: counts of REPLAY (same_topology 1 or 0); with ``reasons`` each differing
    argument counted there by (kernel, parameter name, kind)."""
    out = dict.fromkeys(REPLAY, 0)
    out["same_topology"] = int(len(before) == len(after) and
                               all(a[0] == b[0] and a[2] == b[2] for a, b in zip(before, after)))
    for k, launch in enumerate(after):
        old = before[k] if k < len(before) else None
        if any(arg[0] == "host" for arg in launch[3]):
            out["host"] += 1
            continue
        if old is None or old[0] != launch[0] or len(old[3]) != len(launch[3]):
            out["arrays"] += 1
            if reasons is not None:
                reasons[(launch[0], "(another kernel)", "arrays")] += 1
            continue
        kinds = []
        for i, (a, b) in enumerate(zip(old[3], launch[3])):
            if a != b:
                kind = _kind(a, b)
                kinds.append(kind)
                if reasons is not None:
                    name = launch[1][i] if i < len(launch[1]) else f"argument {i}"
                    reasons[(launch[0], name, kind)] += 1
        if old[2] != launch[2]:
            kinds.append("arrays")
            if reasons is not None:
                reasons[(launch[0], "(grid)", "arrays")] += 1
        out[next((k for k in ("host", "arrays", "scalars") if k in kinds), "identical")] += 1
    return out
