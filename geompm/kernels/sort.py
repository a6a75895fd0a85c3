"""Spatial order of the particles: a counting sort by grid cell inside each material block.

After a flow has mixed its particles, neighbours in memory are far apart in
space, so the P2G and G2P of consecutive particles touch unrelated grid nodes
and every access misses the cache (measured in docs/performance.md: fluid3d
at 1.6 M particles runs 3.5-4x slower permuted than in seeding order).  The
scheduler therefore re-orders each material block by the linear index of the
cell that holds each particle (x-major, the node order of the grid), every
``solver.sort_interval`` steps.

``cell_order`` returns the permutation (stable: particles of one cell keep
their relative order, so a sorted block sorts to itself).  Counting sort over
the cells of the block's bounding box: O(n + cells), two passes over the
particles, no comparison sort.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def cell_order(p_x, origin, h, start, end):
    """Permutation (absolute indices start..end-1) that orders particles start..end-1 by cell."""
    n = end - start
    d = p_x.shape[1]
    perm = np.empty(n, dtype=np.int64)
    if n == 0:
        return perm
    inv_h = 1.0 / h
    lo = np.empty(d, dtype=np.int64)
    hi = np.empty(d, dtype=np.int64)
    for a in range(d):
        lo[a] = np.iinfo(np.int64).max
        hi[a] = np.iinfo(np.int64).min
    cells = np.empty((n, d), dtype=np.int64)
    for k in range(n):
        for a in range(d):
            c = int(np.floor((p_x[start + k, a] - origin[a]) * inv_h))
            cells[k, a] = c
            lo[a] = min(lo[a], c)
            hi[a] = max(hi[a], c)
    stride = np.empty(d, dtype=np.int64)
    total = 1
    for a in range(d - 1, -1, -1):
        stride[a] = total
        total *= hi[a] - lo[a] + 1
    key = np.empty(n, dtype=np.int64)
    count = np.zeros(total + 1, dtype=np.int64)
    for k in range(n):
        v = 0
        for a in range(d):
            v += (cells[k, a] - lo[a]) * stride[a]
        key[k] = v
        count[v + 1] += 1
    for c in range(total):
        count[c + 1] += count[c]
    for k in range(n):
        v = key[k]
        perm[count[v]] = start + k
        count[v] += 1
    return perm


@njit(cache=True)
def out_of_order(p_x, origin, h, start, end):
    """Fraction of neighbours in memory (p, p+1) in different, non-adjacent cells: 0 right after a
    sort, about 1 for a random order.  A diagnostic (docs/performance.md), not used to decide."""
    n = end - start
    if n < 2:
        return 0.0
    d = p_x.shape[1]
    inv_h = 1.0 / h
    far = 0
    for k in range(start, end - 1):
        for a in range(d):
            ca = np.floor((p_x[k, a] - origin[a]) * inv_h)
            cb = np.floor((p_x[k + 1, a] - origin[a]) * inv_h)
            if abs(ca - cb) > 1.0:
                far += 1
                break
    return far / (n - 1)
