"""The time step as a declared scheme: what one explicit step does, in which order, on which fields.

A scheme (PySPH's idea, in geompm's terms) declares

- ``fields``: the particle arrays it needs beyond the core's (mpm/state.py), each a ``Field`` with its shape
  and unit; the set-up makes them (``init_fields``) and every re-ordering, migration and checkpoint carries
  them, since they are the state's arrays like any other;
- its checks of a case (``problems``, ``warnings``), run with the case's other checks before any work;
- ``pore_water``: whether it runs materials with ``pore_water`` (a case gets the ``default`` scheme of its
  kind when ``solver.update`` is left out; naming a scheme of the other kind is refused);
- ``splits_over_ranks``: whether its passes go through the run's decomposition (parallel/), so that a run
  on several MPI ranks may use it;
- ``split_force``: whether its passes read the nodal force apart from the momentum;
- ``passes``: its ordered passes, each the name of a method ``(run, dt)`` of the scheme (the core's passes
  are methods of this base class: ``window``, ``p2g``, ``grid_update``, ``grid_stages``, ``g2p``, ...);
  ``step(run, dt)`` runs them in order through a ``StepContext``, and `geompm validate` prints them.

A scheme is registered as the ``geompm.schemes`` entry point, as a law is; the scheduler runs the scene's
scheme and names none (engine/scheduler.py).  A scheme with passes of its own (saturated soil's two-phase
passes) gives each backend an object of them through ``backend_passes``; a scheme without them gives
``NO_PASSES``.

``StepContext`` holds what a step's passes need of the run, defined here so that the engine imports the
schemes and never the reverse: the backend, the run's decomposition (``domain``), the stages by kind, the
time and the step count, the step's grid window (``view``) and the helpers every explicit step shares
(``window``, ``halo``, ``grid_stages_run``, ``advance``, ``tick``).
The engine's ``Simulation`` is a ``StepContext``.
"""

from __future__ import annotations

import contextlib
from typing import ClassVar, NamedTuple

import numpy as np

from geompm.contract.stages import GridStage, ParticleSource, ParticleStage
from geompm.parallel.whole import WHOLE


class Field(NamedTuple):
    """A particle array a scheme declares: ``shape`` is "" (n,), "d" (n, d) or "dd" (n, d, d)."""

    name: str
    shape: str
    unit: str
    description: str

    def empty(self, n: int, d: int, dtype=np.float64) -> np.ndarray:
        return np.zeros((n,) + {"": (), "d": (d,), "dd": (d, d)}[self.shape], dtype)


class NoPasses:
    """The backend's passes of a scheme that has none beyond the core's kernels."""

    #: particle arrays of the scheme that a device backend keeps on the device (CUDA)
    device_arrays: tuple[str, ...] = ()

    def nbytes(self) -> int:
        return 0

    def wave_speed(self, laws) -> float:
        """The step's wave speed [m/s] from each material block's law speed (a device backend's reduction)."""
        return max(laws, default=0.0)

    def end_reductions(self, backend) -> None:
        """Launch, at the end of a step on a device backend, the reductions the scheme's next ``wave_speed`` reads
        (into the backend's tally, read with the step's other numbers: backend/cuda.py ``settle``)."""


NO_PASSES = NoPasses()


