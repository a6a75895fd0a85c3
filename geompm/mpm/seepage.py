"""A steady seepage state solved once on the grid: the hydraulic head H of the soil's water and its pore
pressure p = rho_w |g| max(H - z, 0) (schema: triggers.water_table.seepage; docs/slope-stability.md).

Darcy's law and continuity in a homogeneous, isotropic soil give Laplace's equation for the head,

    div (k grad H) = 0          in the soil,

solved with bilinear (2D) or trilinear (3D) finite elements on the grid's own cells: every cell that holds a
particle of the soils the table acts on, its nodes the unknowns (element matrices by 2-point Gauss quadrature,
assembled with scipy.sparse, solved by scipy's sparse LU or pyamg's smoothed aggregation beyond
``DIRECT_LIMIT`` unknowns).  The boundaries:

- a ``head`` on a grid side (a reservoir or a river against it): H = head at that side's soil nodes at or
  below the head's level;
- a pond (``pond``, its level at t = 0): H = z_p at the free-face nodes at or below it (a free face: a soil node
  of a cell next to an empty cell inside the grid);
- every other boundary is impermeable (no flux: the natural condition), except
- seepage faces: free-face nodes above the pond and head-side nodes above their head, where the water may
  leave, H <= z (p <= 0): a node whose head comes out above its elevation is fixed at H = z and the solve is
  repeated (Bathe & Khoshgoftaar 1979, Int. J. Numer. Anal. Meth. Geomech. 3:13);
- the phreatic surface (unconfined flow): a cell whose head lies below its centre is unsaturated and
  conducts k_r k, k_r falling linearly from 1 where the cell's pressure head is 0 to ``unsaturated``
  (default 1e-3) one cell below: the free surface is where p = 0, found by iterating the conductivities (each
  iteration a quarter of the way to the new ones) with the seepage faces (the non-linear permeability of
  Bathe & Khoshgoftaar 1979, which needs no mesh iteration) until the seepage faces stay and the head changes
  by less than 1e-4 cell (the report says whether it did: `settled`).

Heads that rise or fall in time (a reservoir filling) solve the state again whenever one has moved by a tenth
of a cell (SeepageSurface): a sequence of steady states, the drained soil's pore pressure following at once.
The head is kept on the grid's nodes (outside the soil a node's own elevation, p = 0 there) and interpolated
multilinearly at each particle as it moves (kernels/lattice.py); beyond the grid the edge values hold.
Verified against the Dupuit discharge of a rectangular dam, q = k (h1^2 - h2^2) / (2 L), which holds exactly for the discharge (Charny 1951;
see Bear 1972, Dynamics of Fluids in Porous Media): tests/unit/test_seepage.py.
"""

from __future__ import annotations

import itertools

import numpy as np

from geompm.kernels.phreatic import head_pressure_2d, head_pressure_3d

#: a moving head's change [cells] after which the state is solved again
RESOLVE = 0.1
#: unknowns up to which the sparse direct solver is used; pyamg's smoothed aggregation above
DIRECT_LIMIT = 200_000
#: the most iterations of the seepage faces and the unsaturated zone, and the change of the head [cells]
#: below which they have settled
MAX_ITERATIONS = 400
TOLERANCE = 1e-4
#: the share of the way to the new conductivities each iteration takes
RELAX = 0.25


def _element_matrix(d: int) -> np.ndarray:
    """The (2^d, 2^d) conductivity matrix of a unit-conductivity cell of side h, without the factor h^(d-2):
    int grad N_a . grad N_b over the cell by 2-point Gauss quadrature, corners in itertools.product order."""
    corners = np.array(list(itertools.product((0, 1), repeat=d)), float)
    g = 0.5 + 0.5 * np.array([-1.0, 1.0]) / np.sqrt(3.0)
    K = np.zeros((2 ** d, 2 ** d))
    for point in itertools.product(g, repeat=d):
        xi = np.array(point)
        grads = np.empty((2 ** d, d))
        for a, c in enumerate(corners):
            f = np.where(c > 0, xi, 1.0 - xi)
            s = np.where(c > 0, 1.0, -1.0)
            for k in range(d):
                grads[a, k] = s[k] * np.prod(np.delete(f, k))
        K += grads @ grads.T / 2 ** d
    return K


