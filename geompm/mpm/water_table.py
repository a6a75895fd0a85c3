"""The water table: the pore pressure of its soils at each step (schema: triggers.water_table).

z_wt(t) is piecewise linear through the case's (times, heights) and held at its end values outside them.
Before each P2G the Simulation asks for the pore pressure at the particles' current positions
(kernels/phreatic.py) and hands it to the backend, whose P2G then takes the total stress sigma' - p I; the
laws integrate the effective stress, unchanged.  Nothing is stored per particle: p is a function of position
and time, so a spatial sort, a deletion or a resumed run need nothing of it.
"""

from __future__ import annotations

import numpy as np

from geompm.kernels.phreatic import phreatic_pressure


class WaterTable:
    """z_wt(t) through ``times`` [s] and ``heights`` [m] along the unit ``normal``; ``gradient`` =
    rho_w (-g . n) [Pa/m]; ``acts`` (materials,) 1.0 for a soil under the table's pressure (scene order)."""

    def __init__(self, times, heights, normal, gradient, acts):
        self.times = np.asarray(times, float)
        self.heights = np.asarray(heights, float)
        self.normal = np.asarray(normal, float)
        self.gradient = float(gradient)
        self.acts = np.asarray(acts, float)
        self._out = np.zeros(0)

    def height(self, time: float) -> float:
        return float(np.interp(time, self.times, self.heights))

    def pressure(self, p_x, p_material, time: float) -> np.ndarray:
        """The pore pressure [Pa] of every particle at ``time`` (a buffer reused between calls)."""
        n = p_x.shape[0]
        if self._out.shape[0] != n or self._out.dtype != p_x.dtype:
            self._out = np.zeros(n, p_x.dtype)
        phreatic_pressure(p_x, p_material, self.acts, self.normal.astype(p_x.dtype), self.height(time),
                          self.gradient, self._out)
        return self._out
