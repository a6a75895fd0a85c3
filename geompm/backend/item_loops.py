"""The CPU backend's loop around a per-item function of a scheme's pass: ``fn(i, *args)`` for every item.

A scheme's passes beyond the core's kernels (the saturated scheme's: schemes/saturated/kernels.py) are
``@njit`` functions of one particle or one node whose first argument is the item's index.  The backend owns
the loop that runs one over ``n`` items (``Backend.each``):

    each(n, a1, a2, ...)    for i in prange(n): item(i, a1, a2, ...)

The loop's parameters are the function's own names after the index, written into the loop's source, so
numba compiles one loop per function with the function inlined (``inline="always"``, as a law's stress in
cpu_loops.py), and caches it on disk (backend/codegen.py).  The CUDA backend's twin is
cuda_loops.each_kernel: one thread per item around the same function.
"""

from __future__ import annotations

import functools
import inspect

from geompm.backend.codegen import loops

EACH = '''
@njit(parallel=True, cache=True)
def each(n, {args}):
    for i in prange(n):
        item(i, {args})
'''


def item_arguments(fn) -> str:
    """The names of ``fn``'s parameters after the item's index, as source text ("a, b, c")."""
    names = list(inspect.signature(getattr(fn, "py_func", fn)).parameters)[1:]
    return ", ".join(names)


@functools.cache
def each_loop(fn):
    """The parallel loop ``each(n, *args)`` around the per-item function ``fn(i, *args)`` (kept per function:
    a step asks for it at every pass)."""
    return loops("each", {"item": fn}, EACH.format(args=item_arguments(fn)), ("each",))[0]