def solve_seepage(p_x, origin, h, ncells, heads, pond, unsaturated=1e-3):
    """The nodal head (ncells + 1 nodes per axis) of the steady seepage through the cells
    that hold the points ``p_x`` (module docstring), and a report: iterations, the seepage-face nodes, the
    saturated cells.  ``heads``: (axis, high side?, head [m]) per grid side with a head; ``pond``: its level
    [m] or None; the vertical is the last axis."""
    p_x = np.asarray(p_x, float)
    d = p_x.shape[1]
    ncells = np.asarray(ncells, np.int64)
    nn = ncells + 1
    cells = np.clip(np.floor((p_x - origin) / h).astype(np.int64), 0, ncells - 1)
    cell_id = np.unique(np.ravel_multi_index(cells.T, ncells))
    cell_idx = np.array(np.unravel_index(cell_id, ncells)).T  # (nc, d)
    occupied = np.zeros(ncells, bool)
    occupied[tuple(cell_idx.T)] = True
    offsets = np.array(list(itertools.product((0, 1), repeat=d)), np.int64)
    corner = cell_idx[:, None, :] + offsets[None, :, :]  # (nc, 2^d, d)
    flat = np.ravel_multi_index(corner.reshape(-1, d).T, nn).reshape(len(cell_idx), -1)
    used, local = np.unique(flat, return_inverse=True)
    local = local.reshape(flat.shape)
    node_idx = np.array(np.unravel_index(used, nn)).T
    node_x = origin + h * node_idx
    z = node_x[:, -1]
    n_unknown = len(used)

    # free-face nodes: a corner of an occupied cell shared with an empty cell inside the grid
    free = np.zeros(n_unknown, bool)
    for off in offsets:
        c = node_idx - off  # the cell whose corner `off` is the node
        inside = np.all((c >= 0) & (c < ncells), axis=1)
        empty = np.zeros(n_unknown, bool)
        empty[inside] = ~occupied[tuple(c[inside].T)]
        free |= empty
    fixed = np.full(n_unknown, np.nan)
    candidate = np.zeros(n_unknown, bool)  # may become a seepage face
    for axis, high, head in heads:
        on_side = node_idx[:, axis] == (ncells[axis] if high else 0)
        fixed[on_side & (z <= head + 1e-9 * h)] = head
        candidate |= on_side & (z > head + 1e-9 * h)
    if pond is not None:
        fixed[free & (z <= pond + 1e-9 * h) & np.isnan(fixed)] = pond
        candidate |= free & (z > pond + 1e-9 * h)
    else:
        candidate |= free
    candidate &= np.isnan(fixed)
    if np.all(np.isnan(fixed)):
        raise ValueError("no head fixed anywhere: give a 'head' on a side the soil touches, or a pond that "
                         "reaches the soil")

    Ke = _element_matrix(d) * h ** (d - 2)
    rows = np.repeat(local, 2 ** d, axis=1).ravel()
    cols = np.tile(local, (1, 2 ** d)).ravel()
    centre_z = origin[-1] + h * (cell_idx[:, -1] + 0.5)
    conductivity = np.ones(len(cell_idx))
    seep = np.zeros(n_unknown, bool)
    H = np.where(np.isnan(fixed), z.max(), fixed)
    for iteration in range(1, MAX_ITERATIONS + 1):
        previous = H
        H = _solve(Ke, rows, cols, conductivity, n_unknown, np.where(seep, z, fixed))
        new_seep = seep | (candidate & (H > z + 1e-9 * h))
        suction = (H[local].mean(axis=1) - centre_z) / h  # the cell's pressure head in cells (< 0: unsaturated)
        new_k = np.clip(1.0 + suction, unsaturated, 1.0)
        change = float(np.max(np.abs(H - previous))) / h
        settled = np.array_equal(new_seep, seep) and change < TOLERANCE
        if settled:
            break
        seep, conductivity = new_seep, conductivity + RELAX * (new_k - conductivity)
    inflow = _inflow(Ke, rows, cols, conductivity, n_unknown, H, node_idx, ncells, heads, fixed)
    # outside the soil the head is the node's elevation (p = 0), so that p falls to 0 across the free faces
    all_idx = np.array(np.unravel_index(np.arange(int(np.prod(nn))), nn)).T
    nodal = origin[-1] + h * all_idx[:, -1].astype(float)
    nodal[used] = H
    return nodal.reshape(nn), {"iterations": iteration, "settled": settled, "change": change,
                               "seepage_nodes": int(seep.sum()),
                               "saturated_cells": int((conductivity == 1.0).sum()), "cells": len(cell_idx),
                               "unknowns": n_unknown, "inflow_per_k": inflow}


