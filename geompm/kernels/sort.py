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
from numba import njit, prange


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


@njit(parallel=True, cache=True)
def gather_rows(src, perm, dst):
    """dst[k] = src[perm[k]] for 2D arrays (n, w), in parallel over k."""
    w = src.shape[1]
    for k in prange(perm.shape[0]):
        q = perm[k]
        for j in range(w):
            dst[k, j] = src[q, j]


@njit(parallel=True, cache=True)
def copy_rows(src, dst):
    """dst[:] = src for 2D arrays (n, w), in parallel."""
    w = src.shape[1]
    for k in prange(src.shape[0]):
        for j in range(w):
            dst[k, j] = src[k, j]


#: widest slab of an array permuted at once [8-byte columns]: the work buffer holds n x 3 doubles
SLAB = 3


def permute_in_place(arr: np.ndarray, perm: np.ndarray, work: np.ndarray) -> None:
    """arr <- arr[perm] along the first axis, keeping the array object (views stay attached).

    ``work``: a float64 buffer (>= n, SLAB) kept by the state between sorts.  Arrays wider than
    SLAB columns go through it in slabs of SLAB columns, so the buffer adds 24 bytes per particle
    instead of the widest row's 72.  A fresh buffer per sort would cost more than the sort: its
    first touch (page faults) measured 120 ns per particle at 204k particles."""
    n = arr.shape[0]
    rows = arr.reshape(n, -1)
    per = max(1, SLAB * 8 // arr.itemsize)  # columns of this dtype that fit a work row
    flat = work.reshape(-1)[: n * SLAB].view(np.uint8)
    for j in range(0, rows.shape[1], per):
        cols = rows[:, j:j + per]
        tmp = flat[: n * cols.shape[1] * arr.itemsize].view(arr.dtype).reshape(n, cols.shape[1])
        gather_rows(cols, perm, tmp)
        copy_rows(tmp, cols)
