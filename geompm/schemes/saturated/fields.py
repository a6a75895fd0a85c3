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
    Field("p_wt", "", "m", "height of its body's water table along the upward direction (the hydrostatic "
                           "reference of the excess pore pressure)"),
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

    def hydrostatic(self, st) -> np.ndarray:
        """Each particle's hydrostatic pore pressure rho_w |g| (z_wt - z) below its body's water table at its
        current height [Pa], 0 for dry particles."""
        if self.up is None:
            return np.zeros(st.n)
        return st.p_sat * self.table[st.p_material, WATER.rho_w] * self.g * np.maximum(st.p_wt - st.p_x @ self.up, 0.0)

    def excess(self, st) -> np.ndarray:
        """Excess pore pressure p - p_hydrostatic [Pa] per particle."""
        return st.p_pore - self.hydrostatic(st)
