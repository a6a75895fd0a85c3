"""Adaptive explicit time step.

    dt = min( cfl * h / max_p(c_p + |v_p|),      (CFL, c_p the material wave speed)
              h^2 / (2 d nu_max),                 (viscous limit, nu = mu / rho)
              dt_max )

Courant, Friedrichs & Lewy (1928); the viscous bound is the explicit diffusion
limit dt <= rho h^2 / (2 d mu).  A fixed ``time.dt`` replaces all of this.
"""

from __future__ import annotations

from ..kernels.reduce import max_speed


def wave_speed(scene, state) -> float:
    """Largest material wave speed c_p over the particles [m/s]."""
    return max((mat.wave_speed(state.p_rho[s:e]) for mat, (s, e) in zip(scene.materials, state.blocks) if e > s),
               default=0.0)


def viscous_limit(scene) -> float:
    """h^2 / (2 d nu_max) [s], infinite without viscosity."""
    return scene.grid.h ** 2 / (2 * scene.dim * scene.nu_max) if scene.nu_max > 0.0 else float("inf")


def stable_dt(scene, state) -> float:
    if scene.dt_fixed is not None:
        return scene.dt_fixed
    speed = wave_speed(scene, state) + (max_speed(state.p_v) if state.n else 0.0)
    dt = scene.cfl * scene.grid.h / speed if speed > 0.0 else float("inf")
    dt = min(dt, viscous_limit(scene))
    if scene.dt_max is not None:
        dt = min(dt, scene.dt_max)
    return dt
