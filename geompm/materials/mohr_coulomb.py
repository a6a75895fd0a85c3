"""Mohr-Coulomb elastic-perfectly plastic soil, returned to the MC hexagon exactly.

Principal stresses sigma_1 >= sigma_2 >= sigma_3 (tension positive):

    f = (sigma_1 - sigma_3) + (sigma_1 + sigma_3) sin(phi) - 2 c cos(phi) <= 0
    g = (sigma_1 - sigma_3) + (sigma_1 + sigma_3) sin(psi)

Return mapping in principal stress space (de Souza Neto, Peric & Owen 2008,
Computational Methods for Plasticity, sec. 8.2, Boxes 8.1-8.3): return to the
main plane; if that breaks the principal order, return to the edge (two planes
active: sigma_1 = sigma_2 in triaxial extension, sigma_2 = sigma_3 in triaxial
compression); if the edge return is inadmissible, return to the apex
sigma_i = c cot(phi).  The principal directions of the trial stress are kept
(isotropy); they come from a register Jacobi solver (kernels/eigen3.py), not
LAPACK, so the law needs no scipy and no allocation per particle.  State
variables and the dilatancy cut-off as in drucker_prager.py.
"""

from __future__ import annotations

import math

from numba import njit
from pydantic import model_validator

from geompm.kernels.eigen3 import sym_eig3
from geompm.contract.layout import param_layout
from geompm.materials.plasticity import ELASTIC, ElastoplasticParams, FrictionalMaterial, current_moduli, kirchhoff_trial

#: packed parameters: ELASTIC, sin and cos of phi, sin psi, cohesion c [Pa], dilatancy cut-off eps_v^p [-]
MC = param_layout(ELASTIC, "sin_phi", "cos_phi", "sin_psi", "cohesion", "dilation_cutoff")


class MohrCoulombParams(ElastoplasticParams):
    @model_validator(mode="after")
    def _dilation(self):
        return self.check_dilation()


@njit(cache=True, inline="always")
def _dot(a0, a1, a2, b0, b1, b2):
    return a0 * b0 + a1 * b1 + a2 * b2


@njit(cache=True, inline="always")
def _eq_strain(e1, e2, e3):
    """sqrt(2/3 e':e') of a principal plastic strain increment."""
    m = (e1 + e2 + e3) / 3.0
    return math.sqrt(2.0 / 3.0 * ((e1 - m) ** 2 + (e2 - m) ** 2 + (e3 - m) ** 2))


@njit(cache=True)
def mc_principal_return(s1, s2, s3, lam, G, sphi, cphi, spsi, c):
    """Returned principal stresses (s1 >= s2 >= s3) and (d_eps_p_eq, d_eps_v_p)."""
    fy = 2.0 * c * cphi
    f = (s1 - s3) + (s1 + s3) * sphi - fy
    if f <= 0.0:
        return s1, s2, s3, 0.0, 0.0
    K = lam + 2.0 * G / 3.0
    vol = lam * 2.0 * spsi
    # main plane
    a0, a1, a2 = vol + 2.0 * G * (1.0 + spsi), vol, vol + 2.0 * G * (-1.0 + spsi)
    nf0, nf2 = 1.0 + sphi, -1.0 + sphi
    dl = f / (nf0 * a0 + nf2 * a2)
    r1, r2, r3 = s1 - dl * a0, s2 - dl * a1, s3 - dl * a2
    if r1 >= r2 >= r3:
        return r1, r2, r3, _eq_strain(dl * (1.0 + spsi), 0.0, dl * (-1.0 + spsi)), 2.0 * spsi * dl
    # edge: second plane chosen by the order that the main return broke
    if r2 > r1:  # triaxial extension edge, sigma_1 = sigma_2
        fb = (s2 - s3) + (s2 + s3) * sphi - fy
        b0, b1, b2 = vol, vol + 2.0 * G * (1.0 + spsi), vol + 2.0 * G * (-1.0 + spsi)
        nb0, nb1, nb2 = 0.0, 1.0 + sphi, -1.0 + sphi
    else:  # triaxial compression edge, sigma_2 = sigma_3
        fb = (s1 - s2) + (s1 + s2) * sphi - fy
        b0, b1, b2 = vol + 2.0 * G * (1.0 + spsi), vol + 2.0 * G * (-1.0 + spsi), vol
        nb0, nb1, nb2 = 1.0 + sphi, -1.0 + sphi, 0.0
    m00 = _dot(nf0, 0.0, nf2, a0, a1, a2)
    m01 = _dot(nf0, 0.0, nf2, b0, b1, b2)
    m10 = _dot(nb0, nb1, nb2, a0, a1, a2)
    m11 = _dot(nb0, nb1, nb2, b0, b1, b2)
    det = m00 * m11 - m01 * m10
    dla = (f * m11 - m01 * fb) / det
    dlb = (m00 * fb - m10 * f) / det
    r1 = s1 - dla * a0 - dlb * b0
    r2 = s2 - dla * a1 - dlb * b1
    r3 = s3 - dla * a2 - dlb * b2
    tol = 1e-12 * (abs(r1) + abs(r3) + fy + 1.0)
    if dla >= 0.0 and dlb >= 0.0 and r1 >= r2 - tol and r2 >= r3 - tol and (sphi == 0.0 or
                                                                          r1 + r2 + r3 <= 3.0 * c * cphi / sphi):
        ga, gb = 1.0 + spsi, -1.0 + spsi
        if nb0 == 0.0:  # extension edge: second plane acts on (sigma_2, sigma_3)
            e1, e2, e3 = dla * ga, dlb * ga, (dla + dlb) * gb
        else:  # compression edge: second plane acts on (sigma_1, sigma_2)
            e1, e2, e3 = (dla + dlb) * ga, dlb * gb, dla * gb
        return r1, r2, r3, _eq_strain(e1, e2, e3), 2.0 * spsi * (dla + dlb)
    # apex
    apex = c * cphi / sphi if sphi > 0.0 else (s1 + s2 + s3) / 3.0
    mean = (s1 + s2 + s3) / 3.0
    d1, d2, d3 = s1 - mean, s2 - mean, s3 - mean
    dev = math.sqrt(d1 * d1 + d2 * d2 + d3 * d3)
    return apex, apex, apex, math.sqrt(2.0 / 3.0) * dev / (2.0 * G), (mean - apex) / K


