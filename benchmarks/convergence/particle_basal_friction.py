"""Experimental basal friction on particles, for the convergence probe (2D only; not a geompm plugin).

Use with a slip floor (--set boundaries.2.condition=slip): after G2P, every particle of the bottom layer
(centre below the particle spacing s = sqrt(V0)) gets a Coulomb friction impulse from its own vertical
stress: J = mu |sigma_yy| s dt (per metre, plane strain), which changes its horizontal velocity by at
most J / m_p, never reversing it.  The friction then acts as a force from the stress at the base instead
of a velocity rule on floor nodes whose velocity averages 1.5 h of material.

    PYTHONPATH=benchmarks/convergence python benchmarks/convergence/column_probe.py 0.02 0.01 \\
        --set boundaries.2.condition=slip --stage particle_basal_friction:ParticleBasalFriction
"""

import numpy as np
from numba import njit

from geompm.contract.stages import NO_AUX, ParticleStage

MU = 0.6009  # tan 31 deg, the shipped floor's coefficient


@njit(cache=True, inline="always")
def basal_friction(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
    """prm = (spacing [m], floor y [m], mu [-])."""
    spacing, floor_y, mu = prm[0], prm[1], prm[2]
    if x[1] - floor_y > spacing:
        return
    syy = s[1]
    if syy >= 0.0:
        return
    dv = mu * (-syy) * spacing * dt / m
    u = v[0]
    v[0] = np.copysign(max(abs(u) - dv, 0.0), u)


class ParticleBasalFriction(ParticleStage):
    label = "particle_basal_friction"
    name = "particle_basal_friction"
    particle_rule = basal_friction

    def __init__(self):
        pass

    def setup(self, scene):
        st = scene.state
        spacing = float(np.sqrt(np.median(st.p_vol)))
        self.prm = np.array([spacing, float(scene.grid.origin[1]), MU])

    def particle_args(self, dt, time):
        return self.prm, NO_AUX
