"""Critical-state laws in single elements against their closed forms (docs/materials.md).

Modified Cam-Clay (materials/modified_cam_clay.py) from a normally consolidated isotropic state p0 (Wood 1990,
Soil Behaviour and Critical State Soil Mechanics, sec. 7.3-7.4, in the log-log indices lambda*, kappa*):
- undrained triaxial: every step on p / p0 = (M^2 / (M^2 + eta^2))^Lambda, Lambda = 1 - kappa*/lambda*, and at
  large strain the critical state q = M p' with p'_cs = p0 / 2^Lambda;
- drained triaxial at constant cell pressure: every step on eps_v = kappa* ln(p / p0)
  + (lambda* - kappa*) ln(p (M^2 + eta^2) / (M^2 p0)), approaching p_cs = 3 p0 / (3 - M), q = M p_cs.
Both within 1e-6 relative at any step size (the return is exact in ln p and ln p_c).

Critical-state sand (materials/critical_state_sand.py; Roux & Radjai 1998, Pailha & Pouliquen 2009):
- drained simple shear at constant normal stress: a loose (0.55) and a dense (0.61) sample reach the critical
  solid fraction 0.58 and the critical stress ratio tau / sigma'_n = sin(phi_cs) (isochoric plane-strain flow
  on the matched cone), the loose one contracting, the dense one dilating;
- undrained simple shear through the two-phase step's own water passes (pressure_increment_one,
  add_increment_one, porosity_one; water K_w = 2.2 GPa, sealed): the loose sample loses its effective stress
  (static liquefaction) and the dense one gains it, each at the rate the cone gives for isochoric shear from an
  isotropic start, d sigma'_n / d gamma = -3 K G beta / (G + 9 K alpha beta) (derived in docs/materials.md),
  within 2 %; the pore pressure takes what the skeleton loses.
"""

import math

import numpy as np
import pytest

from geompm.materials.critical_state_sand import CriticalStateSand, css_stress
from geompm.materials.drucker_prager import dp_cone
from geompm.materials.modified_cam_clay import ModifiedCamClay, mcc_stress
from geompm.materials.plasticity import lame_constants
from geompm.testing.verification.element_paths import simple_shear, triaxial, water_row

P0 = 100e3
CLAY = dict(density=1800.0, poisson_ratio=0.3, critical_friction_angle=25.0, compression_index=0.2,
            swelling_index=0.04, void_ratio=1.0)


def clay():
    law = ModifiedCamClay(ModifiedCamClay.Params(**CLAY))
    p = law.params
    return law, p.m_ratio(), p.compression_index / (1 + p.void_ratio), p.swelling_index / (1 + p.void_ratio)


@pytest.mark.parametrize("steps", [50, 2000])
def test_mcc_undrained_triaxial_follows_the_closed_form_path(steps):
    law, M, lam, kap = clay()
    rows = triaxial(mcc_stress, law.prm, P0, 1800.0, 0.2, steps, drained=False)
    p, q = rows[:, 2], rows[:, 3]
    eta = q / p
    closed = P0 * (M * M / (M * M + eta ** 2)) ** (1 - kap / lam)
    plastic = rows[:, 6] > P0 * (1 + 1e-12)  # p_c has grown: on the yield surface
    assert plastic.sum() > 0.9 * steps
    assert np.abs(p[plastic] / closed[plastic] - 1).max() < 1e-6
    p_cs = P0 * 0.5 ** (1 - kap / lam)
    assert abs(p[-1] / p_cs - 1) < 1e-4 and abs(q[-1] / (M * p[-1]) - 1) < 1e-4


@pytest.mark.parametrize("steps", [40, 400])
def test_mcc_drained_triaxial_follows_the_closed_form_volume_change(steps):
    law, M, lam, kap = clay()
    rows = triaxial(mcc_stress, law.prm, P0, 1800.0, 1.0, steps, drained=True)
    ev, p, q = rows[:, 1], rows[:, 2], rows[:, 3]
    eta = q / p
    assert np.abs(p - (P0 + q / 3)).max() < 1e-8 * P0  # the drained path dp = dq / 3
    closed = kap * np.log(p / P0) + (lam - kap) * np.log(p * (M * M + eta ** 2) / (M * M * P0))
    assert np.abs(ev / closed - 1).max() < 1e-6
    p_cs = 3 * P0 / (3 - M)
    assert abs(p[-1] / p_cs - 1) < 0.005 and abs(eta[-1] / M - 1) < 0.01