class Scheme:
    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    #: runs materials with ``pore_water`` (docs/pore-water.md); a scheme of the other kind is refused
    pore_water: ClassVar[bool] = False
    #: the scheme a case gets, among those of its kind, when ``solver.update`` is left out
    default: ClassVar[bool] = False
    #: its passes go through the run's decomposition, so it runs on several MPI ranks (docs/parallel.md)
    splits_over_ranks: ClassVar[bool] = True
    #: the stable step of its state is that of the core's step-end reductions (kernels/step_end.py), so that
    #: steps may be held (engine/held_step.py); a scheme that reduces its own terms of the step says False
    holds_step: ClassVar[bool] = True
    #: its passes read the nodal force apart from the momentum (g_force, g_vel_old)
    split_force: ClassVar[bool] = False
    #: the particle arrays it declares beyond the core's (mpm/state.py)
    fields: ClassVar[tuple[Field, ...]] = ()
    #: the step's passes in order: names of methods ``(run, dt)`` of the scheme; the first makes the step's
    #: grid window (``run.view``) that the others read
    passes: ClassVar[tuple[str, ...]] = ()

    # -- the case, before any work (schema/load.py) -------------------------------------------------
    @classmethod
    def problems(cls, case, loaded) -> list[tuple[str, str]]:
        """(JSON path, message) of what this scheme cannot run in ``case``."""
        return []

    @classmethod
    def warnings(cls, case) -> list[tuple[str, str]]:
        """(JSON path, sentence) of settings that run but that the scheme advises against."""
        return []

    @classmethod
    def node_bytes(cls, dim: int, kind: int) -> int:
        """Bytes per window node the scheme's own arrays add to the core's grid, for shape functions of
        ``kind`` (kernels/shape.py): the memory check before any work (schema/load.py) and `geompm validate`'s
        estimate."""
        return 0

    # -- the set-up (setup/assemble.py) ----------------------------------------------------------------
    def __init__(self, case=None, names=()):
        """Resolve what the scheme needs of ``case`` (its materials in ``names`` order) once."""

    def law_params(self, case, name: str, params):
        """A material's parameters as the law runs them (saturated soil: the skeleton's dry density)."""
        return params

    #: how many per-particle arrays ``body_arrays`` gives a body
    body_width: ClassVar[int] = 0

    def body_arrays(self, body, mid: int, pts, h: float, ppc: int):
        """The scheme's ``body_width`` per-particle arrays of one body's seeded particles, or None (zeros)."""
        return None

    def overburden_mass(self, p_mass, p_vol, p_material, arrays):
        """Each particle's mass in the geostatic overburden [kg] (``arrays``: body_arrays concatenated)."""
        return p_mass

    def init_fields(self, state, arrays) -> None:
        """Make the declared fields on the assembled state (``arrays``: body_arrays in the state's order)."""
        for f in self.fields:
            setattr(state, f.name, f.empty(state.n, state.dim, state.dtype))

    def after_stages(self, scene) -> None:
        """Once the scene's stages are set up (saturated soil reads their water boundaries)."""

    # -- the run ------------------------------------------------------------------------------------------
    def backend_passes(self, backend):
        """The scheme's own passes on ``backend`` (NO_PASSES when the core's kernels are all it runs)."""
        return NO_PASSES

    def step(self, run: "StepContext", dt: float) -> None:
        """One step: the declared passes in order."""
        for name in self.passes:
            getattr(self, name)(run, dt)

    def timings(self, run) -> dict[str, float]:
        """Running totals of the scheme's own costs that `geompm bench` reports (seconds and counts since the
        run began); none for a scheme without a solve."""
        return {}

    # -- the core's passes, which schemes list by name ---------------------------------------------------------
    def window(self, run, dt: float) -> None:
        """Particles to their rank, the spatial sort when due, the step's grid window (run.view)."""
        run.view = run.window()

    def load(self, run, dt: float) -> None:
        """What acts on the grid from outside the particles' state (a water table's pore pressure)."""
        run.load()

    def p2g(self, run, dt: float) -> None:
        """Mass, momentum, internal and external force (a pond's buoyancy) onto the grid, the halo summed."""
        be, view = run.backend, run.view
        be.p2g(view, 1.0 if be.split_force else dt)
        run.external_force(view, dt)
        run.halo((view.g_mass, view.g_mom, view.g_force))

    def grid_update(self, run, dt: float) -> None:
        """The nodes' momentum balance with gravity."""
        run.backend.grid_update(run.view, dt)

    def grid_stages(self, run, dt: float) -> None:
        """Every grid stage in phase order (loads, damping, boundaries, obstacles)."""
        run.grid_stages_run(run.view, dt)

    def grid_update_and_stages(self, run, dt: float) -> None:
        """The nodes' momentum balance with gravity, then every grid stage in phase order (a device backend runs
        the update and the first stages' node rules in one launch: a node rule reads and writes its own node)."""
        run.backend.grid_update_and_stages(run.view, dt, run.grid_stages, run.time)

    def g2p(self, run, dt: float) -> None:
        """Velocities, affine matrices, positions, velocity gradients and volumes from the grid."""
        run.backend.g2p(run.view, dt, set_velocity=True, move=True, gradient=True)

    def particle_stages(self, run, dt: float) -> None:
        """Every particle stage in phase order (particle damping, the penetration guard)."""
        run.backend.particle_stages(run.particle_stages, dt, run.time)

    def stress_update(self, run, dt: float) -> None:
        """Each material block's law on its particles, then the clock."""
        run.advance(run.view, dt)

    def g2p_stages_and_stress_update(self, run, dt: float) -> None:
        """``g2p``, ``particle_stages`` and ``stress_update`` (a device backend runs the three on each particle in
        one launch per material block: G2P reads the grid alone, a particle rule and a law their own particle;
        the strength trigger, a function of the time alone, sets the laws' parameters first)."""
        self._particle_step(run, dt, True)

    def _particle_step(self, run, dt: float, set_velocity: bool) -> None:
        run.strength_changes()
        run.backend.g2p_stages_and_stress(run.view, dt, run.particle_stages, run.time, set_velocity=set_velocity)
        self.after_particles(run, dt)
        run.tick(run.view, dt)

    def after_particles(self, run, dt: float) -> None:
        """A scheme's own particle pass after the laws and before the clock, on what G2P left (none here)."""

    def wave_speed(self, scene, state, finite_only: bool = False, comm=None) -> float:
        """Largest wave speed [m/s] that bounds the step: each material block's law speed (``finite_only``:
        the blocks whose densities are finite, for a blown-up run's diagnosis).  A law's speed is monotone in
        the density, so this rank's largest is exact and the ranks' maxima need no ``comm`` here."""
        from geompm.backend.timestep import law_speeds

        return law_speeds(scene, state, finite_only)

    def series(self, run: "StepContext") -> dict[str, float]:
        """The scheme's columns of a series.csv row."""
        return {}

    def point_data(self, run: "StepContext", st) -> dict:
        """Particle fields the VTU writer adds (``stress`` replaced where the scheme knows a total stress)."""
        return {}

    def basal_water(self, st):
        """(pore pressure [Pa], mass of solids and water [kg], |g| [m/s2]) of each particle for the hazard
        maps' basal pore-pressure ratio, or None where the scheme carries no pore water."""
        return None

    def report(self, scene) -> list[str]:
        """Lines `geompm validate` prints about the scheme's step."""
        return []

    def drained(self):
        """A context in which the scheme holds its pore pressure, if it carries one, at its present state (the
        gravity-loading stage: engine/gravity_loading.py); nothing for a dry scheme."""
        return contextlib.nullcontext()

    def at_rest(self, state) -> None:
        """Zero what the scheme carries of the particles' motion beyond p_v and p_C (after gravity loading)."""


