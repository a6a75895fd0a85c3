"""A steady inflow down a Voellmy bed reaches the steady depth of the law (geompm/testing/verification/
voellmy_inflow.py): q = 0.5 m2/s enters 1.25 times faster than the normal speed on a 30 deg bed (mu 0.2,
xi 100 m/s2); 4 m downstream its depth and speed, averaged over 2.5-4 s, match the uniform steady flow of a
viscous layer on Voellmy's law, h* = 0.1939 m (the plug's h_n = 0.1970 m, Salm 1993), and the injected volume
is the hydrograph's integral.  Measured at h = 0.05 / 0.025 / 0.0125 m in
benchmarks/results/2026-12-06-issue58/steady-inflow.txt."""

import pytest

from geompm.testing.verification.voellmy_inflow import Q, run_inflow, viscous_depth


@pytest.mark.slow
def test_a_steady_inflow_reaches_the_voellmy_depth():
    means, (vin, vt, vp, held) = run_inflow(0.05)
    depth, speed = means[4.0]
    assert depth == pytest.approx(viscous_depth(), rel=0.01)
    assert speed == pytest.approx(Q / viscous_depth(), rel=0.01)
    assert depth * speed == pytest.approx(Q, rel=0.005)  # the discharge passes the probe
    assert vt - vp < vin <= vt * (1 + 1e-12) and held == pytest.approx(vin, rel=1e-12)
