"""The spatial sort on the device: a stable counting sort by grid cell inside each material block.

The same permutation as the CPU's ``kernels/sort.cell_order`` (x-major cell
index over the block's bounding box of cells; particles of one cell keep
their relative order), built without the particle arrays leaving the GPU:

1. ``cell_bounds``: each particle's cell, and the block's lowest and highest
   cell per axis by atomic min/max (a 2 x d row comes to the host to size the
   counts, unless the caller knows them: the CUDA backend's step-end bounds of
   each block, backend/cuda_kernels.step_end, give them without a copy);
2. ``cell_count``: each particle's key (the linear cell index) and an atomic
   histogram ``count[key + 1] += 1``;
3. ``scan``: the inclusive prefix sum of the histogram (a Hillis-Steele scan
   per block of ``SCAN`` entries in shared memory, the blocks' totals scanned
   the same way, recursively, then added back), so that ``count[c]`` is the
   first row of cell c;
4. ``scatter``: each particle takes the next row of its cell by an atomic
   increment (in no particular order within the cell), which leaves
   ``count[c]`` at the end of cell c;
5. ``order_cells``: one thread per cell puts its rows back in the particles'
   original order (an insertion sort of a few entries: a cell holds
   particles_per_cell ** d of them in a dense flow), which makes the sort
   stable and equal to the CPU's, row for row.

``cell_order(p_x, origin, h, blocks)`` returns the device permutation
(absolute indices, block by block); ``gather`` applies it to a device array.
The scan needs O(cells of the bounding box) memory, as the CPU's sort does.
"""

from __future__ import annotations

import math

import numpy as np
from numba import cuda, int64

from geompm.backend.cuda_kernels import THREADS, blocks
from geompm.backend.cuda_loops import simulated

#: entries per block of the prefix sum (one per thread; the simulator runs each thread as a Python thread)
SCAN = 32 if simulated() else 512
_BIG = np.iinfo(np.int64).max


@cuda.jit
def cell_bounds(p_x, origin, inv_h, start, end, cells, lohi):
    """cells[q] = floor((x - origin) / h) for particle start + q; lohi[0] = min, lohi[1] = max cell per axis."""
    q = cuda.grid(1)
    p = start + q
    if p >= end:
        return
    for a in range(p_x.shape[1]):
        c = int64(math.floor((p_x[p, a] - origin[a]) * inv_h))
        cells[q, a] = c
        cuda.atomic.min(lohi, (0, a), c)
        cuda.atomic.max(lohi, (1, a), c)


@cuda.jit
def cell_count(cells, lo, stride, key, count):
    q = cuda.grid(1)
    if q >= key.shape[0]:
        return
    v = 0
    for a in range(cells.shape[1]):
        v += (cells[q, a] - lo[a]) * stride[a]
    key[q] = v
    cuda.atomic.add(count, v + 1, 1)


@cuda.jit
def scan_block(a, sums):
    """Inclusive prefix sum of each block of SCAN entries of a, in place; the block's total in sums."""
    tmp = cuda.shared.array(SCAN, int64)
    t = cuda.threadIdx.x
    i = cuda.blockIdx.x * SCAN + t
    tmp[t] = a[i] if i < a.shape[0] else 0
    cuda.syncthreads()
    off = 1
    while off < SCAN:
        v = tmp[t - off] if t >= off else 0
        cuda.syncthreads()
        tmp[t] += v
        cuda.syncthreads()
        off *= 2
    if i < a.shape[0]:
        a[i] = tmp[t]
    if t == SCAN - 1:
        sums[cuda.blockIdx.x] = tmp[t]


@cuda.jit
def add_block_offsets(a, sums):
    b = cuda.blockIdx.x
    i = b * SCAN + cuda.threadIdx.x
    if b > 0 and i < a.shape[0]:
        a[i] += sums[b - 1]


def _fresh(key, shape, dtype):
    return cuda.device_array(shape, dtype=dtype)


def scan(a, space=_fresh, level: int = 0) -> None:
    """Inclusive prefix sum of the int64 device array a, in place (``space``: cell_order's)."""
    nb = (a.shape[0] + SCAN - 1) // SCAN
    sums = space(("scan", level), nb, np.int64)
    scan_block[nb, SCAN](a, sums)
    if nb > 1:
        scan(sums, space, level + 1)
        add_block_offsets[nb, SCAN](a, sums)


