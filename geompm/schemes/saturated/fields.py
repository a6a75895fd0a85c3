"""The saturated scheme's particle fields and the resolved pore water of a scene (docs/pore-water.md).

``FIELDS`` are the particle arrays the scheme declares (schemes/base.Field); the state holds them as any other
array, so the sort, the migration between ranks and the checkpoints carry them.  p_mass is then the solids'
mass and p_stress the effective stress.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from geompm.schemes.base import Field
from geompm.schemes.saturated.kernels import WATER
from geompm.schemes.saturated.surface import column_surface


FIELDS = (
    Field("p_vw", "d", "m/s", "water velocity"),
    Field("p_Cw", "dd", "1/s", "the water's affine matrix (APIC and MLS)"),
    Field("p_pore", "", "Pa", "pore pressure, compression positive: the pressure that acts on the grid and that "
                              "every output reports, the carried pressure seen through the grid"),
    Field("p_pore_carried", "", "Pa", "each particle's own sum of its mass-balance increments (the state "
                                      "variable; equal to p_pore without solver.pore_pressure_smoothing)"),
    Field("p_drained", "", "-", "1 where the particle held no pore pressure at its last update (dry, separated, "
                                "at the free surface or a drained boundary), else 0"),
    Field("p_n", "", "-", "porosity"),
    Field("p_sat", "", "-", "1 for a saturated particle, 0 for a dry one"),
    Field("p_wt", "", "m", "height of its body's water table along the upward direction at set-up"),
    Field("p_wt_depth", "", "m", "depth of its body's water table below its column's free surface at set-up (the "
                                 "hydrostatic reference follows the flow's own surface: surface.py)"),
)


@dataclass
class PoreWater:
    """What the two-phase step, the writers and the series need of the case, resolved."""

    table: np.ndarray  # (materials, len(WATER)): the kernels' rows (kernels.WATER), zeros for dry materials
    wet: list[bool]  # per material
    walls: np.ndarray = field(default_factory=lambda: np.zeros((0, 8)))  # (stages, len(WALL)): kernels.node_split
    up: np.ndarray | None = None  # unit vector against gravity, None without gravity
    g: float = 0.0  # |gravity| [m/s2]
    smoothing: bool = True  # the pore pressure seen through the grid each step (kernels.smooth_gather)
    solids: object = None  # the rigid solids' node fill (solids.SolidFill), made once the stages are set up
    grid: tuple = ()  # (origin, extent, cell size) of the grid [m]: the free surface's columns (surface.py)
    pressure_solver: object = None  # solver.pressure_solver (the semi-implicit scheme's solve)
    heads: list = field(default_factory=list)  # per wall row: (times [s], levels [m]) of a held head, or None

    def heads_at(self, time: float) -> np.ndarray:
        """Each wall row's held head H [m] at ``time`` (NaN for a wall without one)."""
        return np.array([np.nan if s is None else float(np.interp(time, s[0], s[1])) for s in self.heads])

    def surface(self, st, comm_max=None) -> np.ndarray:
        """Each particle's column's free surface z_s [m] along the upward direction (surface.py)."""
        origin, extent, h = self.grid
        return column_surface(st.p_x, st.p_vol0 ** (1.0 / st.p_x.shape[1]), self.up, origin, extent, h, comm_max)

    def table_depth(self, st) -> np.ndarray:
        """At set-up: the depth of each saturated particle's water table below its column's free surface [m]."""
        if self.up is None:
            return np.zeros(st.n)
        return st.p_sat * np.maximum(self.surface(st) - st.p_wt, 0.0)

    def hydrostatic(self, st, comm_max=None) -> np.ndarray:
        """Each particle's hydrostatic pore pressure rho_w |g| max(0, z_s - d_wt - z) [Pa], z_s its column's
        free surface now and d_wt its table's depth below it at set-up (surface.py); 0 for dry particles."""
        if self.up is None:
            return np.zeros(st.n)
        level = self.surface(st, comm_max) - st.p_wt_depth
        return st.p_sat * self.table[st.p_material, WATER.rho_w] * self.g * np.maximum(level - st.p_x @ self.up, 0.0)

    def excess(self, st, comm_max=None) -> np.ndarray:
        """Excess pore pressure p - p_hydrostatic [Pa] per particle; ``comm_max``: the columns' surfaces
        over every rank."""
        return st.p_pore - self.hydrostatic(st, comm_max)
