"""Cundall's local non-viscous damping on grid nodes, for quasi-static stages.

Each node's unbalanced force f_i = f_int,i + m_i g is reduced, component by
component, by a force opposite to the node's velocity and proportional to
|f_i|:

    f_damped = f_i - alpha |f_i| sign(v_i)

Cundall (1987), "Distinct element models of rock and soil structure", in
Analytical and Computational Methods in Engineering Rock Mechanics, ch. 4;
the damping of FLAC and PFC.  alpha in [0, 1) (0.8 typical for quasi-static
equilibrium).  It removes kinetic energy without a viscous time scale, so it
reaches equilibrium fast but does not model a physical dissipation: use it
for geostatic initialisation, not for a dynamic run.  ``until`` [s] switches
it off after an initial stage.
"""

from __future__ import annotations

from numba import njit, prange
from pydantic import Field

from ..plugin import Params
from ..stages import DAMPING, GridStage


class LocalParams(Params):
    alpha: float = Field(ge=0.0, lt=1.0, description="Damping coefficient alpha [-], 0.8 typical")
    until: float | None = Field(None, gt=0, description="Simulated time [s] after which damping stops")


@njit(parallel=True, cache=True)
def local_damping(g_mass, g_force, g_vel, g_vel_old, gravity, dt, alpha, mass_eps):
    nn, d = g_vel.shape
    for i in prange(nn):
        m = g_mass[i]
        if m <= mass_eps:
            continue
        for a in range(d):
            f = g_force[i, a] + m * gravity[a]
            v = g_vel_old[i, a]
            sgn = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
            g_vel[i, a] -= dt * alpha * abs(f) * sgn / m


class LocalDamping(GridStage):
    name = "local"
    description = "Cundall local non-viscous damping on grid nodes (quasi-static stages)"
    Params = LocalParams
    phase = DAMPING
    needs_split_force = True  # reads the nodal force and the pre-update velocity

    def setup(self, scene):
        self.gravity = scene.gravity
        self.mass_eps = 1e-9 * float(scene.state.p_mass.min())

    def apply_grid(self, view, dt, time, remap):
        if remap or (self.params.until is not None and time >= self.params.until):
            return
        local_damping(view.g_mass, view.g_force, view.g_vel, view.g_vel_old, self.gravity, dt,
                      self.params.alpha, self.mass_eps)
