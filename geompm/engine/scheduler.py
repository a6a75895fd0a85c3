"""The explicit MPM step: a fixed sequence of backend kernels plus the case's stages.

USL (update stress last), one step:
    [spatial sort every solver.sort_interval steps]
    P2G (mass, momentum, internal force) -> grid update (+ gravity)
    -> grid stages (boundaries, obstacles, grid damping)
    -> G2P (velocity, affine matrix, position, velocity gradient, volume)
    -> particle stages (particle damping, penetration guard) -> stress update per material block
MUSL (Sulsky, Zhou & Schreyer 1995): after the grid update, particle
velocities are updated first, re-mapped to the grid, the grid stages are
applied again, and the velocity gradient and positions come from the
re-mapped velocities.  The update order is fixed when the simulation is made
(``step`` is the USL or the MUSL step function); the kernels are the
backend's (backend/base.py).

Only the stages the case asks for are in the lists; a case without damping
has no damping pass.  Stages are ordered by their declared ``phase``
(contract/stages.py), never by plugin name; each gives per-node or per-particle
functions that the backend runs (``grid_stage``, ``particle_stages``).
"""

from __future__ import annotations

import numpy as np

from geompm.backend import make_backend
from geompm.kernels.reduce import kinetic_energy, max_coordinate, max_coordinate_by_group
from geompm.contract.stages import BOUNDARY, GridStage, ParticleStage
from geompm.engine.triggers import StrengthSchedule
from geompm.mpm.water_table import WaterTable
from geompm.parallel.whole import WHOLE


