"""Factor of safety of finite slopes by strength reduction against Bishop's simplified method.

The geometry of Griffiths & Lane's (1999, Geotechnique 49(3):387) first example: a 2:1 slope 10 m high on a
rough rigid base at the toe's level (geompm/testing/verification/slopes.griffiths_lane_case, drucker_prager with its
plane-strain cone, psi = 0, gamma = 20 kN/m3), with their soil (c' = 10 kPa, phi' = 20 deg) and an
undrained one (c_u = 50 kPa, phi = 0).  The reference is Bishop's simplified method over circles
(geompm/testing/verification/bishop.py, checked in tests/unit/test_bishop.py): 1.378 and 2.022.

A third soil, c' = 5 kPa and phi' = 30 deg (Bishop 1.606), is tested at h = 0.25 m, where its search gave +0.63 %
(at 0.5 m, +4.67 %, too close to the 5 % edge for a test).

At h = 0.5 m the trial of `geompm stability` must stand at 0.95 F and fail at 1.05 F (the issue's 5 %); the
searches at h = 1, 0.5 and 0.25 m (+11.2 / +4.2 / +0.6 %, +7.4 / +2.8 / +0.05 % and +8.7 / +4.7 / +0.6 %,
converging) are in docs/slope-stability.md (benchmarks/results/2026-12-04-slope-stability/griffiths-lane.txt,
benchmarks/slope_stability/finite_slope.py)."""

from __future__ import annotations

import numpy as np
import pytest

import geompm
from geompm.schema.load import parse_case
from geompm.stability import criterion
from geompm.stability.trial import trial_damping, trial_sets
from geompm.testing.verification.bishop import critical_circle, surface_from_points
from geompm.testing.verification.slopes import griffiths_lane_case

pytestmark = pytest.mark.slow
H = 0.5


def _bishop(c, phi):
    s = surface_from_points([-100.0, 12.0, 32.0, 200.0], [10.0, 10.0, 0.0, 0.0])
    return critical_circle(s, c, phi, 20000.0, (np.linspace(0, 40, 11), np.linspace(5, 40, 11)),
                           np.linspace(5, 50, 16), base=0.0, lo=0.0, hi=200.0)[0]


@pytest.mark.parametrize("c, phi, h", [(1.0e4, 20.0, H), (5.0e4, 0.0, H), (5.0e3, 30.0, 0.25)])
def test_slope_stands_below_and_fails_above_five_percent_of_bishop(tmp_path, c, phi, h):
    _stands_below_fails_above(tmp_path, c, phi, h, "drucker_prager", None)


@pytest.mark.parametrize("h", [1.0, 0.5])
def test_mohr_coulomb_psi_zero_slope_with_the_trials_regularisation(tmp_path, h):
    """Griffiths & Lane's soil (c' = 10 kPa, phi' = 20 deg, psi = 0) with `mohr_coulomb` under the trials'
    default Duvaut-Lions time (T/800): within 7.5 % of Bishop at h = 1 m and 5 % at h = 0.5 m, the search
    giving +5.95 / +1.47 / -0.33 % at h = 1 / 0.5 / 0.25 m (docs/slope-stability.md; before the regularisation
    Mohr-Coulomb with psi = 0 was not claimed on finite slopes)."""
    _stands_below_fails_above(tmp_path, 1.0e4, 20.0, h, "mohr_coulomb", 3.0 / 800.0, 0.075 if h == 1.0 else 0.05)


def _stands_below_fails_above(tmp_path, c, phi, h, model, relaxation, margin=0.05):
    ref = _bishop(c, phi)
    raw = griffiths_lane_case(h, friction=phi, cohesion=c, model=model)
    loaded = parse_case(raw)
    out = {}
    for f in ((1.0 - margin) * ref, (1.0 + margin) * ref):
        sets = trial_sets(loaded, f, 3.0, trial_damping(loaded, 40.0 / 3.0, 0.0), relaxation)
        run = geompm.run(raw, out=tmp_path / f"F{f:.4f}", overrides=sets, progress=False, quiet=True)
        assert run.exit_code == 0
        out[f] = criterion.judge(run.series, criterion.DEFAULT_RATIO, criterion.FLOOR_CELLS * h)
    below, above = out[(1.0 - margin) * ref], out[(1.0 + margin) * ref]
    assert not below["failed"], below
    assert above["failed"], above