def _matrix(Ke, rows, cols, conductivity, n):
    import scipy.sparse as sp

    values = (conductivity[:, None, None] * Ke[None, :, :]).ravel()
    return sp.csr_matrix((values, (rows, cols)), shape=(n, n))


def _inflow(Ke, rows, cols, conductivity, n, H, node_idx, ncells, heads, fixed) -> list[float]:
    """The water entering through each head's side per unit conductivity [m2 in 2D, m3 in 3D, times k: per
    second]: the consistent nodal fluxes (K H)_i summed over the side's nodes held at the head."""
    r = _matrix(Ke, rows, cols, conductivity, n) @ H
    out = []
    for axis, high, head in heads:
        on_side = (node_idx[:, axis] == (ncells[axis] if high else 0)) & ~np.isnan(fixed)
        out.append(float(r[on_side].sum()))
    return out


def _solve(Ke, rows, cols, conductivity, n, fixed):
    """H with H = fixed where fixed is not NaN, K H = 0 elsewhere."""
    K = _matrix(Ke, rows, cols, conductivity, n)
    known = ~np.isnan(fixed)
    H = np.where(known, fixed, 0.0)
    free = ~known
    rhs = -K[free][:, known] @ H[known]
    A = K[free][:, free].tocsr()
    if A.shape[0] <= DIRECT_LIMIT:
        from scipy.sparse.linalg import spsolve

        H[free] = spsolve(A.tocsc(), rhs)
    else:
        import pyamg

        H[free] = pyamg.smoothed_aggregation_solver(A).solve(rhs, tol=1e-10, maxiter=500)
    return H


class SeepageSurface:
    """The pore pressure of a solved steady seepage (a WaterTable's ``surface``): p = rho_w |g| max(H(x) - z, 0)
    with H the nodal head (solve_seepage), multilinear.  ``schedule(time)`` gives the heads [(axis, high side?,
    head)] at a time; the state is solved again through the soil's particles as they stand whenever a head has
    moved by RESOLVE cells since the last solve (quasi-steady: a drained soil's pore pressure follows at once),
    and ``pond`` is the pond's level at t = 0 on the free faces."""

    #: not drawn: solved with its faces, so never above the ground by mistake (phreatic_surface.table_warnings)
    drawn = False

    def __init__(self, schedule, pond, grid, unsaturated, points):
        self.schedule = schedule
        self.pond = pond
        self.origin = np.asarray(grid.origin, float)
        self.h = float(grid.h)
        self.ncells = np.asarray(grid.ncells, np.int64)
        self.unsaturated = unsaturated
        self.solves = 0
        self._solve(schedule(0.0), points)

    def _solve(self, heads, points) -> None:
        self.head, self.report = solve_seepage(points, self.origin, self.h, self.ncells, heads, self.pond,
                                               self.unsaturated)
        self.heads = heads
        self.solves += 1

    def pressure(self, p_x, p_material, acts, rise, gradient, out, time: float = 0.0) -> None:
        heads = self.schedule(time)
        if max((abs(a[2] - b[2]) for a, b in zip(heads, self.heads)), default=0.0) >= RESOLVE * self.h:
            self._solve(heads, p_x[acts[p_material] > 0.0])
        kernel = head_pressure_2d if p_x.shape[1] == 2 else head_pressure_3d
        kernel(p_x, p_material, acts, self.head.astype(p_x.dtype), self.origin.astype(p_x.dtype), self.h,
               gradient, out)

    def describe(self) -> str:
        r = self.report
        return (f"a steady seepage state ({r['unknowns']} unknowns, {r['iterations']} iterations, "
                f"{r['seepage_nodes']} seepage-face nodes, {r['saturated_cells']} of {r['cells']} cells saturated"
                f"{'' if r['settled'] else ', not settled'})")


def head_at(nodal, origin, h, pts) -> np.ndarray:
    """The head [m] at the points ``pts`` (n, d), multilinear between the nodes (numpy; set-up only)."""
    pts = np.asarray(pts, float)
    d = pts.shape[1]
    s = (pts - origin) / h
    i = np.clip(np.floor(s).astype(np.int64), 0, np.asarray(nodal.shape) - 2)
    f = np.clip(s - i, 0.0, 1.0)
    out = np.zeros(len(pts))
    for corner in itertools.product((0, 1), repeat=d):
        w = np.ones(len(pts))
        for a, c in enumerate(corner):
            w *= f[:, a] if c else 1.0 - f[:, a]
        out += w * nodal[tuple((i[:, a] + corner[a]) for a in range(d))]
    return out
