"""Bingham, Cross and the Tait EOS at a material point, against their formulas.

Simple shear: L = [[0, g, 0], [0, 0, 0], [0, 0, 0]] gives D'_xy = g/2, so the
shear rate gamma_dot = sqrt(2 D':D') = g and the shear stress sigma_xy = mu_eff g.
Formulas: source eqs. (2), (5), (6) (docs/source-study.md); Bingham
regularised after Papanastasiou (1987) J. Rheol. 31:385.
"""

import numpy as np
import pytest

from geompm.materials.bingham import Bingham
from geompm.materials.cross import Cross
from geompm.materials.newtonian import Newtonian
from geompm.backend.cpu_loops import law_wave_speed
from geompm.testing import update_stress

RATES = np.logspace(-6, 3, 46)


def _shear(mat, rates, rho=None):
    n = len(rates)
    L = np.zeros((n, 3, 3))
    L[:, 0, 1] = rates
    stress = np.zeros((n, 6))
    state = mat.initial_state(n)
    rho = np.full(n, mat.density) if rho is None else rho
    update_stress(mat, 1e-4, L, rho, stress, state)
    return stress, state


def test_bingham_viscosity_and_stress_over_nine_decades():
    p = Bingham.Params(density=2000.0, viscosity=2.0, yield_stress=100.0, regularisation_time=50.0,
                       sound_speed=30.0)
    stress, state = _shear(Bingham(p), RATES)
    mu = 2.0 + 100.0 * (1 - np.exp(-50.0 * RATES)) / RATES
    np.testing.assert_allclose(state[:, 0], RATES, rtol=1e-12)
    np.testing.assert_allclose(stress[:, 3], mu * RATES, rtol=1e-9)
    # above gamma_dot = 5/M the regularised law is the ideal Bingham law tau = tau_B + mu_B gamma_dot within 1%
    high = RATES >= 5.0 / 50.0
    np.testing.assert_allclose(stress[high, 3], 100.0 + 2.0 * RATES[high], rtol=1e-2)
    # at the smallest rate the stress stays finite and tends to zero (no division by zero)
    assert 0 < stress[0, 3] < 100.0 * 50.0 * 1e-6 * 1.001


def test_cross_viscosity_and_stress_over_nine_decades():
    p = Cross.Params(density=2650.0, viscosity_zero=500.0, viscosity_infinity=0.5, time_constant=2.0,
                     rate_exponent=0.8, sound_speed=30.0)
    stress, state = _shear(Cross(p), RATES)
    x = (2.0 * RATES) ** 0.8
    mu = (500.0 + x * 0.5) / (1 + x)
    np.testing.assert_allclose(state[:, 1], mu, rtol=1e-12)
    np.testing.assert_allclose(stress[:, 3], mu * RATES, rtol=1e-12)
    # shear thinning: mu_eff falls strictly from mu_0 towards mu_inf
    assert np.all(np.diff(state[:, 1]) < 0) and 0.5 < state[-1, 1] < state[0, 1] < 500.0


def test_cross_from_bingham_mapping_and_accuracy():
    """mu_inf = mu_B, mu_0 = 1e4 mu_inf, A = mu_0 / tau_B, m = 1 (source, after eq. 6).
    The Cross shear stress is Bingham's times 1 - 1/(1 + A gamma_dot) exactly, so it is within 5%
    for gamma_dot >= 19 tau_B / mu_0 (the '10 tau_B / mu_0' of the issue gives 9.1%)."""
    mu_b, tau_b = 1.2, 500.0
    p = Cross.Params(density=2650.0, sound_speed=30.0, from_bingham={"viscosity": mu_b, "yield_stress": tau_b})
    assert (p.viscosity_infinity, p.viscosity_zero, p.rate_exponent) == (1.2, 12000.0, 1.0)
    assert p.time_constant == pytest.approx(12000.0 / 500.0)
    stress, _ = _shear(Cross(p), RATES)
    bingham = tau_b + mu_b * RATES
    rel = stress[:, 3] / bingham - 1
    np.testing.assert_allclose(rel, -1 / (1 + p.time_constant * RATES), rtol=1e-9, atol=1e-12)
    above = RATES >= 19 * tau_b / p.viscosity_zero
    assert np.abs(rel[above]).max() < 0.05
    assert np.abs(rel[RATES >= 10 * tau_b / p.viscosity_zero]).max() > 0.05  # so 10x is not enough


def test_cross_rejects_mixed_forms():
    with pytest.raises(ValueError, match="either"):
        Cross.Params(density=1.0, sound_speed=1.0, viscosity_zero=1.0, from_bingham={"viscosity": 1, "yield_stress": 1})


