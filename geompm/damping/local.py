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

import numpy as np
from numba import njit
from pydantic import Field

from geompm.contract.layout import pack_in_layout, param_layout
from geompm.contract.plugin import Params
from geompm.contract.stages import DAMPING, NO_AUX, GridStage

#: packed parameters: gravity [m/s2] (3 slots, 2D uses two), alpha [-], the mass below which a node is empty [kg]
LOCAL = param_layout("gravity_x", "gravity_y", "gravity_z", "alpha", "mass_eps")


class LocalParams(Params):
    alpha: float = Field(ge=0.0, lt=1.0, description="Damping coefficient alpha [-], 0.8 typical")
    until: float | None = Field(None, gt=0, description="Simulated time [s] after which damping stops")


@njit(cache=True, inline="always")
def local_damping(prm, aux, dt, x, m, v, v_old, f, pw, work, out):
    if m <= prm[LOCAL.mass_eps]:
        return
    alpha = prm[LOCAL.alpha]
    for a in range(v.shape[0]):
        fa = f[a] + m * prm[LOCAL.gravity_x + a]
        u = v_old[a]
        sgn = 1.0 if u > 0.0 else (-1.0 if u < 0.0 else 0.0)
        v[a] -= dt * alpha * abs(fa) * sgn / m


class LocalDamping(GridStage):
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)
    name = "local"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Cundall local non-viscous damping on grid nodes (quasi-static stages)"
    Params = LocalParams
    phase = DAMPING
    needs_split_force = True  # reads the nodal force and the pre-update velocity
    node_rule = local_damping

    def setup(self, scene):
        g = np.zeros(3)
        g[:scene.dim] = scene.gravity
        values = {f"gravity_{c}": g[k] for k, c in enumerate("xyz")}
        values.update(alpha=self.params.alpha, mass_eps=1e-9 * float(scene.state.p_mass.min()))
        self.prm = pack_in_layout(LOCAL, values, f"stage '{self.label}'")

    def grid_args(self, dt, time, remap):
        if remap or (self.params.until is not None and time >= self.params.until):
            return None
        return self.prm, NO_AUX
