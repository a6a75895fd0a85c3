"""Axial vibration of a fixed-free elastic bar (cases/elastic_bar.json).

Closed form (1D continuum, nu = 0 so plane strain reduces to 1D):
v(x, t) = v0 cos(w1 t) sin(pi x / 2L), w1 = (pi / 2L) sqrt(E / rho), period
T1 = 4 L / sqrt(E / rho) = 10 s for L = 25 m, E = 100 Pa, rho = 1 kg/m3;
the centre-of-mass velocity is v_cm = v0 / (b1 L) cos(w1 t)
(tests/refdata/analytic_bar_axial_vibration_fixed_free.csv).
Checks: first-mode period within 2% and total (kinetic + strain) energy drift
below 1% over 3 periods, APIC with quadratic B-splines.
"""

import numpy as np

from tests.support.elastic_bar import run_bar


def test_first_mode_period_and_energy(refdata):
    period, exact, drift, t, vcm = run_bar()
    assert abs(period / exact - 1) < 0.02, f"period {period:.4f} s vs {exact:.4f} s"
    assert drift < 0.01, f"energy drift {drift:.4%} over 3 periods"

    ref = np.genfromtxt(refdata / "analytic_bar_axial_vibration_fixed_free.csv", delimiter=",", names=True,
                        skip_header=3)
    # over the first half period (before the 0.6% period error shifts the phase)
    # v_cm matches the closed form within 3% of its peak: amplitude and mode shape
    m = ref["t"] <= 5.0
    err = np.abs(np.interp(ref["t"][m], t, vcm) - ref["v_cm"][m]).max()
    assert err < 0.03 * ref["v_cm"][0], f"max v_cm error {err:.3e} m/s"