class StepContext:
    """What a scheme's passes need of the run (module docstring); the engine's Simulation fills it."""

    def __init__(self, scene, backend, domain=WHOLE):
        self.scene = scene
        self.backend = backend
        #: how the run is shared between processes (parallel/whole.py: one; parallel/slabs.py: MPI ranks)
        self.domain = domain
        stages = sorted(scene.stages, key=lambda s: s.phase)
        for stage in stages:
            stage.comm = domain.comm
        self.grid_stages = [s for s in stages if isinstance(s, GridStage)]
        self.particle_stages = [s for s in stages if isinstance(s, ParticleStage)]
        self.sources = [s for s in stages if isinstance(s, ParticleSource)]
        self.time = 0.0
        self.step_count = 0
        self.dt = 0.0
        self.view = None

    @property
    def state(self):
        """The particle arrays on the host (backend.host_state())."""
        return self.backend.host_state()

    def sort_if_due(self) -> None:
        every = self.scene.sort_interval
        if every and self.step_count % every == 0:
            self.backend.sort_particles()

    def load(self) -> None:
        """What acts on the grid from outside the particles' state before P2G (a water table's pore pressure:
        engine/scheduler.py)."""

    def external_force(self, view, dt: float) -> None:
        """Nodal forces from outside the particles' stress after P2G (a pond's buoyancy: engine/scheduler.py)."""

    def supply(self) -> None:
        """The particles the sources add before the step (an inflow hydrograph: engine/scheduler.py)."""

    def window(self):
        """The sources' new particles, particles to their rank, the sort when due, and this rank's grid window."""
        self.supply()
        self.domain.before_step(self)
        self.sort_if_due()
        return self.domain.window(self.backend)

    def grid_stages_run(self, view, dt: float, remap: bool = False, phases=None) -> None:
        """Each grid stage in phase order (``phases``: (lowest, highest) excluded, or None for all)."""
        lo, hi = phases if phases is not None else (-np.inf, np.inf)
        self.backend.grid_stages([s for s in self.grid_stages if lo <= s.phase < hi], view, dt, self.time, remap)

    def halo(self, arrays) -> None:
        """Add the neighbouring ranks' partial sums of window arrays of this step's view (nothing in one
        process)."""
        self.domain.sum_halo(self.view, arrays)

    def strength_changes(self) -> None:
        """A strength trigger's factor on the laws' parameters before the stress update (engine/triggers.py)."""

    def advance(self, view, dt: float) -> None:
        """The stress update of every material block, then the clock."""
        self.strength_changes()
        self.backend.update_stress(dt)
        self.tick(view, dt)

    def tick(self, view, dt: float) -> None:
        """The clock, after the step's stress update."""
        self.view = view
        self.dt = dt
        self.time += dt
        self.step_count += 1
