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


@njit(parallel=True, cache=True)
def gather_slab(src, width, j0, ncols, perm, dst):
    """dst[k, c] = src[perm[k], j0 + c] for c < ncols, on flat float64 views (src rows of ``width``,
    dst rows of ``ncols``): one compiled kernel for every array and slab."""
    for k in prange(perm.shape[0]):
        q = perm[k] * width + j0
        for c in range(ncols):
            dst[k * ncols + c] = src[q + c]


@njit(parallel=True, cache=True)
def scatter_slab(src, ncols, width, j0, dst):
    """dst[k, j0 + c] = src[k, c]: the slab back into its rows (flat views as in gather_slab)."""
    n = src.shape[0] // ncols
    for k in prange(n):
        for c in range(ncols):
            dst[k * width + j0 + c] = src[k * ncols + c]


#: widest slab of an array permuted at once [8-byte columns]: the work buffer holds n x 3 doubles
SLAB = 3


def permute_in_place(arr: np.ndarray, perm: np.ndarray, work: np.ndarray) -> None:
    """arr <- arr[perm] along the first axis, keeping the array object (views stay attached).

    ``work``: a float64 buffer (>= n, SLAB) kept by the state between sorts.  8-byte arrays go through
    it in slabs of SLAB columns as flat float64 views (one compiled kernel for all of them), so the
    buffer adds 24 bytes per particle instead of the widest row's 72; a fresh buffer per sort would
    cost more than the sort (its first touch measured 120 ns per particle at 204k particles).  Other
    item sizes (the int32 material and body ids) take numpy's gather."""
    n = arr.shape[0]
    if arr.itemsize != 8:
        arr[...] = arr[perm]
        return
    flat = arr.reshape(-1).view(np.float64)
    width = flat.shape[0] // n if n else 0
    tmp = work.reshape(-1)
    for j in range(0, width, SLAB):
        cols = min(SLAB, width - j)
        gather_slab(flat, width, j, cols, perm, tmp)
        scatter_slab(tmp[: n * cols], cols, width, j, flat)
