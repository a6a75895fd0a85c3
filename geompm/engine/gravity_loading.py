"""The gravity-loading stage: a case brought to equilibrium under its own weight before its event.

``initial_stress: geostatic`` is exact for level ground only; a slope, a body on terrain or against a wall
starts out of balance and its first steps are a dynamic response that is not the event (a two-phase slope's
pore pressure rose by +50 / -18 kPa in 0.5 s at rest).  Before the event the stage (``gravity_loading`` in the
case) steps the scene

- at t = 0 held: triggers, schedules and moving solids at their initial state (the clock is set back after
  each step);
- drained: a saturated scheme holds its pore pressure at its initial (hydrostatic or table) state
  (Scheme.drained), so the skeleton takes the effective stress that balances it;
- under Cundall's local damping (damping/local.py, ``alpha``) beside the case's own damping;

until the unbalanced-force ratio, the particles' mass-weighted RMS acceleration over one step divided by |g|,

    r = sqrt(sum m_p |v_p^(n+1) - v_p^n|^2 / sum m_p) / (dt |g|),

falls below ``tolerance`` (checked every step; the stage takes at least two steps), then resets the
displacements (x0 = x), the velocities and the affine matrices (and the scheme's, Scheme.at_rest) and the
stages' recorded state (peak forces), keeping the stresses, the plastic state and the positions (as PLAXIS's
and Anura3D's K0 / gravity-loading phases with "reset displacements"). A case still out of balance after
``max_time`` stops with exit 3 before the event.  This is a numerical stage, not physics: the path to
equilibrium (damped, drained) is not a loading history.
"""

from __future__ import annotations

import math
import time as wallclock

import numpy as np

from geompm.damping.local import LocalDamping
from geompm.errors import SimulationError
from geompm.kernels.reduce import velocity_change

#: the fewest steps of the stage (the first step's ratio compares with the start's zero velocities)
MIN_STEPS = 2


def unbalanced_ratio(p_mass, v_new, v_old, dt: float, g: float) -> float:
    """r of the module docstring; v_old takes v_new's values (kernels/reduce.velocity_change)."""
    num, den = velocity_change(p_mass, v_new, v_old)
    return math.sqrt(num / den) / (dt * g) if den > 0.0 else 0.0


def gravity_loading(scene, spec, simulation) -> dict:
    """Bring ``scene`` to equilibrium as the module docstring says; ``simulation(scene)`` makes the stepping
    context (engine/scheduler.Simulation).  Returns its report: steps, simulated time [s], the final ratio,
    the largest displacement [m] and the wall time [s]."""
    g = float(np.linalg.norm(scene.gravity))
    if g == 0.0:
        return {"steps": 0, "time": 0.0, "ratio": 0.0, "max_displacement": 0.0, "wall_seconds": 0.0}
    damping = LocalDamping(LocalDamping.Params(alpha=spec.alpha), "gravity_loading", "gravity_loading")
    damping.setup(scene)
    recorded = [s.state_dict() for s in scene.stages]
    own = scene.damping
    scene.damping = [*own, damping]
    t0 = wallclock.perf_counter()
    loading_time, steps, ratio = 0.0, 0, math.inf
    try:
        with scene.scheme.drained():
            sim = simulation(scene)
            st = sim.state
            v_old = st.p_v.copy()
            while steps < MIN_STEPS or ratio > spec.tolerance:
                if loading_time >= spec.max_time:
                    raise SimulationError(
                        f"gravity_loading: the case is still out of balance after {spec.max_time:g} s of loading "
                        f"({steps} steps; unbalanced-force ratio {ratio:.3g} against the tolerance "
                        f"{spec.tolerance:g}): raise gravity_loading.max_time, or check that the case is supported "
                        "(a slope that cannot stand under its own weight fails here)")
                dt = sim.stable_dt()
                sim.step(dt)
                sim.time = 0.0  # held at t = 0: triggers and moving solids at their initial state
                steps += 1
                loading_time += dt
                ratio = unbalanced_ratio(st.p_mass, st.p_v, v_old, dt, g)
    finally:
        scene.damping = own
        for stage, saved in zip(scene.stages, recorded):
            stage.load_state(saved)
    st = sim.state
    moved = float(np.sqrt(np.max(np.sum((st.p_x - st.p_x0) ** 2, axis=1)))) if st.n else 0.0
    st.p_x0[:] = st.p_x
    st.p_v[:] = 0.0
    st.p_C[:] = 0.0
    scene.scheme.at_rest(st)
    return {"steps": steps, "time": loading_time, "ratio": ratio, "max_displacement": moved,
            "wall_seconds": wallclock.perf_counter() - t0}
