"""Checks of a case's first time step, made after the Scene is assembled and before the loop: they run the
laws' wave-speed loops (so they compile them), which assembling a Scene does not.

- ``check_output_intervals``: an output interval shorter than the first step is refused (CaseError at
  ``outputs.<k>.interval``), saying which limit sets the step;
- ``fixed_step_problem``: a fixed ``time.dt`` above the stable step (validate refuses, run warns);
- ``step_explanation``: which limit sets the first step, and what sets that limit.

``geompm validate``, ``geompm run`` and a study's check of its variants call them (cli/main.py,
study/command.py).
"""

from __future__ import annotations

from geompm.backend.cpu_loops import law_wave_speed
from geompm.backend.timestep import below_dt_min, stable_dt, viscous_limit, wave_limit
from geompm.engine.estimate import step_report
from geompm.errors import CaseError


def check_output_intervals(scene, outputs) -> None:
    """An output interval shorter than the first time step would force every step to be shortened; the
    refusal first says which limit sets that step and why it is so large (step_explanation)."""
    dt = stable_dt(scene, scene.state)
    short = [k for k, o in enumerate(outputs) if 0.0 < o.interval < dt]
    if not short:
        return
    why = step_explanation(scene)
    raise CaseError([(f"outputs.{k}.interval", f"{why}; the interval {outputs[k].interval:g} s is shorter than "
                                               f"the time step ({dt:.3g} s): if that step is right, use an "
                                               f"interval of at least {dt:.3g} s, or 0 to write every step")
                     for k in short])


def step_explanation(scene) -> str:
    """Which limit sets the first time step and what sets that limit: the fastest material's wave speed
    (with its stiffness and density) or the most viscous material's viscosity."""
    if scene.dt_fixed is not None:
        return f"the time step is fixed by time.dt = {scene.dt_fixed:g} s"
    rep = step_report(scene)
    text = rep.governing()
    if rep.viscous_governs:
        return text
    st = scene.state
    speeds = [(law_wave_speed(m, st.p_rho[s:e]), name, m) for m, name, (s, e)
              in zip(scene.materials, scene.material_names, st.blocks) if e > s]
    if not speeds:
        return text
    c, name, mat = max(speeds, key=lambda t: t[0])
    if not c > 0.0:  # no wave at all (a modulus that underflows to a zero speed): nothing crosses a cell
        return text
    stiff = getattr(mat.params, "youngs_modulus", None)
    detail = (f"E = {stiff:g} Pa, " if stiff is not None else "") + f"rho = {mat.density:g} kg/m3"
    return (f"{text}: the fastest wave is c = {c:.3g} m/s in material '{name}' ({detail}), so h = "
            f"{scene.grid.h:g} m is crossed in {scene.grid.h / c:.3g} s")


def fixed_step_problem(scene) -> tuple[str, str] | None:
    """A fixed time.dt above the stable step of the first step (wave and viscous limits): (path, message)."""
    if scene.dt_fixed is None:
        return None
    stable = min(wave_limit(scene, scene.state), viscous_limit(scene))
    if scene.dt_fixed <= stable:
        return None
    limit = "viscous limit rho h^2 / (2 d mu)" if viscous_limit(scene) < wave_limit(scene, scene.state) \
        else f"wave limit cfl h / (c + |v|) at cfl = {scene.cfl:g}"
    return ("time.dt", f"{scene.dt_fixed:g} s is {scene.dt_fixed / stable:.3g}x the stable step {stable:.3g} s "
                       f"(the {limit}): the run would blow up within a few steps; use time.dt <= {stable:.3g} s, "
                       "or remove it and let the step adapt")


def first_step_estimate(scene) -> tuple[float, int, float]:
    """(bytes of memory, active grid nodes, first time step [s]) of an assembled scene."""
    from geompm.mpm.memory import grid_bytes, particle_bytes, window_nodes

    from geompm.contract.stages import ParticleSource

    st = scene.state
    added = sum(s.particles_total() for s in scene.stages if isinstance(s, ParticleSource))
    if added or not st.n:  # what the sources add may go anywhere in the grid
        nodes = window_nodes(scene.grid.origin, scene.grid.upper, scene.grid.h)
    else:
        nodes = window_nodes(st.p_x.min(axis=0), st.p_x.max(axis=0), scene.grid.h)
    extra = nodes * type(scene.scheme).node_bytes(scene.dim, scene.grid.kind)
    particles = st.nbytes() + added * particle_bytes(scene.dim, max((len(m.state_vars) for m in scene.materials),
                                                                    default=0))
    return particles + grid_bytes(nodes, scene.dim) + extra, nodes, stable_dt(scene, st)


def stage_warnings(scene, emit, loaded=None) -> None:
    """Emit the case's plausibility warnings and every stage's and law's own warnings, one line each."""
    for path, text in (loaded.warnings if loaded is not None else []):
        emit(f"warning: {path}: {text}")
    for stage in scene.stages:
        for text in stage.warnings():
            emit("warning: " + text)
    for name, mat in zip(scene.material_names, scene.materials):
        for text in mat.warnings():
            emit(f"warning: materials.{name}: {text}")


def viscous_warning(loaded, scene, emit) -> None:
    """Say so when viscosity sets the time step: the step, the steps, a measured run time, the remedies."""
    from geompm.engine.estimate import viscous_report
    from geompm.setup.assemble import assemble

    if below_dt_min(scene, stable_dt(scene, scene.state)):
        return  # the dt_min check speaks for this case (validate warns, run stops with exit 3)
    rep = viscous_report(scene, lambda: assemble(loaded))
    if rep is not None:
        emit("warning: " + rep.message(scene.end_time))
