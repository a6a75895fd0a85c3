"""Herschel-Bulkley (materials/herschel_bulkley.py; issue 19, point 2, explicit integration) in steady
simple shear, against its closed form tau = tau_y + K gamma_dot^n (Herschel & Bulkley 1926).

Simple shear L = [[0, g, 0], 0, 0] gives gamma_dot = g and sigma_xy = mu_eff g (tests/verification/test_fluid_laws.py).
With the Papanastasiou parameter M = 1e4 s the regularised yield term is within exp(-M gamma_dot) <=
e^-100 of tau_y from gamma_dot = 1e-2 s^-1, so |tau| must equal tau_y + K gamma_dot^n within 1 % over
gamma_dot = 1e-2 ... 1e3 s^-1 for n = 0.5, 1 and 1.5, as the issue asks; the cap mu_max = 1e7 Pa s is
above every mu_eff of that range.  Below the cap's rate the stress is mu_max gamma_dot, and the
explicit viscous limit uses the cap.
"""

import numpy as np
import pytest

from geompm.materials.herschel_bulkley import HerschelBulkley
from geompm.testing import update_stress

from .test_fluid_laws import _shear

RATES = np.logspace(-2, 3, 41)


@pytest.mark.parametrize("n", [0.5, 1.0, 1.5])
def test_simple_shear_follows_tau_y_plus_k_gamma_dot_to_the_n(n):
    p = HerschelBulkley.Params(density=1800.0, consistency=5.0, flow_index=n, yield_stress=50.0,
                               regularisation_time=1e4, max_viscosity=1e7, sound_speed=30.0)
    stress, state = _shear(HerschelBulkley(p), RATES)
    exact = 50.0 + 5.0 * RATES ** n
    rel = stress[:, 3] / exact - 1.0
    assert np.abs(rel).max() < 0.01, f"n = {n}: worst {rel[np.argmax(np.abs(rel))]:+.2e}"
    np.testing.assert_allclose(state[:, 0], RATES, rtol=1e-12)
    np.testing.assert_allclose(state[:, 1], stress[:, 3] / RATES, rtol=1e-12)


def test_the_cap_bounds_the_viscosity_and_sets_the_explicit_limit():
    p = HerschelBulkley.Params(density=1800.0, consistency=5.0, flow_index=0.5, yield_stress=50.0,
                               max_viscosity=1e3, sound_speed=30.0)
    mat = HerschelBulkley(p)
    rates = np.array([1e-6, 1e-3, 1.0])
    stress, state = _shear(mat, rates)
    # below yield (tau_y / mu_max = 0.05 1/s) the capped fluid is Newtonian at mu_max
    np.testing.assert_allclose(stress[:2, 3], 1e3 * rates[:2], rtol=1e-12)
    assert stress[2, 3] == pytest.approx(50.0 * (1 - np.exp(-100.0)) + 5.0, rel=1e-9)
    assert mat.kinematic_viscosity() == pytest.approx(1e3 / 1800.0)
    with pytest.raises(ValueError, match="needs max_viscosity"):
        HerschelBulkley.Params(density=1800.0, consistency=5.0, flow_index=1.5, yield_stress=50.0,
                               sound_speed=30.0)
    bingham_like = HerschelBulkley(HerschelBulkley.Params(density=1800.0, consistency=2.0, flow_index=1.0,
                                                          yield_stress=50.0, sound_speed=30.0))
    assert bingham_like.kinematic_viscosity() == pytest.approx((50.0 * 100.0 + 2.0) / 1800.0)


@pytest.mark.parametrize("n", [0.5, 1.0, 1.5])
def test_the_elastoviscoplastic_integration_reaches_the_same_steady_shear_stress(n):
    """Elasto-viscoplastic integration (fluid.evp_yield_stress: elastic trial, return to the flow
    surface tau = tau_y + K gp^n): under a constant shear rate the stress converges to the corotational
    (Jaumann) steady state, whose shear stress falls below the viscous law as the Weissenberg number
    Wi = tau / G grows (a Maxwell element: mu gamma_dot / (1 + Wi^2)).  With G = 2e7 Pa (Wi <= 0.008 on this
    range) the steady |tau| is tau_y + K gamma_dot^n within 1 % over gamma_dot = 1e-2 ... 1e3 s^-1.  With
    the default G = rho0 c^2 / 4 = 4.05e5 Pa and n = 1.5 at 1e3 s^-1 (tau = 1.6e5 Pa, Wi = 0.39) the
    shear stress is 15 % low (measured 0.846): G must be well above the largest shear stress
    (docs/materials.md)."""
    def steady(mat, G, rate, exact):
        lam = (exact / rate) / G  # Maxwell relaxation time mu / G [s]
        L = np.zeros((1, 3, 3))
        L[0, 0, 1] = rate
        stress = np.zeros((1, 6))
        state = mat.initial_state(1)
        for _ in range(80):
            update_stress(mat, lam, L, np.full(1, 1800.0), stress, state)  # dt = lambda
        return stress[0, 3]

    def law(G):
        return HerschelBulkley(HerschelBulkley.Params(
            density=1800.0, consistency=5.0, flow_index=n, yield_stress=50.0, regularisation_time=1e4,
            max_viscosity=1e7, sound_speed=30.0, integration="elastoviscoplastic", shear_modulus=G))
    stiff = law(2e7)
    assert stiff.kinematic_viscosity() == 0.0  # no explicit viscous limit
    for rate in RATES[::4]:
        exact = 50.0 + 5.0 * rate ** n
        assert steady(stiff, 2e7, rate, exact) == pytest.approx(exact, rel=0.01), (n, rate)
    G = 0.25 * 1800.0 * 30.0 ** 2
    exact = 50.0 + 5.0 * 1e3 ** n
    ratio = steady(law(None), G, 1e3, exact) / exact
    if n == 1.5:  # tau / G = 0.39: the rotation of the elastic stress takes 15 % off (measured 0.846)
        assert 0.80 < ratio < 0.90, ratio
    else:  # tau / G <= 4e-4
        assert ratio == pytest.approx(1.0, rel=0.01)
    # below yield a step is elastic: tau = G gamma_dot dt exactly (no creep), until tau reaches tau_y
    L = np.zeros((1, 3, 3))
    L[0, 0, 1] = 1.0
    stress = np.zeros((1, 6))
    mat = law(None)
    state = mat.initial_state(1)
    update_stress(mat, 1e-6, L, np.full(1, 1800.0), stress, state)
    assert stress[0, 3] == pytest.approx(G * 1e-6, rel=1e-12)
    for _ in range(200):  # 200 x 0.405 Pa: past the 50 Pa yield stress, then on the flow surface
        update_stress(mat, 1e-6, L, np.full(1, 1800.0), stress, state)
    assert 50.0 < stress[0, 3] < 50.0 + 5.0 * 1.0 ** n + 1e-9