@pytest.mark.parametrize("cls", [Newtonian, Bingham, Cross])
def test_tait_pressure_at_small_compression(cls):
    """rho = rho0 (1 + 1e-3): P = rho0 c^2 / r ((1 + 1e-3)^r - 1) (source eq. 5), for every fluid law."""
    mat = cls(cls.example_params())
    rho0, c, r = mat.density, mat.params.sound_speed, mat.params.eos_exponent
    stress, _ = _shear(mat, np.zeros(1), rho=np.array([rho0 * 1.001]))
    P = rho0 * c * c / r * (1.001 ** r - 1)
    np.testing.assert_allclose(stress[0, :3], -P, rtol=1e-12)
    assert law_wave_speed(mat, np.array([rho0 * 1.001])) == pytest.approx(c * 1.001 ** ((r - 1) / 2), rel=1e-12)


def test_cross_elastoviscoplastic_steady_shear_is_the_viscous_law():
    """Cross under the elasto-viscoplastic integration (Maxwell relaxation at the viscous rate, cross.evp_cross_stress): at a
    constant shear rate the stress converges to mu_eff(gamma_dot) gamma_dot (eq. 6) within 1 % from
    1e-3 to 1e3 s^-1 with G = 1e8 Pa (tau / G <= 1e-3), and the first step from rest is elastic,
    G gamma_dot dt / (1 + G dt / mu)."""
    p = Cross.Params(density=2650.0, viscosity_zero=500.0, viscosity_infinity=0.5, time_constant=2.0,
                     sound_speed=30.0, integration="elastoviscoplastic", shear_modulus=1e8)
    mat = Cross(p)
    assert mat.kinematic_viscosity() == 0.0
    for rate in (1e-3, 1e-1, 10.0, 1e3):
        mu = (500.0 + (2.0 * rate) * 0.5) / (1 + 2.0 * rate)
        L = np.zeros((1, 3, 3))
        L[0, 0, 1] = rate
        stress, state = np.zeros((1, 6)), mat.initial_state(1)
        for _ in range(60):
            update_stress(mat, mu / 1e8, L, np.full(1, 2650.0), stress, state)  # dt = lambda
        assert stress[0, 3] == pytest.approx(mu * rate, rel=0.01), rate
    # the first step from rest, dt = 1e-6 s (G dt = 100 Pa s): the trial q_tr = G gamma_dot dt = 100 Pa is
    # returned along q = q_tr - G dt gp with the viscosity at the viscous rate gp, q = mu_eff(gp) gp
    # (gp = 0.2248 1/s, q = 77.5 Pa); the viscosity at the total rate would give 100 / (1 + 100 / 167) = 62.5 Pa
    L = np.zeros((1, 3, 3))
    L[0, 0, 1] = 1.0
    stress, state = np.zeros((1, 6)), mat.initial_state(1)
    update_stress(mat, 1e-6, L, np.full(1, 2650.0), stress, state)
    tau = stress[0, 3]
    gp = (100.0 - tau) / 100.0
    assert tau == pytest.approx(gp * (500.0 + 2.0 * gp * 0.5) / (1.0 + 2.0 * gp), rel=1e-9)
    assert tau == pytest.approx(77.5, abs=0.1) and state[0, 1] == pytest.approx(tau / gp, rel=1e-9)


def test_cross_elastoviscoplastic_return_for_m_not_one():
    """m = 0.5 takes the bisection branch of cross.cross_plastic_rate: one step from rest, dt = 1e-6 s,
    G = 1e8 Pa, gamma_dot = 1 1/s, must satisfy both q = q_tr - G dt gp and q = mu_eff(gp) gp (eq. 6) to
    1e-9, and 0 < q < q_tr = 100 Pa."""
    p = Cross.Params(density=2650.0, viscosity_zero=500.0, viscosity_infinity=0.5, time_constant=2.0,
                     rate_exponent=0.5, sound_speed=30.0, integration="elastoviscoplastic", shear_modulus=1e8)
    L = np.zeros((1, 3, 3))
    L[0, 0, 1] = 1.0
    stress, state = np.zeros((1, 6)), Cross(p).initial_state(1)
    update_stress(Cross(p), 1e-6, L, np.full(1, 2650.0), stress, state)
    tau = stress[0, 3]
    gp = (100.0 - tau) / 100.0
    x = (2.0 * gp) ** 0.5
    assert 0.0 < tau < 100.0
    assert tau == pytest.approx(gp * (500.0 + x * 0.5) / (1.0 + x), rel=1e-9)