def test_mcc_overconsolidated_start_is_elastic_then_yields_at_the_ellipse():
    """OCR 2: undrained, the path is vertical (p constant, elastic) until q^2 = M^2 p (p_c - p), then leaves it."""
    law = ModifiedCamClay(ModifiedCamClay.Params(**CLAY, overconsolidation_ratio=2.0))
    M = law.params.m_ratio()
    rows = triaxial(mcc_stress, law.prm, P0, 1800.0, 0.05, 500, drained=False)
    p, q = rows[:, 2], rows[:, 3]
    first = int(np.argmax(rows[:, 4] > 0))  # first plastic step
    assert np.abs(p[:first] / P0 - 1).max() < 1e-12
    q_yield = M * math.sqrt(P0 * (2 * P0 - P0))
    assert q[first - 1] <= q_yield * (1 + 1e-9) and q[first] > 0.99 * q_yield


def sand(phi0, saturated=False, E=5e6):
    p = CriticalStateSand.Params(density=2650.0 if saturated else 2650.0 * phi0, youngs_modulus=E, poisson_ratio=0.3,
                                 critical_friction_angle=30.0, critical_solid_fraction=0.58,
                                 dilatancy_coefficient=4.09, solid_fraction=None if saturated else phi0)
    return CriticalStateSand(p.with_porosity(1 - phi0) if saturated else p)


@pytest.mark.parametrize("phi0", [0.55, 0.61])
def test_sand_drained_shear_reaches_the_critical_state(phi0):
    law = sand(phi0, E=5e7)
    rows = simple_shear(css_stress, law.prm, law.params.density, 20e3, 2.0, 2000, state=[0, 0, phi0])
    ev, ratio, phi = rows[:, 1], rows[:, 3] / rows[:, 2], rows[:, -1]
    assert abs(phi[-1] - 0.58) < 0.001
    assert abs(ratio[-1] / math.sin(math.radians(30.0)) - 1) < 0.01
    if phi0 < 0.58:
        assert ev[-1] > 0.04  # contracted: ln(0.58 / 0.55) = 0.053
        assert ratio.max() < 0.5 * 1.005  # no peak above critical
    else:
        assert ev[-1] < -0.04  # dilated
        assert ratio.max() > 0.52  # the dense peak


@pytest.mark.parametrize("phi0", [0.55, 0.61])
def test_sand_undrained_shear_liquefies_loose_and_strengthens_dense(phi0):
    E, nu = 5e6, 0.3
    law = sand(phi0, saturated=True, E=E)
    rows = simple_shear(css_stress, law.prm, law.params.density, 20e3, 0.05, 1000, k0=1.0, state=[0, 0, phi0],
                        water=water_row(2.2e9, 1 - phi0), porosity=1 - phi0)
    g, sn, pw = rows[:, 0], rows[:, 2], rows[:, 4]
    assert np.abs(sn + pw - 20e3).max() < 1e-6 * 20e3  # the total normal stress held
    tan_psi = 4.09 * (phi0 - 0.58)
    tan_phi = math.tan(math.radians(30.0)) + tan_psi
    c = 1 / math.sqrt(1 + tan_phi ** 2)
    alpha, _, beta = dp_cone(tan_phi * c, c, tan_psi / math.sqrt(1 + tan_psi ** 2), 0)
    lam, G = lame_constants(E, nu)
    K = lam + 2 * G / 3
    rate = 3 * K * G * beta / (G + 9 * K * alpha * beta)
    flowing = (g > 0.01) & (sn > 0.1 * 20e3)
    measured = np.gradient(sn, g)[flowing]
    assert flowing.sum() > 100
    assert np.abs(measured / rate - 1).max() < 0.02
    if phi0 < 0.58:
        assert sn[-1] < 1e-6 * 20e3 and pw[-1] == pytest.approx(20e3, rel=1e-6)  # liquefied
    else:
        assert sn[-1] > 1.9 * 20e3 and pw[-1] < -0.9 * 20e3  # suction carries the gain
