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
from geompm.kernels.reduce import kinetic_energy, max_coordinate, max_coordinate_by_group
from geompm.engine.triggers import strength_schedule
from geompm.mpm.water_table import water_table_of
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
        """One step of the scene's scheme."""
        self.scheme.step(self, dt)

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

    def load(self) -> None:
        self.water.load(self.backend, self.state, self.time)

    def external_force(self, view, dt: float) -> None:
        self.water.force(self.backend, self.state, view, dt)

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
        for stage in dict.fromkeys(self.grid_stages + self.particle_stages):  # a stage of both kinds once
            row.update(stage.series())
        return row
