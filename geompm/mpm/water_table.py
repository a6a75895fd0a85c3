"""The water table: the pore pressure of its soils at each step (schema: triggers.water_table).

z_wt(t) is piecewise linear through the case's (times, heights) and held at its end values outside them.
Before each P2G the Simulation asks for the pore pressure at the particles' current positions
(kernels/phreatic.py) and hands it to the backend, whose P2G then takes the total stress sigma' - p I; the
laws integrate the effective stress, unchanged.  Nothing is stored per particle: p is a function of position
and time, so a spatial sort, a deletion or a resumed run need nothing of it.

A scene without a water table gets ``NO_WATER_TABLE``, which loads nothing, adds no series column, no work
and no field: the step, the health check and the writers call the same methods either way.
"""

from __future__ import annotations

import numpy as np

from geompm.kernels.phreatic import phreatic_pressure, pore_work


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

    def load(self, backend, state, time: float) -> None:
        """Hand the backend the pore pressure its next P2G takes out of the effective stress."""
        backend.set_table_pressure(self.pressure(state.p_x, state.p_material, time))

    def series(self, time: float) -> dict[str, float]:
        return {"water_table": self.height(time)}

    def work(self, st, time: float) -> float:
        """The work [J] the table's pressure can have done on the particles (kernels/phreatic.pore_work)."""
        return float(pore_work(self.pressure(st.p_x, st.p_material, time), st.p_vol, st.p_vol0, st.p_x, st.p_x0,
                               self.normal.astype(st.p_x.dtype), self.gradient))

    def point_data(self, st, time: float, mean_p) -> dict:
        """The VTU fields under the table (docs/slope-stability.md): "stress" becomes the total stress."""
        return pore_pressure_fields(st.p_stress, self.pressure(st.p_x, st.p_material, time).copy(), mean_p)


class NoWaterTable:
    """A scene without a water table (module docstring)."""

    def load(self, backend, state, time: float) -> None:
        pass

    def series(self, time: float) -> dict[str, float]:
        return {}

    def work(self, st, time: float) -> float:
        return 0.0

    def point_data(self, st, time: float, mean_p) -> dict:
        return {}


NO_WATER_TABLE = NoWaterTable()


def pore_pressure_fields(p_stress, pore, mean_p) -> dict:
    """The output fields of effective stress ``p_stress`` (n, 6) under pore pressure ``pore`` (n,) [Pa,
    compression positive], ``mean_p`` its mean effective stress (n,): "stress" the total stress sigma' - p I,
    "mean_stress_p" the total mean stress, the effective ones beside them (a water table's, saturated soil's)."""
    total = p_stress.copy()
    total[:, :3] -= pore[:, None]
    return {"stress": total, "mean_stress_p": mean_p + pore, "effective_stress": p_stress.copy(),
            "effective_mean_stress_p": mean_p, "pore_pressure": pore}


def water_table_of(scene):
    """The scene's water table (``scene.water_table``'s tuple), or NO_WATER_TABLE."""
    return NO_WATER_TABLE if scene.water_table is None else WaterTable(*scene.water_table)
