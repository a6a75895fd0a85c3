"""A rigid half-space on the grid and on the particles: the shared base of ``wall`` and ``plane``.

On grid nodes: every node whose signed distance (x_i - point) . n is <=
``layer`` gets the contact rule of contact/rules.py (``slip``, ``fixed``,
``friction`` or ``roller``), n the unit normal pointing from the surface into the material.
On particles, after G2P: a particle that still ended behind the surface is
put back on it, so none is ever deeper than round-off (a fast particle, or a
plane that cuts the cells between nodes, can end a step behind it).  Both are per-item functions run by the backend (contract/stages.py).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from geompm.contract.layout import pack_in_layout, param_layout
from geompm.contract.stages import NO_AUX, GridStage, ParticleStage
from geompm.contact.rules import CONDITIONS, ON_SURFACE, apply_condition, effective_mu
from geompm.contact.voellmy import VOELLMY, turbulent_drag
from geompm.contact.voellmy_params import voellmy_density, voellmy_slots

#: packed parameters: a point on the surface [m] and the unit normal into the material (3 slots each,
#: 2D uses the first two), the contact condition (contact.CONDITIONS), the Coulomb coefficient [-],
#: the contact layer [m]; Voellmy's xi [m/s2], rho g h^(d-1) of its drag and the lowest signed distance of
#: the nodes that take it [m] (contact/voellmy.py)
HALFSPACE = param_layout("point_x", "point_y", "point_z", "normal_x", "normal_y", "normal_z",
                         "condition", "mu", "layer", "xi", "drag", "band")
P0, N0 = HALFSPACE.point_x, HALFSPACE.normal_x


@njit(cache=True, inline="always")
def halfspace_node_rule(prm, aux, dt, x, m, v, v_old, f, pw, work, out):
    d = x.shape[0]
    dist = 0.0
    for a in range(d):
        dist += (x[a] - prm[P0 + a]) * prm[N0 + a]
    if dist <= prm[HALFSPACE.layer]:
        condition = int(prm[HALFSPACE.condition])
        apply_condition(v, prm, N0, condition, effective_mu(prm[HALFSPACE.mu], pw, prm, N0, d))
        if condition == VOELLMY and dist > prm[HALFSPACE.band]:
            turbulent_drag(v, prm, N0, prm[HALFSPACE.drag], prm[HALFSPACE.xi], dt, m)


@njit(cache=True, inline="always")
def halfspace_particle_rule(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
    """A particle with phi = (x - point) . n < 0 is put back on the surface, x <- x - phi n, and its
    velocity gets the nodes' rule.  phi is exact for a plane, so this leaves phi >= 0 up to
    round-off; a half-space cannot be crossed within a step without ending behind it, so the end
    position is the whole test."""
    d = x.shape[0]
    phi = 0.0
    for a in range(d):
        phi += (x[a] - prm[P0 + a]) * prm[N0 + a]
    if phi >= 0.0:
        return
    for a in range(d):
        x[a] -= phi * prm[N0 + a]
    apply_condition(v, prm, N0, int(prm[HALFSPACE.condition]), prm[HALFSPACE.mu])


class HalfSpace(GridStage, ParticleStage):
    """Subclasses set ``self.point``, ``self.normal`` (unit) and ``self.layer`` [m] in setup, then call
    ``self.pack_halfspace()``."""
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)

    node_rule = halfspace_node_rule
    particle_rule = halfspace_particle_rule

    def pack_halfspace(self):
        point = np.zeros(3)
        normal = np.zeros(3)
        d = len(self.point)
        point[:d], normal[:d] = self.point, self.normal
        values = {f"point_{c}": point[k] for k, c in enumerate("xyz")}
        values.update({f"normal_{c}": normal[k] for k, c in enumerate("xyz")})
        layer = self.layer + ON_SURFACE * self.grid.h
        values.update(condition=CONDITIONS[self.params.condition], mu=self.params.friction, layer=layer,
                      **voellmy_slots(self.params, self.voellmy_rho, self.gravity, self.grid.h, d, layer))
        self.prm = pack_in_layout(HALFSPACE, values, f"stage '{self.label}'")

    def setup(self, scene):
        self.grid = scene.grid
        self.gravity = float(np.linalg.norm(scene.gravity))
        self.voellmy_rho = voellmy_density(self.params, scene, self.json_path)

    def water_boundary(self):
        """The half-space as a boundary of saturated soil (contract/stages.py): its nodes are those the
        contact rule reaches; ``drainage`` from the parameters."""
        drained = self.params.drainage != "impermeable"  # a held head lets the water through too
        return (np.asarray(self.point, float), np.asarray(self.normal, float), float(self.prm[HALFSPACE.layer]),
                drained)

    def solid_depth(self, pts):
        """Depth behind the surface, -(x - point) . n (n points into the material)."""
        return -(np.asarray(pts) - np.asarray(self.point)) @ np.asarray(self.normal)

    def surface(self):
        """The plane clipped to the grid's box (a segment in 2D)."""
        from geompm.contact.tessellate import plane_surface

        g = self.grid
        return plane_surface(self.point, self.normal, g.origin, g.upper, g.h)

    def grid_args(self, dt, time, remap):
        return self.prm, NO_AUX

    def particle_args(self, dt, time):
        return self.prm, NO_AUX

    def particle_reach(self, prm, lo, hi):
        """Skip the pass when the box's deepest corner is not behind the surface.

        phi is computed at that corner in the rule's own arithmetic; each of its terms and its running sum
        are non-decreasing in every coordinate when rounded, so no particle in the box has a smaller phi
        and the rule would return at once for all of them.  Otherwise the rule moves a particle by
        -phi n with |phi| <= |phi at the corner|: the box grows by that much along every axis (and by
        1e-6 of its coordinates for a float32 state's rounding on store)."""
        phi = 0.0
        for a in range(len(lo)):
            n = prm[N0 + a]
            phi += ((lo[a] if n > 0.0 else hi[a]) - prm[P0 + a]) * n
        if phi >= 0.0:
            return None
        grow = np.abs(phi * prm[N0:N0 + len(lo)]) + 1e-6 * np.maximum(np.abs(lo), np.abs(hi)) + 1e-30
        return lo - grow, hi + grow
