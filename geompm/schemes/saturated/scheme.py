"""Saturated soil: one point, two velocities, explicit in time (docs/pore-water.md; Zienkiewicz et al. 1980;
Bandara & Soga 2015, Computers and Geotechnics 63:199).

One step, the grid holding the mixture while the stages act, then the solid and the water taking their own
velocities (the passes: schemes/saturated/cpu.py and cuda.py around the per-item functions of kernels.py):

    window -> p2g (pressure smoothed, total stress, both phases, halo summed, fill with the rigid solids'
    share (solids.py), mixture)
    -> grid update (the mixture, + gravity) -> grid stages before BOUNDARY (loads, damping)
    -> snapshot (relative velocity, drag implicit) -> BOUNDARY and OBSTACLE stages
    -> split (solid and water velocities, walls' water rules) -> water G2P and the pressure's increment
    -> solid G2P -> particle stages -> porosity -> effective-stress update (the laws, unchanged)

Every scatter is summed over the ranks' halo before it is read, so the step runs on several MPI ranks as the
dry ones do (docs/parallel.md).
"""

from __future__ import annotations

import contextlib
import math

import numpy as np

from geompm.contract.stages import BOUNDARY
from geompm.mpm.water_table import pore_pressure_fields
from geompm.schemes.base import Scheme
from geompm.schemes.saturated import checks, setup
from geompm.schemes.saturated.fields import FIELDS
from geompm.schemes.saturated.kernels import WALL, WATER
from geompm.schemes.saturated.solids import SolidFill



