"""Periodic boundary along one axis (channel and infinite-slope flows).

The period is the grid's extent along ``axis``: node i and node i + ncells
are the same node.  Particles leaving one side re-enter at the other (their
initial position moves with them, so displacements stay continuous).  Grid
nodes beyond the faces are ghosts of their periodic images: after the grid
update each ghost and its image are merged,
    v = (m_ghost v_ghost + m_image v_image) / (m_ghost + m_image),
which equals folding mass, momentum and force before the update because the
explicit update is linear per node.  The scheduler runs it before every other grid
stage (``phase = MERGE``, stages.py).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numba import njit, prange
from pydantic import Field

from ..plugin import Params
from ..stages import MERGE, GridStage, ParticleStage


class PeriodicParams(Params):
    axis: Literal["x", "y", "z"] = Field(description="Periodic axis; the period is the grid extent along it")


@njit(cache=True)
def periodic_fold(g_mass, g_vel, g_vel_old, lo, nloc, axis, ncells, fold_old):
    """Merge each ghost node with its image: summed mass, mass-weighted velocity (and the
    pre-update velocity when ``fold_old``, i.e. when the scene keeps one, engine/grid.py)."""
    nn, d = g_vel.shape
    inner = 1
    for a in range(axis + 1, d):
        inner *= nloc[a]
    outer = nn // (inner * nloc[axis])
    for i in range(nloc[axis]):
        gi = lo[axis] + i
        if 0 <= gi < ncells:
            continue
        j = gi % ncells - lo[axis]
        if j < 0 or j >= nloc[axis]:
            continue  # the image is outside the window: the ghost holds the whole node
        for o in range(outer):
            for q in range(inner):
                g = (o * nloc[axis] + i) * inner + q
                r = (o * nloc[axis] + j) * inner + q
                m = g_mass[g] + g_mass[r]
                if m <= 0.0:
                    continue
                for a in range(d):
                    v = (g_mass[g] * g_vel[g, a] + g_mass[r] * g_vel[r, a]) / m
                    g_vel[g, a] = v
                    g_vel[r, a] = v
                    if fold_old:
                        vo = (g_mass[g] * g_vel_old[g, a] + g_mass[r] * g_vel_old[r, a]) / m
                        g_vel_old[g, a] = vo
                        g_vel_old[r, a] = vo
                g_mass[g] = m
                g_mass[r] = m


@njit(parallel=True, cache=True)
def periodic_wrap(p_x, p_x0, axis, lo_x, period):
    for p in prange(p_x.shape[0]):
        x = p_x[p, axis]
        if x < lo_x or x >= lo_x + period:
            shift = np.floor((x - lo_x) / period) * period
            p_x[p, axis] -= shift
            p_x0[p, axis] -= shift


class Periodic(GridStage, ParticleStage):
    name = "periodic"
    description = "Periodic boundary along one axis (period = grid extent)"
    Params = PeriodicParams
    phase = MERGE  # folds ghost nodes onto their images before every other grid stage

    @classmethod
    def check(cls, params, case):
        k = "xyz".index(params.axis)
        if k >= case.dimension:
            return [("axis", f"'{params.axis}' does not exist in a {case.dimension}D case")]
        if case.grid.extent[k] < 4 * case.grid.cell_size:
            return [("axis", "the periodic axis needs at least 4 cells")]
        return []

    def setup(self, scene):
        self.axis = "xyz".index(self.params.axis)
        self.ncells = int(scene.grid.ncells[self.axis])
        self.lo_x = float(scene.grid.origin[self.axis])
        self.period = self.ncells * scene.grid.h

    def apply_grid(self, view, dt, time, remap):
        fold_old = view.g_vel_old is not None
        old = view.g_vel_old if fold_old else view.g_vel
        periodic_fold(view.g_mass, view.g_vel, old, view.lo, view.nloc, self.axis, self.ncells, fold_old)

    def apply_particles(self, state, dt, time):
        periodic_wrap(state.p_x, state.p_x0, self.axis, self.lo_x, self.period)
