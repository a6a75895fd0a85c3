"""The impact quantities of a force history (geompm/contact/impact.py) against histories whose moving
average, peak and impulse are known exactly."""

import numpy as np
import pytest

from geompm.contact.impact import SNAPSHOTS, WINDOW_SHARE, WINDOW_SHARE_OF_END, ImpactRecord


def _feed(rec, force_of_t, t_end, dt, faces=None):
    for i in range(int(round(t_end / dt))):
        t = i * dt
        rec.step(np.asarray(force_of_t(t), float), dt, t, None if faces is None else faces(t))


def test_a_plateau_longer_than_the_window_is_its_filtered_peak():
    """A force of (300, -400) N (|F| = 500 N) from t = 1 s to 1.5 s, zero before and after, window 0.05 s:
    the moving average reaches 500 N exactly and holds it; the impulse is 500 N x 0.5 s = 250 N s; after the
    plateau the window average falls to 0 (the load at the end)."""
    rec = ImpactRecord(2, 0.05, 3.0)
    _feed(rec, lambda t: (300.0, -400.0) if 1.0 - 1e-9 <= t < 1.5 - 1e-9 else (0.0, 0.0), 2.0, 1e-3)
    rep = rec.report()
    assert rep["first_contact"] == pytest.approx(1.0, abs=1e-9)
    assert rep["filtered_peak_force"] == pytest.approx(500.0, rel=1e-9)
    assert rep["impulse"] == pytest.approx(250.0, rel=1e-6)
    assert rep["final_force"] == pytest.approx(0.0, abs=1e-9)
    assert rep["impulse_vector"] == pytest.approx([150.0, -200.0], rel=1e-6)


def test_a_spike_shorter_than_the_window_counts_by_its_impulse():
    """A 1 ms spike of 1e5 N (impulse 100 N s) on a 1 kN plateau, window 0.1 s: the raw peak is 101 kN,
    the filtered peak is 1 kN + 100 N s / 0.1 s = 2 kN (to the snapshot interpolation, window / 20)."""
    rec = ImpactRecord(2, 0.1, 3.0)
    _feed(rec, lambda t: (1e3 + (1e5 if 0.5 - 1e-9 <= t < 0.501 - 1e-9 else 0.0), 0.0) if t >= 0.2 - 1e-9 else (0.0, 0.0),
          1.0, 1e-4)
    assert rec.report()["filtered_peak_force"] == pytest.approx(2000.0, rel=2e-3)


def test_the_default_window_is_a_share_of_the_travel_time():
    """No force_window: T_w = WINDOW_SHARE x the time of first contact; contact at t = 0: WINDOW_SHARE_OF_END
    x the end time."""
    rec = ImpactRecord(3, None, 10.0)
    _feed(rec, lambda t: (1.0, 0.0, 0.0) if t >= 0.8 - 1e-12 else (0.0, 0.0, 0.0), 1.0, 1e-3)
    assert rec.window == pytest.approx(WINDOW_SHARE * 0.8, rel=1e-9)
    rec0 = ImpactRecord(3, None, 10.0)
    _feed(rec0, lambda t: (1.0, 0.0, 0.0), 0.01, 1e-3)
    assert rec0.window == pytest.approx(WINDOW_SHARE_OF_END * 10.0)


def test_a_ramp_is_averaged_over_the_window_exactly():
    """F = 1000 t N from first contact: the moving average at t is 1000 (t - T_w / 2), the window's
    centre; J is integrated per step (rectangles of F at the step's start), so the average lags by dt / 2."""
    dt, T = 1e-4, 0.02
    rec = ImpactRecord(2, T, 1.0)
    _feed(rec, lambda t: (1000.0 * t, 0.0) if t > 0 else (0.0, 0.0), 0.5, dt)
    assert rec.peak[0] == pytest.approx(1000.0 * (0.5 - T / 2 - dt / 2), rel=1e-3 / SNAPSHOTS)


def test_face_pressures_at_the_filtered_peak():
    """Two faces of 0.5 and 2 m2 carrying 100 N and 400 N of normal force over the peak's window: 200 Pa
    each."""
    rec = ImpactRecord(2, 0.05, 1.0, face_area=np.array([0.5, 2.0]))
    _feed(rec, lambda t: (500.0, 0.0) if t >= 0.1 else (0.0, 0.0), 0.4, 1e-3,
          faces=lambda t: np.array([100.0, 400.0]) if t >= 0.1 else np.zeros(2))
    assert rec.face_pressure_at_peak == pytest.approx([200.0, 200.0], rel=1e-9)


def test_the_state_carries_over_a_restart():
    """Stopping mid-history and loading the state into a fresh record gives the same numbers to the bit."""
    f = lambda t: (np.sin(30 * t) ** 2 * 1e3, 50.0) if t > 0.05 else (0.0, 0.0)  # noqa: E731
    whole = ImpactRecord(2, None, 1.0)
    _feed(whole, f, 0.6, 1e-3)
    first = ImpactRecord(2, None, 1.0)
    _feed(first, f, 0.3, 1e-3)
    second = ImpactRecord(2, None, 1.0)
    second.load_state(first.state_dict())
    for i in range(300, 600):
        second.step(np.asarray(f(i * 1e-3), float), 1e-3, i * 1e-3)
    a, b = second.report(), whole.report()
    assert a == b
