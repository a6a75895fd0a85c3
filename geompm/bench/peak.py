"""The machine's floating-point rate as numba code reaches it: a multiply-add micro-benchmark for the roofline
of `geompm bench` (docs/performance.md, "How far from the machine's limit").

Two rates, each over numba's threads, 2 flops per multiply-add:

- scalar: per thread 12 independent chains x = x a + b in registers, as many as hide the multiply-add's
  latency on current x86 cores (4 cycles, 2 units per core), so the rate is the scalar issue limit.  geompm's
  transfers compile to scalar multiply-adds (numba leaves LLVM's SLP vectoriser off), so this is their
  ceiling;
- vector: the same recurrence over a 64-element array that LLVM's loop vectoriser packs into SIMD lanes
  (4 doubles on AVX2); the ceiling of code that vectorises.

Both chains keep their values bounded (a = 0.5, b = 1: x tends to 2), and the result is checked.  The only
fast-math flag is "contract" (a x + b becomes one multiply-add, as in geompm's kernels, whose fastmath
allows it): with reassociation LLVM folds two steps into one, x 0.25 + 1.5, and the rate it reports
doubles (measured: 170 GFLOP/s on one AVX-512 core at 2.3 GHz, above its 32 flops a cycle).
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit, prange

CHAINS = 12
LANES = 64


@njit(parallel=True, fastmath={"contract"}, cache=True)
def _scalar(nthreads, iters, out):
    for t in prange(nthreads):
        x0 = x1 = x2 = x3 = x4 = x5 = x6 = x7 = x8 = x9 = x10 = x11 = 1.0 + t
        a, b = 0.5, 1.0
        for _ in range(iters):
            x0 = x0 * a + b
            x1 = x1 * a + b
            x2 = x2 * a + b
            x3 = x3 * a + b
            x4 = x4 * a + b
            x5 = x5 * a + b
            x6 = x6 * a + b
            x7 = x7 * a + b
            x8 = x8 * a + b
            x9 = x9 * a + b
            x10 = x10 * a + b
            x11 = x11 * a + b
        out[t] = x0 + x1 + x2 + x3 + x4 + x5 + x6 + x7 + x8 + x9 + x10 + x11


@njit(parallel=True, fastmath={"contract"}, cache=True)
def _vector(nthreads, iters, out):
    for t in prange(nthreads):
        x = np.full(LANES, 1.0 + t)
        for _ in range(iters):
            for i in range(LANES):
                x[i] = x[i] * 0.5 + 1.0
        out[t] = x.sum()


def _rate(kernel, per_iter: int, iters: int, repeats: int) -> float:
    import numba

    nthreads = numba.get_num_threads()
    out = np.zeros(nthreads)
    kernel(nthreads, 10, out)
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        kernel(nthreads, iters, out)
        best = min(best, time.perf_counter() - t)
    if not np.allclose(out, 2.0 * per_iter, rtol=1e-9):
        raise RuntimeError("multiply-add check failed")
    return 2.0 * per_iter * iters * nthreads / best


def fma_rates(iters: int = 20_000_000, repeats: int = 5) -> dict:
    """{"scalar_flops_per_s", "vector_flops_per_s"}: best of ``repeats`` over numba's threads."""
    return {"scalar_flops_per_s": _rate(_scalar, CHAINS, iters, repeats),
            "vector_flops_per_s": _rate(_vector, LANES, iters // 4, repeats)}
