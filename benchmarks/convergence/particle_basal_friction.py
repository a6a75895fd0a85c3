"""Experimental basal friction on particles, for the convergence probe (2D only; not a geompm plugin).

Use with a slip floor (--set boundaries.2.condition=slip): after G2P, every particle of the bottom layer
(centre below the particle spacing s = sqrt(V0)) gets a Coulomb friction impulse from its own vertical
stress: J = mu |sigma_yy| s dt (per metre, plane strain), which changes its horizontal velocity by at
most J / m_p, never reversing it.  The friction then acts as a force from the stress at the base instead
of a velocity rule on floor nodes whose velocity averages 1.5 h of material.

    PYTHONPATH=benchmarks/convergence python benchmarks/convergence/column_probe.py 0.02 0.01 \\
        --set boundaries.2.condition=slip --stage particle_basal_friction:ParticleBasalFriction
"""

import math

import numpy as np
from numba import njit

from geompm.stages import ParticleStage

MU = 0.6009  # tan 31 deg, the shipped floor's coefficient


@njit(cache=True)
def basal_friction(p_x, p_v, p_stress, p_mass, spacing, floor_y, mu, dt):
    for p in range(p_x.shape[0]):
        if p_x[p, 1] - floor_y > spacing:
            continue
        syy = p_stress[p, 1]
        if syy >= 0.0:
            continue
        dv = mu * (-syy) * spacing * dt / p_mass[p]
        u = p_v[p, 0]
        p_v[p, 0] = math.copysign(max(abs(u) - dv, 0.0), u)


class ParticleBasalFriction(ParticleStage):
    label = "particle_basal_friction"

    def __init__(self):
        pass

    def setup(self, scene):
        st = scene.state
        self.spacing = float(np.sqrt(np.median(st.p_vol)))
        self.floor = float(scene.grid.origin[1])

    def apply_particles(self, state, dt, time):
        basal_friction(state.p_x, state.p_v, state.p_stress, state.p_mass, self.spacing, self.floor, MU, dt)
