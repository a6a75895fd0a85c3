"""Background grid: the fixed global lattice and the per-step active window.

The global grid has nodes i_a = 0..ncells[a] along each axis at
``origin + i h``.  Each step only the window of nodes that the particles'
stencils touch is allocated and computed (``lo``, ``nloc``), so a small flow in
a large domain costs what the flow costs.  Buffers grow geometrically and are
reused between steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from geompm.errors import SimulationError
from geompm.kernels.reduce import cell_bounds, first_outside


@dataclass
class GridSpec:
    origin: np.ndarray  # (d,) [m]
    h: float  # cell size [m]
    ncells: np.ndarray  # (d,) int64: cells per axis; nodes 0..ncells
    kind: int  # shape-function kind (kernels/shape.py)

    @property
    def dim(self) -> int:
        return len(self.origin)

    @property
    def upper(self) -> np.ndarray:
        return self.origin + self.ncells * self.h


@dataclass
class GridView:
    """What grid stages (boundaries, obstacles, grid damping) see each step."""

    spec: GridSpec
    lo: np.ndarray  # (d,) int64 global index of the first window node
    nloc: np.ndarray  # (d,) int64 window nodes per axis
    g_mass: np.ndarray  # (nn,) [kg]
    g_mom: np.ndarray  # (nn, d) [kg m/s]
    g_force: np.ndarray | None  # (nn, d) [N]; None when P2G folds the force into the momentum
    g_vel: np.ndarray  # (nn, d) updated velocity [m/s]
    g_vel_old: np.ndarray | None  # (nn, d) velocity before the update [m/s]; None when folded
    #: (nn, 7) the nodes' pore water (contact/rules.NODE_PORE: pore pressure and total stress [Pa]) that a
    #: scheme with pore water leaves for the contact rules' effective-stress friction; None in a dry scene
    g_pore: np.ndarray | None = None


class GridBuffers:
    """Reusable grid arrays, including the per-chunk private P2G grids.

    ``split``: the scene needs the nodal force and the pre-update velocity on their own
    (FLIP, local damping); otherwise P2G folds dt f into the momentum,
    the private grids have 1 + d instead of 1 + 2d columns, and g_force / g_vel_old are
    neither allocated nor offered to the stages.
    """

    def __init__(self, spec: GridSpec, nchunks: int | None = None, split: bool = True, dtype=np.float64):
        self.spec, self.dtype = spec, np.dtype(dtype)
        self.nchunks = nchunks or numba.get_num_threads()
        self.split = split
        self.cap = 0
        self._alloc(1024)

    def _alloc(self, cap):
        d, c = self.spec.dim, self.nchunks
        extra = d if self.split else 0
        self.cap = cap
        f = self.dtype
        self.c_grid = np.zeros((c, cap, 1 + d + extra), f)
        self.g_mass = np.zeros(cap, f)
        self.g_mom = np.zeros((cap, d), f)
        self.g_force = np.zeros((cap if self.split else 0, d), f)
        self.g_vel = np.zeros((cap, d), f)
        self.g_vel_old = np.zeros((cap if self.split else 0, d), f)

    def nbytes(self) -> int:
        return sum(a.nbytes for a in (self.c_grid, self.g_mass, self.g_mom, self.g_force,
                                      self.g_vel, self.g_vel_old))

    def window(self, p_x) -> GridView:
        """Window covering every particle's stencil; error if a particle left the grid."""
        return self.view(*window_extent(self.spec, cell_bounds(p_x, self.spec.origin, 1.0 / self.spec.h),
                                        lambda: p_x))

    def view(self, lo, nloc) -> GridView:
        """The window of ``nloc`` nodes per axis from global node ``lo`` (parallel/halo.py gives it for a
        rank's slab), its buffers grown when needed."""
        nn = int(np.prod(nloc))
        if nn > self.cap:
            self._alloc(int(nn * 1.25) + 64)
        split = self.split
        return GridView(self.spec, lo, nloc, self.g_mass[:nn], self.g_mom[:nn],
                        self.g_force[:nn] if split else None, self.g_vel[:nn],
                        self.g_vel_old[:nn] if split else None)


def window_extent(spec: GridSpec, b: np.ndarray, positions) -> tuple[np.ndarray, np.ndarray]:
    """(lo, nloc) of the window over the particles' cell bounds ``b`` (2, d) (kernels/reduce.cell_bounds);
    SimulationError naming the first particle outside the grid (``positions()``: the host p_x) if one is."""
    if (b[0] < -1).any() or (b[1] > spec.ncells).any():
        p_x = positions()
        p = first_outside(p_x, spec.origin - spec.h, spec.upper + spec.h)
        raise SimulationError(
            f"particle {p} at x = {np.array2string(p_x[p], precision=4)} m left the grid "
            f"[{np.array2string(spec.origin, precision=4)}, {np.array2string(spec.upper, precision=4)}] m; "
            "enlarge grid.extent or add wall boundaries"
        )
    return (b[0] - 1).astype(np.int64), (b[1] - b[0] + 4).astype(np.int64)
