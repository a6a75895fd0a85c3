"""The grid nodes two neighbouring ranks share, and which of them a rank counts in a reduction.

Each rank's grid window covers its own particles' stencils: along the split axis it spans the nodes of
its particles (one below its lowest cell to two above its highest, grid.window_extent), across the other
axes the window of all the run's particles, so that every rank's window has the same cross-section as a
single process's (a periodic axis's ghost nodes and their images are then in every window).

The halo of two neighbours is the overlap of their windows along the split axis.  After P2G each sends
the other its partial sums there (mass, momentum, force) and adds what it receives: both then hold
``own + other`` and ``other + own``, equal to the last bit since addition commutes, and every node of a
window holds the sum over all the run's particles (slabs of at least 4 cells keep any node to two
ranks, parallel/partition.py).  The grid update and the grid stages then run on the halo on both sides
with the same numbers (the update done redundantly, not sent back).

A reduction over nodes (an obstacle's force) must count each node once: in the halo the lower rank counts
the nodes below the cut between the two slabs, the upper rank the rest (``counted``); nodes only one
rank holds are counted by it.

Ghost layers (kernels/shape.py): a particle in cell i writes nodes i .. i + 1 with the linear hat,
i - 1 .. i + 1 or i .. i + 2 with the quadratic B-spline (the lower or upper half of the cell), and
i - 1 .. i + 2 with the cubic B-spline.  A slab of cells [a, b) therefore writes nodes a - 1 .. b + 1
at most: the window keeps one ghost node layer below the slab's lowest cell and two above its highest
(grid.window_extent), the width the widest stencil needs, and the halo two neighbours share is at most
4 node layers thick.
"""

from __future__ import annotations

import numpy as np


def overlap(windows, r: int, s: int):
    """The nodes [a, b) along the split axis that ranks r and s both hold, or None (``windows[r]``:
    (lo, hi) with hi exclusive, or None for a rank without particles)."""
    if not (0 <= r < len(windows) and 0 <= s < len(windows)) or windows[r] is None or windows[s] is None:
        return None
    a, b = max(windows[r][0], windows[s][0]), min(windows[r][1], windows[s][1])
    return (a, b) if a < b else None


def counted(windows, cuts, r: int):
    """The nodes [c_lo, c_hi) along the split axis whose reductions rank r counts (module docstring)."""
    lo, hi = windows[r]
    below, above = overlap(windows, r - 1, r), overlap(windows, r, r + 1)
    c_lo = lo if below is None else int(np.clip(cuts[r], below[0], below[1]))
    c_hi = hi if above is None else int(np.clip(cuts[r + 1], above[0], above[1]))
    return c_lo, c_hi


def node_parts(first, last, axis: int, c_lo: int, c_hi: int):
    """The node box [first, last] (global, inclusive) cut along ``axis`` into the parts below, inside
    and above [c_lo, c_hi): ((first, last, counted), ...), empty parts left out."""
    out = []
    for a, b, is_counted in ((None, c_lo - 1, False), (c_lo, c_hi - 1, True), (c_hi, None, False)):
        f, l = first.copy(), last.copy()
        if a is not None:
            f[axis] = max(f[axis], a)
        if b is not None:
            l[axis] = min(l[axis], b)
        if f[axis] <= l[axis]:
            out.append((f, l, is_counted))
    return out


def slab_of(array: np.ndarray, nloc, axis: int, lo_axis: int, a: int, b: int) -> np.ndarray:
    """The view of a window array (nodes first: (nn,) or (nn, d)) on the global nodes [a, b) along
    ``axis``."""
    shaped = array.reshape(tuple(int(n) for n in nloc) + array.shape[1:])
    index = [slice(None)] * len(nloc)
    index[axis] = slice(a - lo_axis, b - lo_axis)
    return shaped[tuple(index)]
