"""The velocity rule shared by every rigid boundary and obstacle on grid nodes.

For a node with velocity v (relative to the rigid surface) and unit normal n
pointing away from the surface into the material, v_n = v . n:

- fixed (0): v = 0 (no slip);
- slip (1): if v_n < 0 the normal component is removed;
- friction (2): if v_n < 0 the normal component is removed and the
  tangential part scaled by max(0, 1 - mu |v_n| / |v_t|): Coulomb friction in
  velocity form, the tangential impulse never exceeding mu times the normal one
  and never reversing the sliding direction (Bardenhagen, Brackbill & Sulsky
  2000, Comput. Methods Appl. Mech. Eng. 187:529);
- roller (3): the normal component is removed whatever its sign, the tangential
  part is free: a symmetry plane, or a smooth wall the material is bonded to, that
  holds tension as well as compression (an oedometer's ring under suction);
- voellmy (4): friction's rule here; the surface's node rule adds the turbulent drag
  rho g |u|^2 / xi on its first layer of nodes (contact/voellmy.py).

Against saturated soil friction acts on the effective normal force (Terzaghi's principle at the
contact; Iverson 1997, Rev. Geophys. 35:245): the tangential impulse is bounded by
mu (N - p_b A) = mu (1 - lambda) N, with lambda = p_b / sigma_n the water's share of the normal
force, from the node's pore pressure p_b and total normal stress sigma_n = -n . sigma n
(compression positive) that the saturated scheme leaves on the node (contract/stages.NODE_PORE,
schemes/saturated/kernels.node_pore_one): ``effective_mu``.  lambda is held in [0, 1]: a node whose
water carries the whole normal stress (or more: liquefied, or no compression) slides freely, and
suction (p_b < 0) adds no friction beyond the total stress's (docs/pore-water.md, Friction on
effective stress).  A dry node's row is zeros: lambda = 0 and mu unchanged, to the bit.
"""

import math

from numba import njit

CONDITIONS = {"fixed": 0, "slip": 1, "friction": 2, "roller": 3, "voellmy": 4}
#: a node within ON_SURFACE h of a surface is on it, in contact: a node that lies exactly on a face
#: (an obstacle or plane aligned with the grid) otherwise has a signed distance of +-1e-17 m from the
#: round-off of the lattice or of the plane's point, and that sign decided whether the face's whole row
#: of nodes took the load (a hydrostatic plate took 1/8 of its load at the first step, and 10 % less
#: on average, as its far face moved from x = 0.40 to 0.42 m)
ON_SURFACE = 1e-9


@njit(cache=True, inline="always")
def effective_mu(mu, pw, normal, n0, d):
    """mu (1 - lambda), lambda = p_b / sigma_n in [0, 1] for the unit normal normal[n0:n0 + d] and the
    node's pore water ``pw`` (NODE_PORE)."""
    p = pw[0]
    if p <= 0.0:
        return mu
    n_x = normal[n0]
    n_y = normal[n0 + 1]
    n_z = normal[n0 + 2] if d == 3 else 0.0
    s_n = -(n_x * n_x * pw[1] + n_y * n_y * pw[2] + n_z * n_z * pw[3]
            + 2.0 * (n_x * n_y * pw[4] + n_y * n_z * pw[5] + n_x * n_z * pw[6]))
    if s_n <= p:
        return 0.0
    return mu * (1.0 - p / s_n)


@njit(cache=True, inline="always")
def apply_condition(v, normal, n0, condition, mu):
    """Apply the rule to one velocity ``v`` (d,) in place; the unit normal is normal[n0:n0 + d].

    The normal is read at an offset rather than taken as a slice: a slice in a
    per-item function costs a reference count on every call, taken or not (the
    half-space guard ran at 5.7 ns per particle with one, 1.5 without)."""
    d = v.shape[0]
    if condition == 0:
        for a in range(d):
            v[a] = 0.0
        return
    vn = 0.0
    for a in range(d):
        vn += v[a] * normal[n0 + a]
    if vn >= 0.0 and condition != 3:
        return
    vt2 = 0.0
    for a in range(d):
        v[a] -= vn * normal[n0 + a]
        vt2 += v[a] * v[a]
    if (condition == 2 or condition == 4) and vt2 > 0.0:
        scale = max(0.0, 1.0 - mu * (-vn) / math.sqrt(vt2))
        for a in range(d):
            v[a] *= scale
