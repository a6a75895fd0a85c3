"""Periodic boundary along one axis (channel and infinite-slope flows).

The period is the grid's extent along ``axis``: node i and node i + ncells
are the same node.  Particles leaving one side re-enter at the other (their
initial position moves with them, so displacements stay continuous).  Grid
nodes beyond the faces are ghosts of their periodic images: after the grid
update each ghost and its image are merged,
    v = (m_ghost v_ghost + m_image v_image) / (m_ghost + m_image),
which equals folding mass, momentum and force before the update because the
explicit update is linear per node.  The stage gives the image of a node index
(``node_image``) and the backend merges (contract/stages.py); the scheduler runs it
before every other grid stage (``phase = MERGE``).
"""

from __future__ import annotations

import math
from typing import Literal

from numba import njit
from pydantic import Field

from geompm.contract.layout import pack_in_layout, param_layout
from geompm.contract.plugin import Params
from geompm.contract.stages import MERGE, NO_AUX, GridStage, ParticleStage

#: packed parameters: the periodic axis, its cell count, the grid's lower coordinate on it [m], the period [m]
PERIODIC = param_layout("axis", "ncells", "lo_x", "period")


class PeriodicParams(Params):
    axis: Literal["x", "y", "z"] = Field(description="Periodic axis; the period is the grid extent along it")


@njit(cache=True, inline="always")
def periodic_image(prm, axis, i):
    """Global node index i along ``axis``: its image i mod ncells on the periodic axis, else itself."""
    if axis != int(prm[PERIODIC.axis]):
        return i
    n = int(prm[PERIODIC.ncells])
    return i % n


@njit(cache=True, inline="always")
def periodic_wrap(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
    """A particle that left the period re-enters at the other side, with its initial position."""
    a = int(prm[PERIODIC.axis])
    lo_x = prm[PERIODIC.lo_x]
    period = prm[PERIODIC.period]
    if x[a] < lo_x or x[a] >= lo_x + period:
        shift = math.floor((x[a] - lo_x) / period) * period
        x[a] -= shift
        x0[a] -= shift


class Periodic(GridStage, ParticleStage):
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)
    name = "periodic"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Periodic boundary along one axis (period = grid extent)"
    Params = PeriodicParams
    phase = MERGE  # folds ghost nodes onto their images before every other grid stage
    node_image = periodic_image
    particle_rule = periodic_wrap

    @classmethod
    def check(cls, params, case):
        k = "xyz".index(params.axis)
        if k >= case.dimension:
            return [("axis", f"'{params.axis}' does not exist in a {case.dimension}D case")]
        if case.grid.extent[k] < 4 * case.grid.cell_size:
            return [("axis", "the periodic axis needs at least 4 cells")]
        return []

    def setup(self, scene):
        axis = "xyz".index(self.params.axis)
        ncells = int(scene.grid.ncells[axis])
        self.prm = pack_in_layout(PERIODIC, {"axis": axis, "ncells": ncells, "lo_x": float(scene.grid.origin[axis]),
                                             "period": ncells * scene.grid.h}, f"stage '{self.label}'")

    def periodic_axes(self):
        return ("xyz".index(self.params.axis),)

    def grid_args(self, dt, time, remap):
        return self.prm, NO_AUX

    def particle_args(self, dt, time):
        return self.prm, NO_AUX
