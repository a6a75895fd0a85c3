"""Drucker-Prager and Mohr-Coulomb at a material point, against closed-form yield points.

Path A (triaxial compression at constant volume): from isotropic stress -p0,
strain rate diag(-1, 1/2, 1/2) e_dot.  While elastic, the mean stress stays -p0
and s = G e diag(-2, 1, 1), so
  DP:  sqrt(J2) = sqrt3 G e  ->  yield at e_y = (3 alpha p0 + k) / (sqrt3 G)
  MC:  sigma_3 = -p0 - 2 G e, sigma_1 = sigma_2 = -p0 + G e
       ->  yield at e_y = 2 (p0 sin phi + c cos phi) / (G (3 - sin phi))
(de Souza Neto, Peric & Owen 2008, ch. 6 and 8).  The DP 'outer' cone
touches MC on triaxial compression, so both laws must yield at the same strain.
"""

import math

import numpy as np
import pytest

from geompm.testing import update_stress
from geompm.materials.drucker_prager import DruckerPrager, dp_coefficients
from geompm.materials.mohr_coulomb import MohrCoulomb

P0 = 5.0e4
N = 1


def _law(cls, **over):
    kw = dict(density=2000.0, youngs_modulus=1.0e7, poisson_ratio=0.3, friction_angle=30.0, cohesion=5.0e3,
              dilation_angle=0.0)
    kw.update(over)
    return cls(cls.Params(**kw))


def _drive(mat, rate, strain, steps=2000, stress0=None):
    """Integrate a constant velocity gradient ``rate`` (3x3) up to ``strain``; history of (e, stress)."""
    stress = np.zeros((N, 6)) if stress0 is None else stress0.copy()
    if stress0 is None:
        stress[:, :3] = -P0
    state = mat.initial_state(N)
    L = np.broadcast_to(rate, (N, 3, 3)).copy()
    dt = strain / steps
    hist = []
    for k in range(steps):
        update_stress(mat, dt, L, np.full(N, 2000.0), stress, state)
        hist.append(((k + 1) * dt, stress[0].copy(), state[0].copy()))
    return hist


def _dp_f(s, alpha, k):
    I1 = s[:3].sum()
    dev = s[:3] - I1 / 3
    return math.sqrt(0.5 * (dev ** 2).sum() + (s[3:] ** 2).sum()) + alpha * I1 - k


def _mc_f(s, phi, c):
    M = np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
    w = np.linalg.eigvalsh(M)
    sp = math.sin(math.radians(phi))
    return (w[2] - w[0]) + (w[2] + w[0]) * sp - 2 * c * math.cos(math.radians(phi))


TRIAX = np.diag([-1.0, 0.5, 0.5])


@pytest.mark.parametrize("cone", ["plane_strain", "outer", "inner", "middle"])
def test_dp_elastic_then_on_the_cone(cone):
    mat = _law(DruckerPrager, cone=cone)
    lam, G = mat.params.lame()
    alpha, kc = dp_coefficients(30.0, cone, 0.0)  # the cone for psi = 0, the law's flow rule here
    k = kc * 5.0e3
    e_y = (3 * alpha * P0 + k) / (math.sqrt(3) * G)
    for e, s, q in _drive(mat, TRIAX, 3 * e_y):
        if e < 0.999 * e_y:  # elastic: exactly the elastic solution
            np.testing.assert_allclose(s[:3], -P0 + G * e * np.array([-2.0, 1.0, 1.0]), rtol=1e-9)
            assert q[0] == 0.0
        elif e > 1.001 * e_y:  # plastic: on the cone
            assert abs(_dp_f(s, alpha, k)) <= 1e-8 * (abs(s).max() + k)
            assert q[0] > 0.0
            # psi = 0: no plastic volume change, so at constant volume the mean stress stays -p0
            assert q[1] == 0.0
            assert s[:3].mean() == pytest.approx(-P0, rel=1e-10)


