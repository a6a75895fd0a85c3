"""The machine's memory bandwidth, measured the way STREAM does (McCalpin 1995,
"Memory bandwidth and machine balance in current high performance computers",
IEEE TCCA Newsletter): the triad a = b + s c over arrays far larger than the
caches, with numba's threads; 24 bytes move per element (two reads, one write;
write-allocate traffic not counted, as in STREAM).
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit, prange


@njit(parallel=True, cache=True)
def _triad(a, b, c, s):
    for i in prange(a.shape[0]):
        a[i] = b[i] + s * c[i]


def triad_bandwidth(n: int = 20_000_000, repeats: int = 5) -> float:
    """Best-of-``repeats`` triad bandwidth [bytes/s] over three float64 arrays of n elements (480 MB)."""
    a = np.zeros(n)
    b = np.ones(n)
    c = np.full(n, 2.0)
    _triad(a, b, c, 3.0)
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        _triad(a, b, c, 3.0)
        best = min(best, time.perf_counter() - t)
    if not np.all(a[:: max(n // 97, 1)] == 7.0):
        raise RuntimeError("triad check failed")
    return 24.0 * n / best
