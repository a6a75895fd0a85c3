"""The CPU backend's loop around a per-item function of a scheme's pass: ``fn(i, *args)`` for every item.

A scheme's passes beyond the core's kernels (the saturated scheme's: schemes/saturated/kernels.py) are
``@njit`` functions of one particle or one node whose first argument is the item's index.  The backend owns
the loop that runs one over ``n`` items (``Backend.each``):

    each(n, a1, a2, ...)    for i in prange(n): item(i, a1, a2, ...)

A run of such functions that the scheme declares pointwise (``Backend.each_in_turn``: of what one function
writes, a later one reads only its own item's entries) is one loop, the functions called in turn on each item:

    each(n, a0_x, ..., a1_y, ...)    for i in prange(n): item0(i, a0_x, ...); item1(i, a1_y, ...)

The loop's parameters are the functions' own names after the index (prefixed by the function's place in the
run), written into the loop's source, so numba compiles one loop per run of functions with them inlined
(``inline="always"``, as a law's stress in cpu_loops.py), and caches it on disk (backend/codegen.py).  The
CUDA backend's twin is cuda_loops.each_kernel: one thread per item around the same calls.
"""

from __future__ import annotations

import functools
import inspect

from geompm.backend.codegen import loops

EACH = '''
@njit(parallel=True, cache=True)
def each(n, {args}):
    for i in prange(n):
{calls}'''


def item_calls(fns: tuple, indent: str) -> tuple[str, str, dict]:
    """For the per-item functions ``fns`` called in turn on item ``i``: the loop's parameters after the count
    ("a0_p_x, a0_h, a1_p_x"), the calls, one per line at ``indent`` ("item0(i, a0_p_x, a0_h)"), and the
    functions by the aliases the calls use."""
    params, calls = [], []
    for k, fn in enumerate(fns):
        names = [f"a{k}_{name}" for name in list(inspect.signature(getattr(fn, "py_func", fn)).parameters)[1:]]
        params += names
        calls.append(f"{indent}item{k}(i, {', '.join(names)})\n")
    return ", ".join(params), "".join(calls), {f"item{k}": fn for k, fn in enumerate(fns)}


@functools.cache
def each_loop(fns: tuple):
    """The parallel loop ``each(n, *args)`` calling the per-item functions ``fns`` in turn on each item, the
    arguments of each in order (kept per run of functions: a step asks for it at every pass)."""
    args, calls, functions = item_calls(fns, "        ")
    return loops("each", functions, EACH.format(args=args, calls=calls), ("each",))[0]
