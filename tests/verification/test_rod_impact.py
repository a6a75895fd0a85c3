"""The first-contact load of an elastic block on a rigid wall is rho c v H for 2 L / c, and the wall takes
2 m v (geompm/testing/verification/rod_impact.py: one-dimensional wave theory, de Saint-Venant's rod
impact; Graff 1975 section 1.4).  The spike a flow makes at first contact is this load: its height scales
with the wave speed c = sqrt(M / rho), i.e. with the square root of the stiffness (checked at E and 4 E).
Measured at h = 0.05 / 0.025 / 0.0125 m (docs/impact-forces.md): filtered peak +1.3 / +4.0 / +4.1 %
(the overshoot of the discrete wave front), impulse -3.4 / -1.8 / -0.9 %, duration 40 / 34 / 30 ms
against 27.3 ms."""

import pytest

from geompm.testing.verification.rod_impact import rod_impact


@pytest.fixture(scope="module")
def rod():
    return rod_impact(0.025)


def test_the_contact_load_is_the_acoustic_impedance_times_the_speed(rod):
    assert rod["filtered_peak"] == pytest.approx(rod["load"], rel=0.06)
    assert rod["raw_peak"] == pytest.approx(rod["load"], rel=0.06)


def test_the_wall_takes_twice_the_momentum(rod):
    assert rod["impulse_x"] == pytest.approx(rod["impulse_exact"], rel=0.03)
    assert rod["duration"] == pytest.approx(rod["duration_exact"], rel=0.3)


def test_the_spike_follows_the_stiffness(rod):
    """Four times E doubles c and the load; the impulse stays 2 m v."""
    stiff = rod_impact(0.025, E=8e6)
    assert stiff["filtered_peak"] / rod["filtered_peak"] == pytest.approx(2.0, rel=0.04)
    assert stiff["impulse_x"] == pytest.approx(rod["impulse_x"], rel=0.03)
