"""The simulation: the scene's scheme stepped on its backend, over the run's decomposition.

The step is the scene's scheme (schemes/: ``usl``, ``musl``, ``saturated``, or a plugin's), resolved from the
case before the run (schema/scheme.py) and run here without being named: ``step(dt)`` is the scheme's
``step(self, dt)``.  A ``Simulation`` is the ``StepContext`` the scheme's passes use (schemes/base.py): the
backend, the run's decomposition, the stages by kind and the helpers every explicit step shares.

Only the stages the case asks for are in the lists; a case without damping has no damping pass.  Stages
are ordered by their declared ``phase`` (contract/stages.py), never by plugin name; each gives per-node or
per-particle functions that the backend runs (``grid_stage``, ``particle_stages``).
"""

from __future__ import annotations

import numpy as np

from geompm.backend import make_backend
from geompm.backend.timestep import entering_speed, step_limit
from geompm.kernels.reduce import kinetic_energy, max_coordinate, max_coordinate_by_group
from geompm.engine.triggers import strength_schedule
from geompm.mpm.water_table import water_table_of
from geompm.parallel.migrate import merge
from geompm.parallel.whole import WHOLE
from geompm.schemes.base import StepContext


class Simulation(StepContext):
    def __init__(self, scene, nchunks: int | None = None, domain=WHOLE):
        super().__init__(scene, None, domain)
        self.scheme = scene.scheme
        # the nodal force and pre-update velocity are kept apart only when something reads them
        split_force = scene.transfer == "flip" or any(s.needs_split_force for s in self.grid_stages) \
            or self.scheme.split_force
        self.backend = make_backend(scene, split_force, nchunks)
        self.backend.domain = domain
        #: the strength trigger's F(t) (engine/triggers.py), a schedule that changes nothing without one
        self.strength = strength_schedule(scene.strength_trigger)
        #: the water table whose pore pressure the grid sees (mpm/water_table.py), NO_WATER_TABLE without one
        self.water = water_table_of(scene)

    def step(self, dt: float) -> None:
        """One step of the scene's scheme, the clock only while a scene with sources holds no particle; then the
        sources' particles due by the step's end (what is written at that time holds them).  The backend settles
        the step's reductions before anything reads them (Backend.settle)."""
        if self.sources:
            self.supply()
            if self.count() == 0:
                self.dt, self.time, self.step_count = dt, self.time + dt, self.step_count + 1
            else:
                self.scheme.step(self, dt)
                self.backend.settle()
            self.supply()
            return
        self.scheme.step(self, dt)
        self.backend.settle()

    @property
    def buffers(self):
        return self.backend.buffers

    def stable_dt(self) -> float:
        """The next step [s]: the sources' particles due now are added first (their speeds count); while the run
        holds no particle, the step of the particles to come (c + v of ``entering_speed``)."""
        self.supply()
        dt = self.domain.stable_dt(self.backend)
        if self.sources and self.count() == 0:  # the step of the particles to come (they enter less than a cell late)
            dt = min(dt, step_limit(self.scene, entering_speed(self.scene), 0.0))
        return dt

    def distribute(self) -> None:
        """Keep this rank's particles of the whole state every rank holds (before the first step, after a
        resume); nothing in one process."""
        self.domain.distribute(self.state)

    def count(self) -> int:
        """Particles in the run, on every rank."""
        return int(round(float(self.domain.comm.sum([self.state.n])[0])))

    def load(self) -> None:
        self.water.load(self.backend, self.time)

    def supply(self) -> None:
        """Each source's particles due by now, merged into the root rank's state (parallel/migrate.py; the
        migration that follows sends them to their ranks); every rank asks every source, so their counts agree."""
        for source in self.sources:
            # the source reads the state's array names, dtypes and shapes only: the backend's host object, whose
            # values a device backend has not brought back (``self.state`` would copy every array, every step)
            packet = source.supply(self.backend.state, self.time)
            if packet is not None and self.domain.comm.is_root:
                merge(self.state, np.ones(self.state.n, bool), [packet])
                self.backend.particles_added()

    def pending(self) -> bool:
        """Whether a source has particles still to add."""
        return any(s.pending(self.time) for s in self.sources)

    def external_force(self, view, dt: float) -> None:
        self.water.force(self.backend, view, dt)

    def strength_changes(self) -> None:
        self.strength.apply(self.scene, self.backend, self.time)

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
        row.update(self.strength.series(self.time))
        row.update(self.water.series(self.time))
        row.update(self.scheme.series(self))
        for stage in dict.fromkeys(self.grid_stages + self.particle_stages + self.sources):  # each stage once
            row.update(stage.series())
        return row
