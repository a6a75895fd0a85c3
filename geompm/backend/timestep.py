"""Adaptive explicit time step.

    dt = min( cfl * h / max_p(c_p + |v_p|),      (CFL, c_p the material wave speed)
              h^2 / (2 d nu_max),                 (viscous limit, nu = mu / rho)
              STRAIN_INCREMENT / max_p,i |L_ii|,  (strain increment per step)
              dt_max )

The strain-increment limit keeps the volume update V <- V det(I + dt L)
(kernels/volume.py) far from inverting a particle.  The CFL bound alone does
not: in a 50 m/s impact on a wall at cfl = 0.8 the stress wave drives
velocities of 75 m/s against arriving material, dt |L| passes 1 and densities
turn negative (docs/numerical-envelope.md, Strain increment).  The stretching rates
L_ii are what change a particle's volume (a shear L_01 alone leaves
det(I + dt L) = 1).  In ordinary flows the limit never binds: the largest
dt |L_ij| measured was 0.005 (column collapse) and 0.008 (dam break), fifty
times below it.  It uses the velocity gradient of the previous step (the
backend's stress loop returns its largest |L_ii|).

The wave speed is the scheme's (schemes/base.Scheme.wave_speed): each material block's law speed, or with
saturated soil the largest of the undrained, water and skeleton wave speeds (schemes/saturated/speeds.py).

This module is the one place the limits are computed (the health check's diagnoses ask here).
Courant, Friedrichs & Lewy (1928); the viscous bound is the explicit diffusion
limit dt <= rho h^2 / (2 d mu).  A fixed ``time.dt`` replaces all of this.
"""

from __future__ import annotations

from geompm.backend.cpu_loops import law_wave_speed
from geompm.kernels.reduce import max_rate, max_speed

#: the largest stretching increment dt |L_ii| a step may take [-] (module docstring)
STRAIN_INCREMENT = 0.25


def wave_speed(scene, state, finite_only: bool = False, materials=None, comm=None) -> float:
    """Largest material wave speed c_p over the particles [m/s], each block through its law's loop
    (backend/cpu_loops.py); ``finite_only`` skips blocks with a non-finite density (a blown-up run's
    diagnosis); ``materials`` replaces the scene's laws block by block (the time-step report's other
    integrations, estimate.py); ``comm``: the ranks whose particles a scheme that combines several extremes
    reduces them over first (Backend.dt_parts)."""
    if materials is None:
        return scene.scheme.wave_speed(scene, state, finite_only, comm)
    return law_speeds(scene, state, finite_only, materials)


def law_speeds(scene, state, finite_only: bool = False, materials=None) -> float:
    """Largest law wave speed c_p over the material blocks [m/s] (arguments as ``wave_speed``)."""
    import numpy as np

    mats = scene.materials if materials is None else materials
    return max((law_wave_speed(mat, state.p_rho[s:e]) for mat, (s, e) in zip(mats, state.blocks)
                if e > s and (not finite_only or np.isfinite(state.p_rho[s:e]).all())), default=0.0)


def wave_limit(scene, state, materials=None) -> float:
    """The CFL step cfl h / max_p(c_p + |v_p|) [s], infinite at rest in a material without waves."""
    speed = wave_speed(scene, state, materials=materials) + (max_speed(state.p_v) if state.n else 0.0)
    speed = max(speed, entering_speed(scene, materials))
    return scene.cfl * scene.grid.h / speed if speed > 0.0 else float("inf")


def viscous_limit(scene, materials=None) -> float:
    """h^2 / (2 d nu_max) [s], infinite without viscosity (``materials`` as in ``wave_speed``)."""
    nu = scene.nu_max if materials is None else max((m.kinematic_viscosity() for m in materials), default=0.0)
    return scene.grid.h ** 2 / (2 * scene.dim * nu) if nu > 0.0 else float("inf")


def stable_dt(scene, state, rate: float | None = None) -> float:
    """The next step [s].  ``rate``: the largest |L_ii| [1/s] if the caller knows it (the backend's
    stress loop finds it as a by-product); otherwise it is taken from the particles."""
    if scene.dt_fixed is not None:
        return scene.dt_fixed
    if rate is None:
        rate = max_rate(state.p_L) if state.n else 0.0
    speed = max(wave_speed(scene, state) + (max_speed(state.p_v) if state.n else 0.0), entering_speed(scene))
    return step_limit(scene, speed, rate)


def entering_speed(scene, materials=None) -> float:
    """Largest c + |v| [m/s] of the particles the scene's sources add (contract/stages.ParticleSource): the law's
    wave speed at its reference density plus the speed they enter with; 0 without sources (``materials`` as in
    ``wave_speed``)."""
    import numpy as np

    from geompm.backend.cpu_loops import law_wave_speed
    from geompm.contract.stages import ParticleSource

    out = 0.0
    for s in scene.stages:
        entry = s.entering() if isinstance(s, ParticleSource) else None
        if entry is not None:
            mat = (scene.materials if materials is None else materials)[entry[0]]
            out = max(out, law_wave_speed(mat, np.array([mat.density])) + entry[1])
    return out


def below_dt_min(scene, dt: float) -> bool:
    """Whether a step ``dt`` [s] is below the case's ``time.dt_min`` (or not a number): the one test of it.
    `geompm validate` warns, the first-step report stays silent and the health check stops the run (exit 3)."""
    return not dt >= scene.dt_min


def step_limit(scene, speed: float, rate: float) -> float:
    """The next step [s] from the largest c_p + |v_p| [m/s] and the largest |L_ii| [1/s]: the limits of
    the module docstring (a backend that reduces on its device calls this with its own reductions)."""
    if scene.dt_fixed is not None:
        return scene.dt_fixed
    wave = scene.cfl * scene.grid.h / speed if speed > 0.0 else float("inf")
    dt = min(wave, viscous_limit(scene))
    if rate > 0.0:
        dt = min(dt, STRAIN_INCREMENT / rate)
    if scene.dt_max is not None:
        dt = min(dt, scene.dt_max)
    return dt
