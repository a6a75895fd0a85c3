"""The water table: the pore pressure of its soils at each step (schema: triggers.water_table).

The table is a plane at height z_wt(t) along its normal (kernels/phreatic.phreatic_pressure), or a phreatic
surface from data, hydrostatic along the vertical below it (a polyline in 2D, a lattice in 3D from points or a
raster: mpm/phreatic_surface.py) raised by rise(t); either may stand under a pond, a level of free water
z_p(t) outside the soil.  Schedules are piecewise linear through the case's (times, values) and held at their
end values outside them.  Before each P2G the Simulation asks for the pore pressure at the particles' current
positions and hands it to the backend, whose P2G then takes the total stress; the laws integrate the effective
stress, unchanged.  Nothing is stored per particle: p is a function of position and time, so a spatial sort, a
deletion or a resumed run need nothing of it.

**The pond.**  Under a pond the water in the soil stands at least at the pond's level, p = max(p_table,
p_pond) with p_pond = rho_w |g| max(z_p - z, 0), and the pond presses on every face of the soil below its
level.  That pressure on the faces is, by the divergence theorem over the soil (p_pond continuous across the
faces), the body force -grad p_pond = rho_w |g| up on the submerged soil plus the stress p_pond I:

    f_i = - int sigma' . grad N_i dV + int (p - p_pond) grad N_i dV - int N_i grad p_pond dV

so the grid sees the total stress over the excess sigma' - (p - p_pond) I and each submerged particle its
buoyancy rho_w |g| V0 (kernels/phreatic.buoyancy).  The faces need not be found, the pond's load moves with
them, and a table that daylights on a face above the pond pushes that face out (a seepage face, p = 0, is
what the soil then reaches: the warning of schema/triggers.py).  Without a pond p_pond = 0: the table's
formulation, unchanged.

A scene without a water table gets ``NO_WATER_TABLE``, which loads nothing, adds no series column, no work
and no field: the step, the health check and the writers call the same methods either way.
"""

from __future__ import annotations

import numpy as np

from geompm.kernels.phreatic import phreatic_pressure, pond_pressure, pore_work, scatter_buoyancy


