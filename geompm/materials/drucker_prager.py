"""Drucker-Prager elastic-perfectly plastic soil, non-associated flow.

Yield and plastic potential (tension positive, I1 = tr sigma, J2 of the deviator s):

    f = sqrt(J2) + alpha I1 - k <= 0,       g = sqrt(J2) + beta I1

Return mapping in closed form (elastic predictor sigma_tr, see plasticity.py):
    dlambda = f(sigma_tr) / (G + 9 K alpha beta)
    s = s_tr (1 - G dlambda / sqrt(J2_tr)),   I1 = I1_tr - 9 K beta dlambda
and when that would pass the apex (sqrt(J2_tr) < G dlambda) the stress returns
to the apex, I1 = k / alpha, s = 0.  A tension cut-off caps the mean stress at
``tension_cutoff`` (default: the apex).  de Souza Neto, Peric & Owen (2008)
Computational Methods for Plasticity, sec. 8.3.3.

Matching to Mohr-Coulomb (phi, c), with t = tan(phi), s = sin(phi):
  plane_strain: the MC plane-strain strength for the flow rule in use.  At a
      plane-strain limit state the plastic eps_zz rate vanishes, so
      s_zz = -2 beta sqrt(J2), and the in-plane Mohr circle (radius R, centre
      c_m, tension positive) of the DP surface is
          R (1 - 3 alpha beta) / sqrt(1 - 3 beta^2) = k - 3 alpha c_m.
      Equating it with MC, R = -c_m sin(phi) + c cos(phi):
          beta  = sin(psi) / sqrt(9 + 3 sin^2(psi))
          alpha = sin(phi) / (3 sqrt(1 - 3 beta^2) + 3 beta sin(phi))
          k     = c cos(phi) (1 - 3 alpha beta) / sqrt(1 - 3 beta^2)
      Associated flow (psi = phi) gives the textbook alpha = t / sqrt(9 + 12 t^2),
      k = 3 c / sqrt(9 + 12 t^2); isochoric flow (psi = 0) gives alpha = s / 3,
      k = c cos(phi).  The associated alpha with psi = 0 would make the cone
      weaker than MC: sqrt(J2) = 0.494 p instead of sin 31 deg p = 0.515 p,
      an effective friction angle of 29.6 deg for 31.
  outer (triaxial compression): alpha = 2 s / (sqrt3 (3 - s)), k = 6 c cos(phi) / (sqrt3 (3 - s))
  inner (triaxial extension):   alpha = 2 s / (sqrt3 (3 + s)), k = 6 c cos(phi) / (sqrt3 (3 + s))
  middle: the mean of the outer and inner coefficients.
beta uses the same formula with psi.  Past the dilatancy cut-off the flow is
isochoric (beta = 0) and the plane-strain cone switches to its psi = 0 match,
so the MC strength is kept at every state.

State variables: accumulated equivalent plastic strain eps_p = sum dlambda / sqrt3
(sqrt(2/3 de_p:de_p) of the deviatoric plastic strain), plastic volumetric
strain eps_v^p = sum 3 beta dlambda (dilatant positive).  With a dilatancy
cut-off (plasticity.py) beta = 0 once eps_v^p has reached it.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numba import njit
from pydantic import Field, model_validator

from geompm.contract.layout import param_layout
from geompm.materials.plasticity import (ELASTIC, ElastoplasticParams, FrictionalMaterial, current_moduli, kirchhoff_trial,
                         set_scaled_deviator, sqrt_j2)

SQ3 = math.sqrt(3.0)

#: packed parameters: ELASTIC, the cone alpha [-] and k [Pa], the potential's beta [-], the largest
#: mean stress [Pa], the dilatancy cut-off eps_v^p [-] (inf: none) and the cone past it (isochoric flow)
DP = param_layout(ELASTIC, "alpha", "k", "beta", "tension_cutoff", "dilation_cutoff", "alpha_isochoric",
                  "k_isochoric")


class DruckerPragerParams(ElastoplasticParams):
    cone: Literal["plane_strain", "outer", "inner", "middle"] = Field(
        "plane_strain", description="How the DP cone is matched to Mohr-Coulomb")
    tension_cutoff: float | None = Field(
        None, ge=0.0, description="Largest mean stress (tension positive) [Pa]; default the cone apex")

    @model_validator(mode="after")
    def _dilation(self):
        return self.check_dilation()


def dp_coefficients(angle_deg: float, cone: str, dilation_deg: float | None = None) -> tuple[float, float]:
    """(alpha, k/c) of the DP cone matched to MC with friction angle ``angle_deg``.

    For the plane_strain cone the match depends on the flow rule: ``dilation_deg`` psi (None: associated,
    psi = phi).  The potential's beta is ``dp_coefficients(psi, cone)[0]``."""
    phi = math.radians(angle_deg)
    t, s = math.tan(phi), math.sin(phi)
    if cone == "plane_strain":
        if dilation_deg is None:
            q = math.sqrt(9 + 12 * t * t)
            return t / q, 3 / q
        beta = dp_coefficients(dilation_deg, cone)[0]
        root = math.sqrt(1.0 - 3.0 * beta * beta)
        alpha = s / (3.0 * root + 3.0 * beta * s)
        return alpha, math.cos(phi) * (1.0 - 3.0 * alpha * beta) / root
    out = (2 * s / (SQ3 * (3 - s)), 6 * math.cos(phi) / (SQ3 * (3 - s)))
    inn = (2 * s / (SQ3 * (3 + s)), 6 * math.cos(phi) / (SQ3 * (3 + s)))
    if cone == "outer":
        return out
    if cone == "inner":
        return inn
    return 0.5 * (out[0] + inn[0]), 0.5 * (out[1] + inn[1])


