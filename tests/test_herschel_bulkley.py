"""Herschel-Bulkley (materials/herschel_bulkley.py; issue 19, point 2, explicit integration) in steady
simple shear, against its closed form tau = tau_y + K gamma_dot^n (Herschel & Bulkley 1926).

Simple shear L = [[0, g, 0], 0, 0] gives gamma_dot = g and sigma_xy = mu_eff g (tests/test_fluid_laws.py).
With the Papanastasiou parameter M = 1e4 s the regularised yield term is within exp(-M gamma_dot) <=
e^-100 of tau_y from gamma_dot = 1e-2 s^-1, so |tau| must equal tau_y + K gamma_dot^n within 1 % over
gamma_dot = 1e-2 ... 1e3 s^-1 for n = 0.5, 1 and 1.5, as the issue asks; the cap mu_max = 1e7 Pa s is
above every mu_eff of that range.  Below the cap's rate the stress is mu_max gamma_dot, and the
explicit viscous limit uses the cap.
"""

import numpy as np
import pytest

from geompm.materials.herschel_bulkley import HerschelBulkley

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
