"""Infinite slopes under a water table (triggers.water_table), at three cell sizes, against limit equilibrium.

The periodic strip of geompm/testing/verification/slopes.py (1 m deep on a fixed base, gravity tilted by beta = 20 deg,
rho_sat = 2000 kg/m3, associated Drucker-Prager, c = 0) under a water table parallel to its surface, so the
pore pressure is that of slope-parallel seepage, gamma_w z cos^2(beta) (rho_w = 1000 kg/m3).  Limit
equilibrium of the base (Skempton & DeLory 1957; Duncan, Wright & Brandon 2014, Soil Strength and Slope
Stability, 2nd ed., sec. 6.2):

- the table at the surface, phi = 40 deg: F = (gamma' / gamma_sat) tan(phi) / tan(beta) = 1.1527.  At h = 0.1,
  0.05 and 0.025 m the strength-reduction trial (trial.py, 2 s) must stand at 0.97 F and fail at 1.03 F (the
  issue's 3 %); the searches gave 1.1389 at all three (-1.2 %, docs/slope-stability.md);
- the table rising through a slope of phi = 30 deg at 0.1 m/s: F(h_w) = (1 - rho_w h_w / (rho H)) tan(phi) /
  tan(beta) reaches 1 at h_w = 0.739 m.  The onset, the zero of the slide's speed extrapolated along its
  linear growth (geompm/testing/verification/slopes.onset_from_velocity), must put the table within 3 % of that height;
  measured -0.43 / -0.45 / +0.32 %.
"""

from __future__ import annotations

import pytest

import geompm
from geompm.schema.load import parse_case
from geompm.stability import criterion
from geompm.stability.trial import trial_damping, trial_sets
from geompm.testing.verification.slopes import (critical_table, onset_from_velocity, rising_table_case,
                                  saturated_infinite_slope_case, saturated_limit_equilibrium)

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("h", [0.1, 0.05, 0.025])
def test_saturated_infinite_slope_stands_below_and_fails_above_three_percent(tmp_path, h):
    ref = saturated_limit_equilibrium(20.0, 40.0)
    assert ref == pytest.approx(1.1527, abs=1e-4)
    raw = saturated_infinite_slope_case(h)
    loaded = parse_case(raw)
    verdicts = []
    for factor in (0.97 * ref, 1.03 * ref):
        sets = trial_sets(loaded, factor, 2.0, trial_damping(loaded, 20.0, 0.0))
        run = geompm.run(raw, out=tmp_path / f"F{factor:.4f}", overrides=sets, progress=False, quiet=True)
        verdicts.append(criterion.judge(run.series, criterion.DEFAULT_RATIO, criterion.FLOOR_CELLS * h))
    below, above = verdicts
    assert not below["failed"], below
    assert above["failed"], above


@pytest.mark.parametrize("h", [0.1, 0.05, 0.025])
def test_rising_table_starts_the_slide_within_three_percent_of_limit_equilibrium(tmp_path, h):
    start, first, stop, last = 0.5, 0.55, 5.0, 1.0  # the table from 0.55 m at 0.5 s to 1.0 m at 5 s
    run = geompm.run(rising_table_case(h, rise=(start, first, stop, last), end=3.6), out=tmp_path / "run",
                     progress=False, quiet=True)
    assert run.exit_code == 0
    onset = onset_from_velocity(run.series, after=start)
    height = first + (last - first) * (onset - start) / (stop - start)
    critical = critical_table(20.0, 30.0)
    assert critical == pytest.approx(0.7392, abs=1e-4)
    assert height == pytest.approx(critical, rel=0.03)
    # the series records the table: its column follows the schedule
    t = run.series["time"][-1]
    assert run.series["water_table"][-1] == pytest.approx(first + (last - first) * (t - start) / (stop - start))