def test_mc_elastic_then_on_the_hexagon_and_outer_dp_agrees():
    mc = _law(MohrCoulomb)
    dp = _law(DruckerPrager, cone="outer")
    lam, G = mc.params.lame()
    sp, cp = math.sin(math.radians(30)), math.cos(math.radians(30))
    e_y = 2 * (P0 * sp + 5.0e3 * cp) / (G * (3 - sp))
    hist_mc = _drive(mc, TRIAX, 3 * e_y)
    hist_dp = _drive(dp, TRIAX, 3 * e_y)
    first_plastic = {}
    for name, hist in (("mc", hist_mc), ("dp", hist_dp)):
        first_plastic[name] = next(e for e, s, q in hist if q[0] > 0)
    # both yield within one strain step of the closed-form e_y
    step = 3 * e_y / 2000
    assert abs(first_plastic["mc"] - e_y) <= step and abs(first_plastic["dp"] - e_y) <= step
    for e, s, q in hist_mc:
        if e > 1.001 * e_y:
            assert abs(_mc_f(s, 30.0, 5.0e3)) <= 1e-8 * (abs(s).max() + 5.0e3)
            assert q[1] == pytest.approx(0.0, abs=1e-15)
            assert s[:3].mean() == pytest.approx(-P0, rel=1e-9)


@pytest.mark.parametrize("cls", [DruckerPrager, MohrCoulomb])
def test_dilation_raises_confinement_at_constant_volume(cls):
    """psi > 0: plastic dilation at constant total volume compresses elastically: dI1 = -3 K eps_v^p."""
    mat = _law(cls, dilation_angle=10.0)
    lam, G = mat.params.lame()
    K = lam + 2 * G / 3
    e, s, q = _drive(mat, TRIAX, 0.05)[-1]
    assert q[1] > 0.0
    assert s[:3].sum() - (-3 * P0) == pytest.approx(-3 * K * q[1], rel=1e-9)


@pytest.mark.parametrize("cls,apex", [
    (DruckerPrager, lambda p: dp_coefficients(30.0, "plane_strain", 0.0)[1] * p.cohesion
     / (3 * dp_coefficients(30.0, "plane_strain", 0.0)[0])),
    (MohrCoulomb, lambda p: p.cohesion / math.tan(math.radians(p.friction_angle))),
])
def test_pure_tension_returns_to_the_apex(cls, apex):
    """Isotropic stretching: the stress ends at the apex, isotropic with mean stress c cot(phi) (MC)
    or k / (3 alpha) (DP), and does not move when stretched further."""
    mat = _law(cls)
    hist = _drive(mat, np.eye(3), 0.02, steps=200, stress0=np.zeros((N, 6)))
    for e, s, q in hist[100:]:
        np.testing.assert_allclose(s[:3], apex(mat.params), rtol=1e-10)
        assert np.abs(s[3:]).max() <= 1e-9 * apex(mat.params)


def test_dp_tension_cutoff_caps_the_mean_stress():
    mat = _law(DruckerPrager, tension_cutoff=1.0e3)
    e, s, q = _drive(mat, np.eye(3), 0.02, steps=200, stress0=np.zeros((N, 6)))[-1]
    assert s[:3].mean() == pytest.approx(1.0e3, rel=1e-12)