@cuda.jit
def scatter(key, count, start, perm):
    q = cuda.grid(1)
    if q >= key.shape[0]:
        return
    row = cuda.atomic.add(count, key[q], 1)
    perm[start + row] = start + q


@cuda.jit
def order_cells(count, start, perm):
    """Cell c holds rows start + [count[c-1], count[c]) after the scatter: sort them by particle index."""
    c = cuda.grid(1)
    if c >= count.shape[0] - 1:
        return
    s = start + (count[c - 1] if c > 0 else 0)
    e = start + count[c]
    for i in range(s + 1, e):
        v = perm[i]
        j = i - 1
        while j >= s and perm[j] > v:
            perm[j + 1] = perm[j]
            j -= 1
        perm[j + 1] = v


@cuda.jit
def zero_counts(count):
    i = cuda.grid(1)
    if i < count.shape[0]:
        count[i] = 0


def _sent(key, values):
    return cuda.to_device(values)


def cell_order(p_x, origin, h: float, block_list, extents=None, send=_sent, space=_fresh, perm=None):
    """Device int64 permutation of all n particles: perm[k] is the particle that goes to row k
    (kernels/sort.cell_order on each block of ``block_list``, equal to it row for row), written into ``perm``
    where given.  ``extents``: per block its (lowest, highest) cell per axis ((d,) int64 each) where the caller
    knows them, else None (found here, one copy to the host per block); ``send(key, array)``: a small array on
    the device (the CUDA backend's copy, sent again only when its values change); ``space(key, shape, dtype)``:
    a work array (the CUDA backend's are kept from sort to sort: backend/cuda_scratch.py; by default new)."""
    n, d = p_x.shape
    perm = space("perm", n, np.int64) if perm is None else perm
    inv_h = 1.0 / h
    for k, (start, end) in enumerate(block_list):
        m = end - start
        if m == 0:
            continue
        cells = space("cells", (m, d), np.int64)  # one block after the other: the stream orders their uses
        known = extents[k] if extents is not None else None
        if known is None:
            lohi = cuda.to_device(np.array([[_BIG] * d, [-_BIG - 1] * d], dtype=np.int64))
            cell_bounds[blocks(m), THREADS](p_x, origin, inv_h, start, end, cells, lohi)
            lo, hi = lohi.copy_to_host()
        else:  # the cells only: the bounds' atomics go to scratch that nothing reads
            lo, hi = known
            cell_bounds[blocks(m), THREADS](p_x, origin, inv_h, start, end, cells, space("lohi", (2, d), np.int64))
        stride = np.empty(d, dtype=np.int64)
        total = 1
        for a in range(d - 1, -1, -1):
            stride[a] = total
            total *= int(hi[a] - lo[a] + 1)
        key = space("key", m, np.int64)
        count = space("count", total + 1, np.int64)
        zero_counts[blocks(total + 1), THREADS](count)
        cell_count[blocks(m), THREADS](cells, send(("sort_lo", k), np.asarray(lo, np.int64)),
                                       send(("sort_stride", k), stride), key, count)
        scan(count, space)
        scatter[blocks(m), THREADS](key, count, start, perm)
        order_cells[blocks(total), THREADS](count, start, perm)
    return perm


@cuda.jit
def gather_rows(src, perm, offset, dst):
    """dst[k] = src[perm[k] - offset], row by row (arrays viewed as (rows, columns))."""
    k = cuda.grid(1)
    if k >= dst.shape[0]:
        return
    q = perm[k] - offset
    for c in range(src.shape[1]):
        dst[k, c] = src[q, c]


def gather(src, perm, offset: int = 0, dst=None):
    """src's rows in the order perm (less offset), any shape with rows first, into ``dst`` (src's shape and type,
    another array) or a new device array."""
    rows = src.shape[0]
    dst = cuda.device_array(src.shape, dtype=src.dtype) if dst is None else dst
    cols = int(np.prod(src.shape[1:], dtype=np.int64)) if src.ndim > 1 else 1
    if rows and cols:
        gather_rows[blocks(rows), THREADS](src.reshape(rows, cols), perm, offset, dst.reshape(rows, cols))
    return dst