class WaterTable:
    """z_wt(t) through ``times`` [s] and ``heights`` [m] along the unit ``normal`` (a plane; None with a
    ``surface`` or a pond alone); ``gradient`` = rho_w (-g . n) [Pa/m]; ``acts`` (materials,) 1.0 for a soil
    under the table's pressure (scene order).  ``surface``: a phreatic surface (mpm/phreatic_surface.py) raised
    by ``heights`` [m] at ``times``; ``pond``: (times, levels [m]) of free water outside the soil, level
    along the axis ``up`` (against gravity), its pressure rho_w |g| = ``weight`` [Pa/m] per metre of depth."""

    def __init__(self, times, heights, normal, gradient, acts, surface=None, pond=None, up=None, weight=None,
                 rho_w=1000.0):
        self.times = np.asarray(times, float)
        self.heights = None if heights is None else np.asarray(heights, float)
        self.normal = None if normal is None else np.asarray(normal, float)
        self.gradient = float(gradient)
        self.acts = np.asarray(acts, float)
        self.surface = surface
        self.pond = None if pond is None else (np.asarray(pond[0], float), np.asarray(pond[1], float))
        self.up = up
        self.weight = self.gradient if weight is None else float(weight)
        self.rho_w = float(rho_w)
        self._out = np.zeros(0)
        self._pond = np.zeros(0)

    def height(self, time: float) -> float:
        """The plane's height, or the surface's rise [m], at ``time``; 0 for a pond alone."""
        return 0.0 if self.heights is None else float(np.interp(time, self.times, self.heights))

    def pond_level(self, time: float) -> float | None:
        return None if self.pond is None else float(np.interp(time, *self.pond))

    def _buffers(self, p_x):
        n = p_x.shape[0]
        if self._out.shape[0] != n or self._out.dtype != p_x.dtype:
            self._out = np.zeros(n, p_x.dtype)
            self._pond = np.zeros(n, p_x.dtype)
        return self._out, self._pond

    def pressure(self, p_x, p_material, time: float) -> np.ndarray:
        """The pore pressure [Pa] of every particle at ``time``: the table's, raised to the pond's below its
        level (a buffer reused between calls; the pond's share is kept beside it for ``load``)."""
        out, pond = self._buffers(p_x)
        if self.surface is not None:
            self.surface.pressure(p_x, p_material, self.acts, self.height(time), self.gradient, out, time)
        elif self.normal is not None:
            phreatic_pressure(p_x, p_material, self.acts, self.normal.astype(p_x.dtype), self.height(time),
                              self.gradient, out)
        else:
            out[:] = 0.0
        if self.pond is not None:
            pond_pressure(p_x, p_material, self.acts, self.up, self.pond_level(time), self.weight, pond, out)
        else:
            pond[:] = 0.0
        return out

    def load(self, backend, time: float) -> None:
        """Hand the backend the pore pressure its next P2G takes out of the effective stress (the excess
        over the pond's)."""
        state = backend.host_state()
        p = self.pressure(state.p_x, state.p_material, time)
        if self.pond is not None:
            p -= self._pond  # the excess, in place: the buffer is refilled by the next call
        backend.set_table_pressure(p)

    def force(self, backend, view, dt: float) -> None:
        """After P2G: the pond's buoyancy on the submerged particles into the nodal force (kernels/phreatic.
        scatter_buoyancy; the pressure of the last ``load``)."""
        if self.pond is None:
            return
        state = backend.host_state()
        g = backend.scene.grid
        split = view.g_force is not None and backend.split_force
        scatter_buoyancy(state.p_x, self._pond, state.p_vol0, self.weight, self.up, g.origin, 1.0 / g.h, g.kind,
                         view.lo, view.nloc, 1.0 if split else dt, view.g_force if split else view.g_mom)

    def buoyant_mass(self, p_x, p_material, p_mass, p_vol) -> np.ndarray:
        """The particles' masses less the pond's water they displace, rho_w V (the geostatic stress's
        overburden under a pond: setup/assemble.py)."""
        if self.pond is None:
            return p_mass
        self.pressure(p_x, p_material, 0.0)
        return p_mass - np.where(self._pond > 0.0, self.rho_w * p_vol, 0.0)

    def excess(self, p_x, p_material, time: float) -> np.ndarray:
        """p - p_pond [Pa]: the pressure the grid's total stress takes."""
        return self.pressure(p_x, p_material, time) - self._pond

    def series(self, time: float) -> dict[str, float]:
        out = {} if self.heights is None else {"water_table": self.height(time)}
        if self.pond is not None:
            out["pond_level"] = self.pond_level(time)
        return out

    def work(self, backend, time: float) -> float:
        """The work [J] the table's pressure can have done on the particles (kernels/phreatic.pore_work)."""
        st = backend.host_state()
        plane = self.normal is not None and self.surface is None
        direction = self.normal if plane else self._up_vector(st.p_x.shape[1])
        return float(pore_work(self.pressure(st.p_x, st.p_material, time), st.p_vol, st.p_vol0, st.p_x, st.p_x0,
                               direction.astype(st.p_x.dtype), self.gradient if plane else self.weight))

    def _up_vector(self, dim: int) -> np.ndarray:
        e = np.zeros(dim)
        e[dim - 1 if self.up is None else self.up] = 1.0
        return e

    def describe(self, material_names) -> str:
        """`geompm validate`'s line: the table's schedule, its soils and the pond."""
        names = ", ".join(n for n, a in zip(material_names, self.acts) if a)
        values = [] if self.heights is None else self.heights
        points = ", ".join(f"{z:g} m at {t:g} s" for t, z in zip(self.times, values))
        if self.surface is not None:
            rises = "" if not np.any(values) else f", raised by {points} (linear between, held outside)"
            what = f"{self.surface.describe()}{rises}"
        elif self.normal is not None:
            what = (f"{points} along n = ({', '.join(f'{v:.3g}' for v in self.normal)}) (linear between, held "
                    f"outside)")
        else:
            what = "none in the soil beyond the pond's"
        pond = "" if self.pond is None else ("; a pond at " + ", ".join(
            f"{z:g} m at {t:g} s" for t, z in zip(*self.pond)) + " presses on the faces below it")
        return f"water table: {what}; pore pressure {self.gradient:.4g} Pa/m below it acts on {names}{pond}"

    def point_data(self, st, time: float, mean_p) -> dict:
        """The VTU fields under the table (docs/slope-stability.md): "stress" becomes the total stress."""
        return pore_pressure_fields(st.p_stress, self.pressure(st.p_x, st.p_material, time).copy(), mean_p)


class NoWaterTable:
    """A scene without a water table (module docstring): it never asks for the particles (on a device backend
    that would bring them to the host every step)."""

    def load(self, backend, time: float) -> None:
        pass

    def force(self, backend, view, dt: float) -> None:
        pass

    def series(self, time: float) -> dict[str, float]:
        return {}

    def work(self, backend, time: float) -> float:
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
    """The scene's water table (a WaterTable), or NO_WATER_TABLE."""
    return NO_WATER_TABLE if scene.water_table is None else scene.water_table
