"""The backend contract: what the scheduler asks of the machine a step runs on.

One step in backend calls (the ``usl`` scheme's, schemes/usl.py; other schemes order the same calls
differently and add their own passes, ``scheme_passes``):

    sort_particles()                 every solver.sort_interval steps
    view = window()                  the active grid window (mpm/grid.py)
    p2g(view, f_scale)               mass, momentum, internal force
    grid_update_and_stages(view, dt, stages, time)   momentum balance + gravity, then each grid stage's
                                     node rule or node merge in order (grid_update, grid_stages)
    g2p_stages_and_stress(view, dt, stages, time, set_velocity)   the three below, one after the other
                                     (a device backend runs them per particle in one launch per block)
    g2p(view, dt, set_velocity, move, gradient)
    particle_stages(stages, dt, time)          every particle stage's particle rule, in order
    update_stress(dt)                each material block through its law's loop; sets max_rate,
                                     the largest |L_ii| of the step, for the strain-increment limit
(the next step's CFL limit runs each law's wave-speed loop: backend/timestep.py)

A held batch (engine/held_step.py) wraps steps in ``hold(box, cells)``, ``gate(i)`` before each step after the
first, and ``release(launched)``, which says how many were taken.

The transfer scheme (PIC/APIC/FLIP/MLS) and the stencil support are fixed when
the backend is made and reach the kernels as compile-time tags
(kernels/stencil.py); the update order (USL/MUSL) is the scheduler's choice of
scheme's (schemes/), fixed before the run.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from geompm.parallel.whole import WHOLE


def mass_floor(scene) -> float:
    """The grid's mass below which a node is empty [kg]: 1e-9 of the smallest particle mass of the scene, counting
    the particles its sources add (contract/stages.ParticleSource), so a scene that starts empty has one too."""
    from geompm.contract.stages import ParticleSource

    st = scene.state
    masses = [float(st.p_mass.min())] if st.n else []
    masses += [s.particle_mass() for s in scene.stages if isinstance(s, ParticleSource) and s.particle_mass() > 0]
    return 1e-9 * min(masses) if masses else 0.0


class Backend:
    name: ClassVar[str] = ""
    #: the host ParticleState object (its values are current only through ``host_state()`` on a device backend;
    #: its array names, dtypes, shapes and blocks always are)
    state = None
    #: the run's decomposition over processes (parallel/whole.py, parallel/slabs.py): the backend asks it
    #: which nodes a stage's reduction counts and stacks every rank's accumulator rows through it
    domain = WHOLE
    #: largest |L_ii| [1/s] found by the last update_stress; None when unknown (before the first step,
    #: after a restore): the time step then takes it from the particles
    max_rate: float | None = None

    def particles_added(self) -> None:
        """A source added particles to the host state (a device backend would take them over here): what was
        measured on the old particles no longer applies."""
        self.max_rate = None

    def stable_dt(self) -> float:
        """The next step [s] (backend/timestep.py) from the particles' speeds, densities and the last
        stress update's largest |L_ii|."""
        if self.scene.dt_fixed is not None:
            return self.scene.dt_fixed
        c, v, rate = self.dt_parts()
        return self.step_from(c + v, rate)

    def step_from(self, speed: float, rate: float) -> float:
        """The step [s] from the largest c_p + |v_p| [m/s] and |L_ii| [1/s] (backend/timestep.step_limit)."""
        from geompm.backend.timestep import step_limit

        return step_limit(self.scene, speed, rate)

    def dt_parts(self) -> tuple[float, float, float]:
        """(largest wave speed c_p [m/s], largest |v_p| [m/s], largest |L_ii| [1/s]) over this process's
        particles: the step's inputs, which ranks reduce before the step is taken (parallel/slabs.py); a
        device backend overrides it with its own reductions."""
        from geompm.backend.timestep import wave_speed
        from geompm.kernels.reduce import max_rate, max_speed

        st = self.host_state()
        rate = self.max_rate if self.max_rate is not None else (max_rate(st.p_L) if st.n else 0.0)
        return wave_speed(self.scene, st, comm=self.domain.comm), (max_speed(st.p_v) if st.n else 0.0), rate

    def host_state(self):
        """The particle arrays as host (numpy) arrays: read by writers, checkpoints and a failed check's message."""
        raise NotImplementedError

    def settle(self) -> None:
        """The end of a step (engine/scheduler.Simulation.step): a backend that defers its reductions hands them
        to the host here (every stage's ``*_reduced``, the last stress update's largest |L_ii|), so that what
        reads the stages and the time step's inputs after the step sees this step's; nothing on the CPU."""

    def health_sums(self, gravity) -> tuple[float, float, float]:
        """(particles with a non-finite position, velocity or stress, kinetic energy [J], energy gravity
        released [J]) over this process's particles (kernels/health.health_sums; a device backend reduces them
        on its device)."""
        from geompm.kernels.health import health_sums

        st = self.host_state()
        return health_sums(st.p_x, st.p_x0, st.p_v, st.p_stress, st.p_mass, gravity)

    def particles_outside(self, lo, hi) -> int:
        """How many of this process's particles lie outside the box [lo, hi] [m] ((d,) arrays)."""
        from geompm.kernels.health import outside_grid

        return int(outside_grid(self.host_state().p_x, lo, hi).sum())

    def window(self):
        """The grid window over every particle's stencil (mpm/grid.py), or during a held batch over the cells
        it holds (``hold``); SimulationError naming a particle that left the grid."""
        from geompm.mpm.grid import window_extent

        cells = self._held[1] if self._held is not None else self.particle_cells()
        return self.window_at(*window_extent(self.scene.grid, cells, lambda: self.host_state().p_x))

    # -- the held step (engine/held_step.py) ---------------------------------------------------------------
    #: during a held batch: (its box, the cells its window covers); None otherwise
    _held = None

    def end_rows(self) -> np.ndarray:
        """The step-end rows of this process's particles, flat (material blocks * END_ROW: kernels/step_end.py);
        a device backend reads its own reduction."""
        from geompm.kernels.step_end import end_rows

        return end_rows(self.host_state(), self.scene.gravity)

    def hold(self, box, cells) -> None:
        """Begin a held batch: its steps are checked against ``box`` (held_step.limits) and its grid window
        covers ``cells`` (2, d)."""
        self._held = (box, cells)

    def gate(self, i: int) -> bool:
        """Before the batch's step ``i`` (from 1): whether it may be taken (held_step.fits on this step's start);
        a device backend launches the test and answers True, its later kernels returning at once if it failed."""
        from geompm.kernels.held_box import fits
        from geompm.kernels.reduce import max_rate

        rate = self.max_rate if self.max_rate is not None else (max_rate(self.host_state().p_L) if self.state.n
                                                                 else 0.0)
        return bool(fits(self.end_rows(), rate, self._held[0]))

    def release(self, launched: int) -> int:
        """End the held batch of which ``launched`` steps were asked for: how many were taken (a device backend
        hands the stages the reductions of those, in order)."""
        self._held = None
        return launched

    def joined(self, rows, slots: int):
        """A pass's accumulator rows with every rank's stacked (comm.rows); a stage that declares no
        reduction (``slots`` 0) gets its own rows back and no rank waits for another."""
        return self.domain.comm.rows(rows) if slots else rows

    def particle_cells(self):
        """Per axis the lowest and highest cell of the particles, (2, d) int64 (kernels/reduce.cell_bounds),
        or None without particles."""
        raise NotImplementedError

    def window_at(self, lo, nloc):
        """The window of ``nloc`` nodes per axis from global node ``lo`` (a rank's, parallel/slabs.py)."""
        raise NotImplementedError

    def p2g(self, view, f_scale: float) -> None:
        raise NotImplementedError

    def grid_update(self, view, dt: float) -> None:
        raise NotImplementedError

    def remap_velocity(self, view) -> None:
        """Grid velocity from the re-mapped momentum (MUSL)."""
        raise NotImplementedError

    def g2p(self, view, dt: float, *, set_velocity: bool, move: bool, gradient: bool) -> None:
        raise NotImplementedError

    def grid_stage(self, stage, view, dt: float, time: float, remap: bool) -> None:
        """Run a GridStage's node rule (or node merge) over the window and hand it the reduction."""
        raise NotImplementedError

    def grid_update_and_stages(self, view, dt: float, stages, time: float) -> None:
        """``grid_update`` and then ``grid_stages`` (a device backend joins the update to the first stages' node
        rules in one launch)."""
        self.grid_update(view, dt)
        self.grid_stages(stages, view, dt, time, False)

    def grid_stages(self, stages, view, dt: float, time: float, remap: bool) -> None:
        """Every grid stage of ``stages`` in order (``grid_stage`` each; a device backend launches consecutive
        stages of one class together)."""
        for stage in stages:
            self.grid_stage(stage, view, dt, time, remap)

    def particle_stage(self, stage, dt: float, time: float) -> None:
        """Run a ParticleStage's particle rule over its blocks and hand it the reduction."""
        raise NotImplementedError

    def particle_stages(self, stages, dt: float, time: float) -> None:
        """Every ParticleStage's rule, in the order given (a backend may skip a stage that declares it
        cannot reach the particles: ``ParticleStage.particle_reach``)."""
        for stage in stages:
            self.particle_stage(stage, dt, time)

    def update_stress(self, dt: float) -> None:
        raise NotImplementedError

    def g2p_stages_and_stress(self, view, dt: float, stages, time: float, *, set_velocity: bool) -> None:
        """``g2p`` (positions, gradients and volumes; velocities where ``set_velocity``), ``particle_stages`` and
        ``update_stress`` (a device backend runs the three on each particle in one launch per material block: G2P
        reads the grid alone, and a particle rule and a law read and write their own particle)."""
        self.g2p(view, dt, set_velocity=set_velocity, move=True, gradient=True)
        self.particle_stages(stages, dt, time)
        self.update_stress(dt)

    #: the scene's scheme's own passes on this backend (schemes/base.Scheme.backend_passes; NO_PASSES when
    #: the scheme runs the core's kernels only): the backend declares them here so a scheme finds them
    scheme_passes = None

    def set_table_pressure(self, p_table_pressure) -> None:
        """The pore pressure [Pa] of each particle under a water table (mpm/water_table.py) that the next P2G
        takes out of the effective stress: the grid sees sigma' - p I.  The CPU backend implements it; the
        case check refuses a water table elsewhere (schema/triggers.py)."""
        raise NotImplementedError("a water table runs on the CPU backend only")

    def each(self, fn, n: int, *args) -> None:
        """Run a scheme's per-item function ``fn(i, *args)`` for i in 0..n-1, in parallel: the backend's
        generated loop (backend/item_loops.py on the CPU, cuda_loops.each_kernel on a GPU)."""
        self.each_in_turn(n, ((fn, args),))

    def each_in_turn(self, n: int, calls, moves: bool = True) -> None:
        """Run the per-item functions of ``calls`` ((fn, args) pairs) in turn on each item i in 0..n-1, in one
        parallel loop (one launch on a GPU): ``fn(i, *args)`` for each pair in order.  The caller declares the
        run pointwise: of what one function writes, a later one reads only item i's own entries, and no
        function writes what an earlier one reads at other items (then the loop's order over the items does
        not matter, and the run equals the functions' loops one after the other).  ``moves`` False: the run
        writes none of the particle arrays the step-end reductions read (positions, velocities, masses,
        densities, stresses), so a device backend keeps those it has (the porosity)."""
        raise NotImplementedError

    def material_parameters_changed(self) -> None:
        """The laws' packed parameters (``scene.materials[k].prm``) were changed in place (a strength
        trigger, engine/triggers.py): a backend that keeps its own copy takes them again."""

    def sort_particles(self) -> None:
        raise NotImplementedError

    def nbytes(self) -> int:
        raise NotImplementedError


def relaxed_materials(scene) -> list[bool]:
    """Per material: whether ``solver.viscoplastic_time`` regularises its law (the law declares an elastic
    predictor: Material.elastic_predictor; kernels/viscoplastic.py)."""
    tau = getattr(scene, "viscoplastic_time", None)
    return [bool(tau) and type(m).elastic_predictor is not None for m in scene.materials]