class Saturated(Scheme):
    holds_step = False  # its wave speeds are the step-end reductions of its own passes
    name = "saturated"
    description = "saturated soil, one point and two velocities (docs/pore-water.md)"
    pore_water = True
    default = True
    split_force = True
    fields = FIELDS
    #: runs water of infinite bulk modulus (the pressure implicit: semi_implicit.py)
    incompressible_water = False
    #: the backend's passes of the scheme, by backend name (imported when a backend of that name asks)
    backend_modules = {"cpu": ("geompm.schemes.saturated.cpu", "SaturatedCpu"),
                       "cuda": ("geompm.schemes.saturated.cuda", "SaturatedCuda")}
    body_width = 4  # saturated flag, water-table height, pore pressure, buoyant flag (setup.body_water)

    @classmethod
    def problems(cls, case, loaded):
        return checks.unsupported(case, loaded, cls.incompressible_water)

    @classmethod
    def warnings(cls, case):
        return checks.flow_warnings(case)

    def __init__(self, case=None, names=()):
        #: the resolved pore water (fields.PoreWater): the materials' table, gravity, walls
        self.water = setup.material_table(case, list(names)) if case is not None else None

    def law_params(self, case, name, params):
        return setup.skeleton_params(case, name, params)

    def body_arrays(self, body, mid, pts, h, ppc):
        return setup.body_water(body, self.water, mid, pts, h, ppc)

    def overburden_mass(self, p_mass, p_vol, p_material, arrays):
        return setup.buoyant_mass(p_mass, p_vol, p_material, arrays[0], arrays[3], self.water)

    def init_fields(self, state, arrays) -> None:
        state.p_sat, state.p_wt, state.p_pore = (np.ascontiguousarray(a) for a in arrays[:3])
        state.p_pore_carried = state.p_pore.copy()
        state.p_drained = 1.0 - state.p_sat
        state.p_vw = state.p_v.copy()
        state.p_Cw = np.zeros_like(state.p_C)
        state.p_n = self.water.table[state.p_material, WATER.n0].copy()
        state.p_wt_depth = self.water.table_depth(state)

    @contextlib.contextmanager
    def drained(self):
        """Every saturated material drained while the context lasts (setup.drain: p held, the water bound to
        the grains), the table restored after (the backend's passes copy it when a Simulation is made, so a
        Simulation made inside runs drained and one made after coupled)."""
        saved = self.water.table.copy()
        setup.drain(self.water.table, np.asarray(self.water.wet, bool))
        try:
            yield
        finally:
            self.water.table[:] = saved

    def at_rest(self, state) -> None:
        state.p_vw[:] = 0.0
        state.p_Cw[:] = 0.0

    def after_stages(self, scene) -> None:
        bounds = [s for s in scene.stages if s.water_boundary() is not None]
        self.water.heads = [s.water_head() for s in bounds]
        rows = [setup.wall_row(s.water_boundary(), held is not None) for s, held in zip(bounds, self.water.heads)]
        self.water.walls = np.array(rows).reshape(-1, len(WALL))
        self.water.solids = SolidFill(scene)

    def backend_passes(self, backend):
        import importlib

        if backend.name not in self.backend_modules:
            raise NotImplementedError(f"the scheme '{self.name}' has no passes for the '{backend.name}' backend")
        module, cls = self.backend_modules[backend.name]
        return getattr(importlib.import_module(module), cls)(backend, self.water)

    passes = ("window", "two_phase_p2g", "grid_update", "loads_and_damping", "relative_velocity", "contacts",
              "split", "water_g2p", "g2p_stages_and_stress_update")

    def two_phase_p2g(self, run, dt: float) -> None:
        """Both phases onto the grid (the pressure smoothed, the total stress, the halo summed), the nodes'
        fill and the mixture."""
        run.backend.scheme_passes.p2g(run.view, run.halo, run.time)

    def loads_and_damping(self, run, dt: float) -> None:
        """The grid stages before BOUNDARY, acting on the mixture."""
        run.grid_stages_run(run.view, dt, phases=(-math.inf, BOUNDARY))

    def relative_velocity(self, run, dt: float) -> None:
        """The water's velocity relative to the solid after the step, drag implicit."""
        run.backend.scheme_passes.snapshot(run.view, dt)

    def contacts(self, run, dt: float) -> None:
        """The boundary and obstacle stages, acting on the mixture."""
        run.grid_stages_run(run.view, dt, phases=(BOUNDARY, math.inf))

    def split(self, run, dt: float) -> None:
        """The solid's and the water's velocities from the mixture's, with the walls' water rules."""
        run.backend.scheme_passes.split(run.view, dt)

    def water_g2p(self, run, dt: float) -> None:
        """The water's particle velocity and the pore pressure's step, at the particles before they move."""
        run.backend.scheme_passes.water_g2p(run.view, dt, run.halo)

    def porosity(self, run, dt: float) -> None:
        """Each particle's porosity from its skeleton's volume."""
        run.backend.scheme_passes.porosity()

    def after_particles(self, run, dt: float) -> None:
        """The porosity from the volumes G2P left, after the laws (which do not read it: a law sees the effective
        stress and its own state), so that G2P, the particle stages and the laws run as one particle pass
        (``g2p_stages_and_stress_update``: one launch per material block on a device)."""
        self.porosity(run, dt)

    def wave_speed(self, scene, state, finite_only: bool = False, comm=None) -> float:
        from geompm.schemes.saturated.speeds import saturated_speeds

        speeds = saturated_speeds(scene, state, self.water, comm)
        return max(speeds["undrained"], speeds["water"], speeds["skeleton"])

    def series(self, run) -> dict[str, float]:
        """``max_excess_pore_pressure`` [Pa] over the particles of every rank, and per body
        (``..._body<b>``) where a scene has more than one (docs/pore-water.md)."""
        st, sc, top = run.state, run.scene, run.domain.comm.max
        excess = self.water.excess(st, top)
        nb = len(sc.body_materials)
        row = np.full(1 + (nb if nb > 1 else 0), -np.inf)
        if st.n:
            row[0] = excess.max()
            for b in range(row.size - 1):
                mine = excess[st.p_body == b]
                row[1 + b] = mine.max() if mine.size else -np.inf
        row = top(row)
        out = {"max_excess_pore_pressure": float(row[0]) if np.isfinite(row[0]) else float("nan")}
        for b in range(row.size - 1):
            out[f"max_excess_pore_pressure_body{b}"] = float(row[1 + b]) if np.isfinite(row[1 + b]) else float("nan")
        return out

    def point_data(self, run, st) -> dict:
        """The pore water's fields: pore pressure p and its excess over the hydrostatic
        p_h = rho_w |g| (z_wt - z) [Pa, compression positive], porosity, water velocity, the drained flag
        (1 where the particle held no pore pressure at its last update: dry, separated, at the free surface
        or a drained boundary), and the effective stress with its invariants; the particle "stress" becomes
        the total stress sigma' - p I."""
        s = st.p_stress
        mean = -(s[:, 0] + s[:, 1] + s[:, 2]) / 3.0
        dev = s[:, :3] + mean[:, None]
        vw = np.zeros((st.n, 3))
        vw[:, :st.dim] = st.p_vw
        out = pore_pressure_fields(s, st.p_pore.copy(), mean)
        out.update({"effective_von_mises_q": np.sqrt(1.5 * (dev ** 2).sum(axis=1) + 3.0 * (s[:, 3:] ** 2).sum(axis=1)),
                    "excess_pore_pressure": self.water.excess(st), "porosity": st.p_n.copy(),
                    "water_velocity": vw, "drained": st.p_drained.copy()})
        return out

    def basal_water(self, st):
        """(pore pressure [Pa], mass of solids and water [kg], |g| [m/s2]) of each particle: the hazard maps'
        basal pore-pressure ratio (writers/hazard_maps.py)."""
        rho_w = self.water.table[st.p_material, WATER.rho_w]
        return st.p_pore, st.p_mass + st.p_sat * st.p_n * rho_w * st.p_vol, self.water.g

    def report(self, scene) -> list[str]:
        from geompm.schemes.saturated.report import pore_water_lines

        return pore_water_lines(scene, self.water)