@njit(cache=True, inline="always")
def _rebuild(s, w0, w1, w2, x0, y0, z0, x1, y1, z1, x2, y2, z2):
    """Voigt stress s = w0 v0 v0^T + w1 v1 v1^T + w2 v2 v2^T, v_k = (x_k, y_k, z_k)."""
    s[0] = w0 * x0 * x0 + w1 * x1 * x1 + w2 * x2 * x2
    s[1] = w0 * y0 * y0 + w1 * y1 * y1 + w2 * y2 * y2
    s[2] = w0 * z0 * z0 + w1 * z1 * z1 + w2 * z2 * z2
    s[3] = w0 * x0 * y0 + w1 * x1 * y1 + w2 * x2 * y2
    s[4] = w0 * y0 * z0 + w1 * y1 * z1 + w2 * y2 * z2
    s[5] = w0 * x0 * z0 + w1 * x1 * z1 + w2 * x2 * z2


@njit(cache=True, inline="always")
def mc_update(s, state, tr, lam, G, sphi, cphi, spsi, c):
    """The return of the trial stress ``tr`` (a Voigt 6-tuple) to the hexagon (phi, c) with dilation psi, in
    principal space (module docstring); s (6,) and state (2,) in place."""
    # Voigt order (xx, yy, zz, xy, yz, xz); eigenvalues ascending: w[2] = sigma_1
    e = sym_eig3(tr[0], tr[1], tr[2], tr[3], tr[4], tr[5])
    r1, r2, r3, deq, dvol = mc_principal_return(e[2], e[1], e[0], lam, G, sphi, cphi, spsi, c)
    if deq == 0.0 and dvol == 0.0:
        for i in range(6):
            s[i] = tr[i]
        return
    state[0] += deq
    state[1] += dvol
    # sigma = sum_k r_k v_k v_k^T with the trial stress's principal directions v_k (columns)
    _rebuild(s, r3, r2, r1, e[3], e[4], e[5], e[6], e[7], e[8], e[9], e[10], e[11])


@njit(cache=True)
def mc_stress(prm, dt, L, rho, s, state):
    """One particle's MC return in principal space (module docstring); s (6,) and state (2,) in place."""
    lam, G = current_moduli(prm, rho)
    spsi = prm[MC.sin_psi] if state[1] < prm[MC.dilation_cutoff] else 0.0  # dilatancy cut-off
    tr = kirchhoff_trial(s, L, dt, lam, G)
    mc_update(s, state, tr, lam, G, prm[MC.sin_phi], prm[MC.cos_phi], spsi, prm[MC.cohesion])


class MohrCoulomb(FrictionalMaterial):
    name = "mohr_coulomb"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Mohr-Coulomb elastic-perfectly plastic soil, exact return to the hexagon with corners"
    Params = MohrCoulombParams
    state_vars = ("plastic_strain", "plastic_volumetric_strain")
    layout = MC
    particle_stress = mc_stress

    @classmethod
    def pack(cls, p):
        phi, psi = math.radians(p.friction_angle), math.radians(p.dilation_angle)
        return {**cls.elastic_pack(p), "sin_phi": math.sin(phi), "cos_phi": math.cos(phi),
                "sin_psi": math.sin(psi), "cohesion": p.cohesion, "dilation_cutoff": p.cutoff()}

    @classmethod
    def example_params(cls):
        return cls.Params(density=2650.0, youngs_modulus=0.84e6, poisson_ratio=0.3, friction_angle=31.0,
                          cohesion=100.0, dilation_angle=5.0)