class Simulation:
    def __init__(self, scene, nchunks: int | None = None, domain=WHOLE):
        self.scene = scene
        #: how the run is shared between processes (parallel/whole.py: one; parallel/slabs.py: MPI ranks)
        self.domain = domain
        stages = sorted(scene.stages, key=lambda s: s.phase)
        self.grid_stages = [s for s in stages if isinstance(s, GridStage)]
        self.particle_stages = [s for s in stages if isinstance(s, ParticleStage)]
        # the nodal force and pre-update velocity are kept apart only when something reads them
        split_force = scene.transfer == "flip" or any(s.needs_split_force for s in self.grid_stages) \
            or scene.pore_water is not None
        self.backend = make_backend(scene, split_force, nchunks)
        self.backend.domain = domain
        self.step = self._step_musl if scene.musl else self._step_usl
        if scene.pore_water is not None:
            self.step = self._step_saturated
        trig = scene.strength_trigger
        self.strength = StrengthSchedule(*trig) if trig is not None else None
        #: the water table whose pore pressure the grid sees (mpm/water_table.py), or None
        self.water = WaterTable(*scene.water_table) if scene.water_table is not None else None
        self.time = 0.0
        self.step_count = 0
        self.dt = 0.0
        self.view = None

    @property
    def state(self):
        """The particle arrays on the host (backend.host_state())."""
        return self.backend.host_state()

    @property
    def buffers(self):
        return self.backend.buffers

    def stable_dt(self) -> float:
        return self.domain.stable_dt(self.backend)

    def distribute(self) -> None:
        """Keep this rank's particles of the whole state every rank holds (before the first step, after a
        resume); nothing in one process."""
        self.domain.distribute(self.state)

    def count(self) -> int:
        """Particles in the run, on every rank."""
        return int(round(float(self.domain.comm.sum([self.state.n])[0])))

    def _sort_if_due(self):
        every = self.scene.sort_interval
        if every and self.step_count % every == 0:
            self.backend.sort_particles()

    def _begin(self, dt):
        self.domain.before_step(self)
        self._sort_if_due()
        be = self.backend
        view = self.domain.window(be)
        if self.water is not None:
            st = self.state
            be.set_pore_pressure(self.water.pressure(st.p_x, st.p_material, self.time))
        be.p2g(view, 1.0 if be.split_force else dt)
        self.domain.sum_halo(view, (view.g_mass, view.g_mom, view.g_force))
        be.grid_update(view, dt)
        for stage in self.grid_stages:
            be.grid_stage(stage, view, dt, self.time, False)
        return view

    def _end(self, view, dt):
        self.backend.particle_stages(self.particle_stages, dt, self.time)
        self._end_stress(view, dt)

    def _end_stress(self, view, dt):
        if self.strength is not None:
            self.strength.apply(self.scene, self.backend, self.time)
        self.backend.update_stress(dt)
        self.view = view
        self.dt = dt
        self.time += dt
        self.step_count += 1

    def _step_usl(self, dt: float) -> None:
        view = self._begin(dt)
        self.backend.g2p(view, dt, set_velocity=True, move=True, gradient=True)
        self._end(view, dt)

    def _step_musl(self, dt: float) -> None:
        be = self.backend
        view = self._begin(dt)
        be.g2p(view, dt, set_velocity=True, move=False, gradient=False)
        be.p2g(view, 0.0)
        self.domain.sum_halo(view, (view.g_mass, view.g_mom))
        be.remap_velocity(view)
        for stage in self.grid_stages:
            be.grid_stage(stage, view, dt, self.time, True)
        be.g2p(view, dt, set_velocity=False, move=True, gradient=True)
        self._end(view, dt)

    def _step_saturated(self, dt: float) -> None:
        """USL with pore water (backend/twophase_cpu.py): the grid holds the mixture while the stages act;
        the solid and the water then take their own velocities."""
        self._sort_if_due()
        be, wet = self.backend, self.backend.saturated
        view = be.window()
        wet.p2g(view)
        be.grid_update(view, dt)
        for stage in self.grid_stages:
            if stage.phase >= BOUNDARY:
                break
            be.grid_stage(stage, view, dt, self.time, False)
        wet.snapshot(view, dt)
        for stage in self.grid_stages:
            if stage.phase >= BOUNDARY:
                be.grid_stage(stage, view, dt, self.time, False)
        wet.split(view, dt)
        wet.water_g2p(view, dt)
        be.g2p(view, dt, set_velocity=True, move=True, gradient=True)
        be.particle_stages(self.particle_stages, dt, self.time)
        wet.porosity()
        self._end_stress(view, dt)

    def group_fronts(self) -> dict[str, float]:
        """``front_x_body<b>`` of each body and ``front_x_<material>`` of each material [m] (the largest x of
        their particles, NaN once all have left), where a scene has more than one of them: the runout of a
        slide is its own front, not that of the ground it rests on."""
        st, sc = self.state, self.scene
        out = {}
        nbodies = len(sc.body_materials)
        top = self.domain.comm.max
        if nbodies > 1:
            for b, x in enumerate(top(max_coordinate_by_group(st.p_x, 0, st.p_body, nbodies))):
                out[f"front_x_body{b}"] = float(x) if np.isfinite(x) else float("nan")
        if len(sc.material_names) > 1:
            fronts = top(max_coordinate_by_group(st.p_x, 0, st.p_material, len(sc.material_names)))
            for name, x in zip(sc.material_names, fronts):
                out[f"front_x_{name}"] = float(x) if np.isfinite(x) else float("nan")
        return out

    def pore_pressure_series(self) -> dict[str, float]:
        """``max_excess_pore_pressure`` [Pa] over the particles, and per body (``..._body<b>``) where a scene
        has more than one (docs/pore-water.md)."""
        st, sc = self.state, self.scene
        excess = sc.pore_water.excess(st)
        out = {"max_excess_pore_pressure": float(excess.max()) if st.n else float("nan")}
        if len(sc.body_materials) > 1:
            for b in range(len(sc.body_materials)):
                mine = excess[st.p_body == b]
                out[f"max_excess_pore_pressure_body{b}"] = float(mine.max()) if mine.size else float("nan")
        return out

    def series_row(self) -> dict[str, float]:
        """The quantities of one series.csv row at the current state."""
        st, comm = self.state, self.domain.comm
        row = {
            "time": self.time,
            "step": self.step_count,
            "dt": self.dt,
            "kinetic_energy": float(comm.sum([kinetic_energy(st.p_mass, st.p_v)])[0]),
            "front_x": float(comm.max([max_coordinate(st.p_x, 0)])[0]),
        }
        row.update(self.group_fronts())
        if self.strength is not None:
            row["strength_factor"] = self.strength.factor(self.time)
        if self.water is not None:
            row["water_table"] = self.water.height(self.time)
        if self.scene.pore_water is not None:
            row.update(self.pore_pressure_series())
        for stage in dict.fromkeys(self.grid_stages + self.particle_stages):  # a stage of both kinds once
            row.update(stage.series())
        return row