#: the cone matchings, in the order of the packed ``cone`` index of the laws that compute their cone per particle
CONES = ("plane_strain", "outer", "inner", "middle")


@njit(cache=True, inline="always")
def dp_cone(sphi, cphi, spsi, cone):
    """(alpha, k / c, beta) of the cone matched to Mohr-Coulomb with sin(phi), cos(phi), sin(psi), for the
    matching ``CONES[cone]``: the formulas of the module docstring, as dp_coefficients gives them, in a form
    a kernel can evaluate per particle (a softening law's phi and psi change with its plastic strain)."""
    if cone == 0:
        beta = spsi / math.sqrt(9.0 + 3.0 * spsi * spsi)
        root = math.sqrt(1.0 - 3.0 * beta * beta)
        alpha = sphi / (3.0 * root + 3.0 * beta * sphi)
        return alpha, cphi * (1.0 - 3.0 * alpha * beta) / root, beta
    a_out, k_out, b_out = 2.0 * sphi / (SQ3 * (3.0 - sphi)), 6.0 * cphi / (SQ3 * (3.0 - sphi)), 2.0 * spsi / (SQ3 * (3.0 - spsi))
    a_in, k_in, b_in = 2.0 * sphi / (SQ3 * (3.0 + sphi)), 6.0 * cphi / (SQ3 * (3.0 + sphi)), 2.0 * spsi / (SQ3 * (3.0 + spsi))
    if cone == 1:
        return a_out, k_out, b_out
    if cone == 2:
        return a_in, k_in, b_in
    return 0.5 * (a_out + a_in), 0.5 * (k_out + k_in), 0.5 * (b_out + b_in)


@njit(cache=True, inline="always")
def dp_return(s, state, tr, K, G, alpha, k, beta, tcut):
    """The return of the trial stress ``tr`` (a Voigt 6-tuple) to the cone (alpha, k) with potential beta and
    the tension cut-off tcut (module docstring); s (6,) and state (2,) in place."""
    I1 = tr[0] + tr[1] + tr[2]
    mean = I1 / 3.0
    tau = sqrt_j2(tr, mean)
    f = tau + alpha * I1 - k
    if f <= 0.0 and mean <= tcut:
        for i in range(6):
            s[i] = tr[i]
        return
    if f > 0.0:
        dlam = f / (G + 9.0 * K * alpha * beta)
        if tau - G * dlam >= 0.0:
            scale = 1.0 - G * dlam / tau
            I1n = I1 - 9.0 * K * beta * dlam
            state[0] += dlam / SQ3
            state[1] += 3.0 * beta * dlam
        else:  # apex return
            scale = 0.0
            I1n = k / alpha if alpha > 0.0 else I1
            state[0] += tau / (SQ3 * G)
            state[1] += (I1 - I1n) / (3.0 * K)
    else:
        scale = 1.0
        I1n = I1
    if I1n / 3.0 > tcut:  # tension cut-off, then back inside the cone
        state[1] += (I1n - 3.0 * tcut) / (3.0 * K)
        I1n = 3.0 * tcut
        tmax = k - alpha * I1n
        t_now = tau * scale
        if t_now > tmax:
            scale = max(tmax, 0.0) / tau if tau > 0.0 else 0.0
    set_scaled_deviator(s, tr, mean, scale, I1n / 3.0)


@njit(cache=True)
def dp_stress(prm, dt, L, rho, s, state):
    """One particle's DP return (module docstring); s (6,) and state (2,) in place."""
    lam, G = current_moduli(prm, rho)
    alpha, k, beta = prm[DP.alpha], prm[DP.k], prm[DP.beta]
    K = lam + 2.0 * G / 3.0
    if state[1] >= prm[DP.dilation_cutoff]:  # dilatancy cut-off: isochoric past it, with the cone matched to that
        alpha, k, beta = prm[DP.alpha_isochoric], prm[DP.k_isochoric], 0.0
    tr = kirchhoff_trial(s, L, dt, lam, G)
    dp_return(s, state, tr, K, G, alpha, k, beta, prm[DP.tension_cutoff])


class DruckerPrager(FrictionalMaterial):
    name = "drucker_prager"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Drucker-Prager elastic-perfectly plastic soil, non-associated, MC-matched cone"
    Params = DruckerPragerParams
    state_vars = ("plastic_strain", "plastic_volumetric_strain")
    layout = DP
    particle_stress = dp_stress

    @classmethod
    def pack(cls, p):
        alpha, kc = dp_coefficients(p.friction_angle, p.cone, p.dilation_angle)
        alpha0, kc0 = dp_coefficients(p.friction_angle, p.cone, 0.0)
        beta, _ = dp_coefficients(p.dilation_angle, p.cone)
        k = kc * p.cohesion
        apex = k / (3 * alpha) if alpha > 0 else np.inf
        tcut = apex if p.tension_cutoff is None else min(p.tension_cutoff, apex)
        return {**cls.elastic_pack(p), "alpha": alpha, "k": k, "beta": beta, "tension_cutoff": tcut,
                "dilation_cutoff": p.cutoff(), "alpha_isochoric": alpha0, "k_isochoric": kc0 * p.cohesion}

    @classmethod
    def example_params(cls):
        return cls.Params(density=2650.0, youngs_modulus=0.84e6, poisson_ratio=0.3, friction_angle=31.0,
                          cohesion=100.0, dilation_angle=5.0)
