"""The resolved pore water of a scene (setup/pore_water.py makes it; docs/pore-water.md)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from geompm.kernels.twophase import RHO_W


@dataclass
class PoreWater:
    """What the two-phase step, the writers and the series need of the case, resolved."""

    table: np.ndarray  # (materials, 7): the kernels' rows (kernels/twophase.py), zeros for dry materials
    wet: list[bool]  # per material
    walls: np.ndarray = field(default_factory=lambda: np.zeros((0, 8)))  # (stages, 8): kernels/twophase.node_split
    up: np.ndarray | None = None  # unit vector against gravity, None without gravity
    g: float = 0.0  # |gravity| [m/s2]
    smoothing: bool = True  # the pore pressure seen through the grid each step (kernels/twophase.smooth_pressure)

    def hydrostatic(self, st) -> np.ndarray:
        """Each particle's hydrostatic pore pressure rho_w |g| (z_wt - z) below its body's water table at its
        current height [Pa], 0 for dry particles."""
        if self.up is None:
            return np.zeros(st.n)
        return st.p_sat * self.table[st.p_material, RHO_W] * self.g * np.maximum(st.p_wt - st.p_x @ self.up, 0.0)

    def excess(self, st) -> np.ndarray:
        """Excess pore pressure p - p_hydrostatic [Pa] per particle."""
        return st.p_pore - self.hydrostatic(st)