@pytest.mark.parametrize("psi", [30.0, 10.0, 0.0])
def test_plane_strain_dp_gives_the_mc_plane_strain_strength(psi):
    """Plane-strain biaxial compression, associated (psi = phi = 30 deg) and non-associated (psi = 10, 0 deg):
    eps_zz = 0, sigma_yy held at -p0 (lateral strain rate found by secant iteration each step), eps_xx
    compressed to 20% (non-associated flow approaches its limit state more slowly: at 5% the psi = 0 strength
    was still 0.11 % short).  At the limit state all stress rates vanish, so the plastic eps_zz rate is zero and the
    in-plane stresses of the plane_strain-matched DP satisfy Mohr-Coulomb:
    (sigma_1 - sigma_3) = -(sigma_1 + sigma_3) sin(phi) + 2 c cos(phi)  (Drucker & Prager 1952 for psi = phi;
    the non-associated match is derived in drucker_prager.py).  The associated match used with psi = 0 (geompm
    before issue 15) is 3.9 % weaker in (sigma_1 - sigma_3) here at psi = 0 (1.7 % at 10): this test then fails."""
    mat = _law(DruckerPrager, cone="plane_strain", dilation_angle=psi)
    stress = np.zeros((N, 6))
    stress[:, :3] = -P0
    state = mat.initial_state(N)
    rho = np.full(N, 2000.0)
    dt = 0.2 / 5000

    def trial(x):  # one step at lateral rate x; the density follows the volume, as in the engine
        s2, q2, r2 = stress.copy(), state.copy(), rho / (1.0 + (x - 1.0) * dt)
        update_stress(mat, dt, np.diag([-1.0, x, 0.0])[None].copy(), r2, s2, q2)
        return s2, q2, r2

    for _ in range(5000):
        x0, x1 = 0.0, 1.0
        f0 = trial(x0)[0][0, 1] + P0
        for _ in range(30):
            f1 = trial(x1)[0][0, 1] + P0
            if abs(f1) < 1e-9 * P0 or f1 == f0:
                break
            x0, x1, f0 = x1, x1 - f1 * (x1 - x0) / (f1 - f0), f1
        stress, state, rho = trial(x1)
    s = stress[0]
    assert s[1] == pytest.approx(-P0, rel=1e-8)
    s1, s3 = s[1], s[0]  # sigma_xx is the most compressive
    sp, cp = math.sin(math.radians(30)), math.cos(math.radians(30))
    strength = -(s1 + s3) * sp + 2 * 5.0e3 * cp
    # psi = 0: exact (measured 3e-10).  psi > 0: the sample keeps dilating at the limit state, so the Kirchhoff
    # stress J sigma of the law (plasticity.current_moduli) keeps changing at a stationary sigma; the elastic
    # eps_zz rate that goes with it is of order sigma / E (1e-2 here) of the plastic one, and the limit state is
    # MC's to that order times the dilation (measured 3.2e-4 at psi = 10, 4e-5 at 30; 1.7 % with the old alpha).
    assert (s1 - s3) == pytest.approx(strength, rel=1e-6 if psi == 0.0 else 1e-3)
    assert s3 < s[2] < s1  # sigma_zz is the intermediate principal stress


@pytest.mark.parametrize("cls", [DruckerPrager, MohrCoulomb])
def test_psi0_volume_gain_is_separation_at_the_apex(cls):
    """Why a cohesionless soil at psi = 0 shows plastic_volumetric_strain > 0 (the main job reached 1.6 and
    81 kg/m3): the law never dilates in shear, but a particle whose neighbours move apart is stretched past
    the apex (zero stress for c = 0), and that stretch is booked as plastic volume.

    (1) Triaxial shear under 50 kPa at psi = 0: plastic_strain grows, plastic_volumetric_strain stays 0
        (below 1e-12).
    (2) Isotropic stretching of the same c = 0 soil from rest at zero stress: the stress stays 0 and
        plastic_volumetric_strain equals the volume strain imposed, sum tr(D) dt = 3 x 0.02 (relative 1e-9),
        which is ln(V/V0) to first order.  docs/materials.md ("Plastic volume at psi = 0") explains it."""
    mat = _law(cls, cohesion=0.0)
    e, s, q = _drive(mat, TRIAX, 0.05)[-1]
    assert q[0] > 0.01 and abs(q[1]) < 1e-12
    hist = _drive(mat, np.eye(3), 0.02, steps=200, stress0=np.zeros((N, 6)))
    e, s, q = hist[-1]
    assert np.abs(s).max() == 0.0
    assert q[1] == pytest.approx(3 * 0.02, rel=1e-9)
