"""Slabs of cells along one axis, one per rank, balanced by particle count.

Rank r owns the cells ``cuts[r] <= i < cuts[r + 1]`` along the split axis (every cell across the other
axes) and the particles in them; a particle outside the grid on that axis belongs to the first or last
rank.  The cuts put about ``n / size`` particles in each slab: cut r is the cell boundary below which the
number of particles is nearest to ``r n / size``, then moved apart to ``MIN_SLAB_CELLS`` cells.

Why at least 4 cells: a particle in cell i writes nodes i - 1 .. i + 2 (the cubic B-spline's four; the
linear hat and the quadratic B-spline write fewer), so a rank's grid window reaches one node below its slab
and two above, and with slabs of 4 or more cells only neighbours' windows meet.  Every node is then summed
from at most two ranks (parallel/halo.py), and each of the two adds the same two partial sums.

The split axis is, among the axes that are not periodic, the one with the most grid cells (a grid is
drawn long where the flow runs out: a dam break's water, 20 cells wide and 40 high at the start, ends as
a layer 120 cells long and 5 high, and slabs cut across its height would leave one rank most of it), then
the one along which the particles span the most cells at the start (the most slabs of particles, and the
smallest halo across); a case periodic along every axis cannot be split.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from geompm.errors import CaseError

#: the thinnest slab [cells] (module docstring)
MIN_SLAB_CELLS = 4


def split_axis(ncells, periodic_axes=(), spans=None) -> int:
    """The axis the slabs are cut along: of the axes that are not periodic, the one with the most grid
    cells, then the one along which the particles span the most cells (``spans``, (d,)), then the
    lowest; CaseError when every axis is periodic."""
    free = [a for a in range(len(ncells)) if a not in set(periodic_axes)]
    if not free:
        raise CaseError([("boundaries", "the case is periodic along every axis, so it cannot be cut into slabs "
                                        "for several MPI ranks; run it in one process")])
    spans = np.zeros(len(ncells)) if spans is None else spans
    return max(free, key=lambda a: (int(ncells[a]), int(spans[a]), -a))


def check_rank_count(size: int, ncells_axis: int, axis: int) -> None:
    """CaseError when ``size`` slabs of ``MIN_SLAB_CELLS`` cells do not fit along the split axis."""
    if size * MIN_SLAB_CELLS > ncells_axis:
        name = "xyz"[axis]
        raise CaseError([("grid", f"{size} MPI ranks need at least {size * MIN_SLAB_CELLS} cells along the "
                                  f"split axis {name} ({MIN_SLAB_CELLS} per rank, parallel/partition.py), but the "
                                  f"grid has {ncells_axis}: run on at most {ncells_axis // MIN_SLAB_CELLS} ranks "
                                  "or make grid.cell_size smaller")])


def particle_cells(p_x, axis: int, origin: float, h: float, ncells: int) -> np.ndarray:
    """Each particle's cell along the axis, clipped into [0, ncells)."""
    if p_x.shape[0] == 0:
        return np.zeros(0, np.int64)
    return np.clip(np.floor((p_x[:, axis] - origin) / h), 0, ncells - 1).astype(np.int64)


def balanced_cuts(counts: np.ndarray, size: int, min_cells: int = MIN_SLAB_CELLS) -> np.ndarray:
    """Cuts (size + 1,) over cells 0..ncells from the particle count of each cell (module docstring)."""
    counts = np.asarray(counts, np.int64)
    ncells = counts.size
    cum = np.concatenate([[0], np.cumsum(counts)])  # cum[c]: particles below cell boundary c
    total = int(cum[-1])
    cuts = np.zeros(size + 1, np.int64)
    cuts[-1] = ncells
    for r in range(1, size):
        if not total:
            cuts[r] = r * ncells // size
            continue
        target = r * total / size
        c = int(np.searchsorted(cum, target, side="left"))  # the first boundary with at least target below
        cuts[r] = c - 1 if c > 0 and target - cum[c - 1] < cum[c] - target else c  # or the nearer one below
    for r in range(1, size):  # apart by min_cells from below, then leave room above
        cuts[r] = max(cuts[r], cuts[r - 1] + min_cells)
    for r in range(size - 1, 0, -1):
        cuts[r] = min(cuts[r], cuts[r + 1] - min_cells)
    return cuts


def owners(cells: np.ndarray, cuts: np.ndarray) -> np.ndarray:
    """The rank that owns each cell index (int64)."""
    return np.searchsorted(cuts[1:-1], cells, side="right").astype(np.int64)


@njit(cache=True)
def particle_owners(p_x, axis, origin, inv_h, cuts, rank, owner):
    """Each particle's rank into ``owner`` (n,) from its cell along the axis (outside the grid: the first
    or last rank); returns (how many belong to another rank than ``rank``, how many to a rank that is
    not a neighbour).  One pass, no temporaries: the check runs every step."""
    size = cuts.shape[0] - 1
    away = 0
    far = 0
    for p in range(p_x.shape[0]):
        c = math.floor((p_x[p, axis] - origin) * inv_h)
        r = 0
        while r < size - 1 and c >= cuts[r + 1]:
            r += 1
        owner[p] = r
        if r != rank:
            away += 1
            if r < rank - 1 or r > rank + 1:
                far += 1
    return away, far
