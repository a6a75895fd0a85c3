"""A probe: the flow's depth, speed and discharge through a column of the flow, every step.

The column is every point within ``half_width`` b [m] of the line through ``point`` along ``direction``
(default: against gravity), a strip of width 2 b in 2D, a cylinder of radius b in 3D.  Each particle in it
counts with the tent weight w = 1 - r / b, r its distance from the axis, so a reading moves smoothly as
particles cross the column's edge (with a sharp edge a strip two particle spacings wide jumps by a quarter as
one column enters).  From the particles, after G2P each step:

    V = sum w_p m_p / rho0_p              (reference volumes: a flow that dilated counts as the solid it
                                           carries, as the hazard maps' depths do)
    h = V / A,   A = int w dA = b (2D, per metre) or pi b^2 / 3 (3D)     depth along ``direction`` [m]
    u = |sum w_p m_p v_p| / sum w_p m_p                                    the column's bulk speed [m/s]
    rho = sum w_p m_p / V                                                  its reference density [kg/m3]
    q = h u                                                                discharge per unit width [m2/s]

A uniform layer of thickness H on a particle lattice aligned with the column reads h = H exactly (the
midpoint rule is exact for the tent).  Every body counts: place the column where only the flow passes (not
through a resting bed).  Series columns <name>_depth, <name>_speed, <name>_q.  A contact surface that names
the probe (``probe``) reads it for the design coefficients (contact/impact_design.py).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from geompm.contract.layout import pack_in_layout, param_layout
from geompm.contract.stages import OBSTACLE as OBSTACLE_PHASE
from geompm.contract.stages import ParticleStage

PROBE = param_layout("point_x", "point_y", "point_z", "dir_x", "dir_y", "dir_z", "half_width")
#: the reduction: reference volume, mass, momentum (d)
VOLUME, MASS, MOMENTUM = 0, 1, 2


@njit(cache=True, inline="always")
def probe_rule(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
    """Add a particle inside the column to the sums with the tent weight w = 1 - r / b: its reference volume
    m / rho0 (aux[k], the block's reference density), its mass and momentum."""
    d = x.shape[0]
    along = 0.0
    rr = 0.0
    for a in range(d):
        rel = x[a] - prm[PROBE.point_x + a]
        along += rel * prm[PROBE.dir_x + a]
        rr += rel * rel
    b = prm[PROBE.half_width]
    r = math.sqrt(max(rr - along * along, 0.0))
    if r >= b:
        return
    w = 1.0 - r / b
    out[VOLUME] += w * m / aux[k]
    out[MASS] += w * m
    for a in range(d):
        out[MOMENTUM + a] += w * m * v[a]


class ProbeStage(ParticleStage):
    """The probe ``params`` (schema/case.ProbeSpec) as a particle pass that changes nothing."""
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)

    phase = OBSTACLE_PHASE  # after the contacts: it reads the velocities they leave
    particle_rule = probe_rule

    def setup(self, scene):
        d = scene.dim
        p = self.params
        self.dim = d
        self.particle_reduction = MOMENTUM + d
        up = np.asarray(p.direction if p.direction is not None else -np.asarray(scene.gravity, float), float)
        up = up / np.linalg.norm(up)
        full = np.zeros(3), np.zeros(3)
        full[0][:d], full[1][:d] = p.point, up
        self.prm = pack_in_layout(PROBE, {**{f"point_{c}": full[0][i] for i, c in enumerate("xyz")},
                                          **{f"dir_{c}": full[1][i] for i, c in enumerate("xyz")},
                                          "half_width": p.half_width}, f"{self.json_path}")
        self.aux = np.array([m.density for m in scene.materials], float)
        self.area = p.half_width if d == 2 else math.pi * p.half_width ** 2 / 3.0  # int w dA
        self.reading = (0.0, 0.0, 0.0)  # (depth [m], speed [m/s], density [kg/m3]) of the last step
        self.velocity = np.zeros(d)  # the column's bulk velocity [m/s] of the last step

    def particle_args(self, dt, time):
        return self.prm, self.aux

    def particle_reach(self, prm, lo, hi):
        return lo, hi  # it moves no particle

    def particle_reduced(self, out, dt, time):
        total = out.sum(axis=0)
        vol, mass = float(total[VOLUME]), float(total[MASS])
        if vol <= 0.0:
            self.reading = (0.0, 0.0, 0.0)
            self.velocity[:] = 0.0
            return
        self.velocity = total[MOMENTUM:MOMENTUM + self.dim] / mass
        self.reading = (vol / self.area, float(np.linalg.norm(self.velocity)), mass / vol)

    def series(self):
        h, u, _ = self.reading
        return {f"{self.label}_depth": h, f"{self.label}_speed": u, f"{self.label}_q": h * u}

    def state_dict(self):
        return {"reading": list(self.reading), "velocity": self.velocity.tolist()}

    def load_state(self, state):
        self.reading = tuple(state.get("reading", (0.0, 0.0, 0.0)))
        if "velocity" in state:
            self.velocity = np.asarray(state["velocity"], float)
