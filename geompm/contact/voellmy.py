"""Voellmy basal friction on a rigid surface's nodes: the practice law of RAMMS and r.avaflow.

    tau = mu sigma_n + rho g |u|^2 / xi          [Pa]   (Voellmy 1955; Salm 1993; RAMMS::DEBRISFLOW's
                                                        manual; r.avaflow's Voellmy-type friction)

mu [-] the Coulomb coefficient (on the effective normal stress of saturated soil: contact/rules.effective_mu)
and xi [m/s2] the "turbulent" coefficient.  The Coulomb part is the velocity-form friction every contact
rule uses (its tangential impulse at most mu times the normal one).  The turbulent part is a force
rho g |u_t|^2 A / xi on each node of the surface's first layer, A = h^(d-1) its share of the bed (one node
per h of bed in each direction: the nodes within one cell behind the contact layer, where a plane at any
angle has on average one node per bed area h^(d-1)), so the bed takes rho g |u|^2 / xi per unit area; rho
is the flow's density (``density`` or the materials' common one).  The drag acts on every node of that layer
that holds mass, pressed into the bed or not: a basal node's normal velocity rings from step to step (the
light nodes at a bed under USL), and a drag switched off with it let a sliding layer run 5-14 % over its
terminal speed at h = 0.0125 m; the Coulomb part needs the normal impulse and acts only when pressed.  On a node of mass m it changes the
tangential speed implicitly over the step, |u'| + K |u'|^2 = |u|, K = rho g A dt / (xi m):

    |u'| = (sqrt(1 + 4 K |u|) - 1) / (2 K)

(stable for any step, never reversing the sliding; a thin flow's basal node holds its whole column, so its
deceleration is g |u|^2 / (xi H), the depth-averaged law's).  The nodes one cell beyond a flow's edges hold a
little of its mass and take a whole cell's drag: a block six cells wide slides 6.6 % slow at t = 0.25 s, 3.2 %
at half the cell size (docs/basal-friction.md).  Walls, planes (boundaries/halfspace.py), the terrain and the
obstacles (contact/force.contact_and_record) offer it.  A layer of depth H down a slope beta reaches
u = sqrt(xi H (sin beta - mu cos beta)) (tests/verification/test_voellmy.py).
"""

from __future__ import annotations

import math

from numba import njit

#: the condition's number (contact/rules.CONDITIONS): Coulomb friction on the normal, plus the drag below
VOELLMY = 4


@njit(cache=True, inline="always")
def turbulent_drag(v, normal, n0, drag, xi, dt, m):
    """Slow the tangential part of ``v`` (the unit normal at normal[n0:n0 + d]) by the turbulent term: ``drag``
    = rho g A [kg/m2 m/s2 m^(d-1)], ``xi`` [m/s2], the node's mass ``m`` [kg]; the normal part is left."""
    if m <= 0.0 or xi <= 0.0:
        return
    d = v.shape[0]
    vn = 0.0
    for a in range(d):
        vn += v[a] * normal[n0 + a]
    ut2 = 0.0
    for a in range(d):
        t = v[a] - vn * normal[n0 + a]
        ut2 += t * t
    if ut2 == 0.0:
        return
    ut = math.sqrt(ut2)
    k = drag * dt / (xi * m)
    scale = (math.sqrt(1.0 + 4.0 * k * ut) - 1.0) / (2.0 * k * ut)
    for a in range(d):
        v[a] = vn * normal[n0 + a] + scale * (v[a] - vn * normal[n0 + a])
