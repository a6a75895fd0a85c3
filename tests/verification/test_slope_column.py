"""The infinite slope's reference without the MPM (geompm/testing/verification/slope_column.py).

A one-dimensional column in simple shear, run with the strength-reduction trial's schedule, damping and
criterion and the law's own return, gives the factor a trial of finite length can reach.  Checked against the
closed forms where they apply (Taylor 1948 for associated flow, tan(phi)/tan(beta); Davis 1968 for psi = 0,
sin(phi_F) = tan(beta)) and for convergence in its element count; a trial of 2 s on a steep slope stops short
of the closed form by a few per cent (the transient), which the same column with longer trials removes.
"""

from __future__ import annotations

import math

import pytest

from geompm.materials.drucker_prager import DruckerPrager
from geompm.materials.mohr_coulomb import MohrCoulomb
from geompm.testing.verification.slope_column import column_factor

SOIL = dict(density=2000.0, youngs_modulus=2e6, poisson_ratio=0.3, friction_angle=30.0, cohesion=0.0,
            dilation_cutoff=1.0)
DAVIS = math.tan(math.radians(30.0)) / math.tan(math.asin(math.tan(math.radians(20.0))))  # 1.4775
ASSOCIATED = math.tan(math.radians(30.0)) / math.tan(math.radians(20.0))  # 1.5863


@pytest.mark.parametrize("law", [MohrCoulomb, DruckerPrager])
def test_psi_zero_column_converges_to_davis(law):
    """psi = 0, beta = 20 deg, phi = 30 deg, T = 2 s: the factor at 10, 20 and 40 elements is one (a uniform
    column has no spatial error beyond its base), within 1 % of Davis's 1.4775, and below the associated
    soil's (1.5863) by more than 5 %."""
    params = dict(SOIL, dilation_angle=0.0)
    f = [column_factor(law, params, low=1.3, high=1.7, elements=n)[0] for n in (10, 20, 40)]
    assert max(f) - min(f) < 2e-3 * f[0]
    assert f[-1] == pytest.approx(DAVIS, rel=0.01)
    assert f[-1] < 0.95 * ASSOCIATED


def test_associated_column_meets_taylor():
    """Associated flow (psi = phi = 30 deg): within 1.5 % of tan(phi)/tan(beta) at T = 2 s, as the MPM's
    associated slope is (+0.7 %, docs/slope-stability.md)."""
    f, _ = column_factor(MohrCoulomb, dict(SOIL, dilation_angle=30.0), low=1.3, high=1.8, elements=20)
    assert f == pytest.approx(ASSOCIATED, rel=0.015)


def test_steep_slope_trial_bias_shrinks_with_the_trial():
    """beta = 36 deg, phi = psi = 40 deg: tan(phi)/tan(beta) = 1.1547.  A 2 s trial stops 2-4 % short of it
    (the soil near its limit still slows when the trial ends), an 8 s trial within 0.5 %: the steep slope's
    reference for the default trial is the column's, not the closed form."""
    params = dict(SOIL, friction_angle=40.0, dilation_angle=40.0)
    closed = math.tan(math.radians(40.0)) / math.tan(math.radians(36.0))
    short, _ = column_factor(DruckerPrager, params, low=0.8, high=1.6, elements=20, slope=36.0, duration=2.0)
    long, _ = column_factor(DruckerPrager, params, low=0.8, high=1.6, elements=20, slope=36.0, duration=8.0)
    assert -0.04 < short / closed - 1.0 < -0.02
    assert long == pytest.approx(closed, rel=0.005)


def test_regularisation_moves_the_column_little():
    """The trials' default Duvaut-Lions time (T/800 = 2.5 ms) moves the psi = 0 column's factor by less than
    0.5 % (kernels/viscoplastic.py: the overstress vanishes as the flow slows)."""
    params = dict(SOIL, dilation_angle=0.0)
    f0, _ = column_factor(MohrCoulomb, params, low=1.3, high=1.7, elements=20)
    f1, _ = column_factor(MohrCoulomb, params, low=1.3, high=1.7, elements=20, viscoplastic_time=0.0025)
    assert abs(f1 / f0 - 1.0) < 0.005
