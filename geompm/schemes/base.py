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
- ``step(run, dt)``: its ordered passes, the backend's kernels and the stages, through a ``StepContext``.

A scheme is registered as the ``geompm.schemes`` entry point, as a law is; the scheduler runs the scene's
scheme and names none (engine/scheduler.py).  A scheme with passes of its own (saturated soil's two-phase
passes) gives each backend an object of them through ``backend_passes``; a scheme without them gives
``NO_PASSES``.

``StepContext`` holds what a step's passes need of the run, defined here so that the engine imports the
schemes and never the reverse: the backend, the run's decomposition (``domain``), the stages by kind, the
time and the step count, and the helpers every explicit step shares (``begin``, ``end``, ``advance``).
The engine's ``Simulation`` is a ``StepContext``.
"""

from __future__ import annotations

from typing import ClassVar, NamedTuple

import numpy as np

from geompm.contract.stages import GridStage, ParticleStage
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
    #: its passes read the nodal force apart from the momentum (g_force, g_vel_old)
    split_force: ClassVar[bool] = False
    #: the particle arrays it declares beyond the core's (mpm/state.py)
    fields: ClassVar[tuple[Field, ...]] = ()

    # -- the case, before any work (schema/load.py) -------------------------------------------------
    @classmethod
    def problems(cls, case, loaded) -> list[tuple[str, str]]:
        """(JSON path, message) of what this scheme cannot run in ``case``."""
        return []

    @classmethod
    def warnings(cls, case) -> list[tuple[str, str]]:
        """(JSON path, sentence) of settings that run but that the scheme advises against."""
        return []

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
        raise NotImplementedError

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

    def window(self):
        """Particles to their rank, the sort when due, and this rank's grid window."""
        self.domain.before_step(self)
        self.sort_if_due()
        return self.domain.window(self.backend)

    def grid_stages_run(self, view, dt: float, remap: bool = False, phases=None) -> None:
        """Each grid stage in phase order (``phases``: (lowest, highest) excluded, or None for all)."""
        lo, hi = phases if phases is not None else (-np.inf, np.inf)
        for stage in self.grid_stages:
            if lo <= stage.phase < hi:
                self.backend.grid_stage(stage, view, dt, self.time, remap)

    def begin(self, dt: float):
        """The window, P2G with the halo summed, the grid update and the grid stages (USL and MUSL)."""
        view = self.window()
        be = self.backend
        self.load()
        be.p2g(view, 1.0 if be.split_force else dt)
        self.domain.sum_halo(view, (view.g_mass, view.g_mom, view.g_force))
        be.grid_update(view, dt)
        self.grid_stages_run(view, dt)
        return view

    def end(self, view, dt: float) -> None:
        """The particle stages and the stress update, then the clock."""
        self.backend.particle_stages(self.particle_stages, dt, self.time)
        self.advance(view, dt)

    def strength_changes(self) -> None:
        """A strength trigger's factor on the laws' parameters before the stress update (engine/triggers.py)."""

    def advance(self, view, dt: float) -> None:
        """The stress update of every material block, then the clock."""
        self.strength_changes()
        self.backend.update_stress(dt)
        self.view = view
        self.dt = dt
        self.time += dt
        self.step_count += 1
