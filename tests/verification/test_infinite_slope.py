"""Factor of safety of an infinite slope by strength reduction, at three cell sizes, against the closed form.

A periodic strip 1 m deep on a fixed base with gravity tilted by beta = 20 deg (geompm/testing/verification/slopes.py),
phi = 30 deg, associated flow (psi = phi, so the slip plane carries tan(phi): Davis 1968), gamma =
2000 x 9.81 N/m3.  Limit equilibrium of the slope-parallel plane at the base (Taylor 1948, ch. 16):

    c = 0:       F = tan(phi) / tan(beta) = 1.5863
    c = 2 kPa:   F = c / (gamma z cos^2(beta) tan(beta)) + tan(phi) / tan(beta) = 1.9034

The issue's tolerance is 3 %: at h = 0.1, 0.05 and 0.025 m the trial of `geompm stability` (trial.py: the
strength ramped from F = 1 to F, viscous damping, 2 s) must stand at 0.97 F and fail at 1.03 F, so that the
factor the search would bracket lies within 3 % of the closed form.  The full searches at h = 0.1, 0.05 and
0.025 m are in docs/slope-stability.md (benchmarks/results/2026-12-04-slope-stability/infinite-slope.txt)."""

from __future__ import annotations

import pytest

import geompm
from geompm.schema.load import parse_case
from geompm.stability import criterion
from geompm.stability.trial import trial_damping, trial_sets
from geompm.testing.verification.slopes import infinite_slope_case, limit_equilibrium

pytestmark = pytest.mark.slow


def _trial(tmp_path, h, cohesion, factor):
    raw = infinite_slope_case(h, cohesion=cohesion)
    loaded = parse_case(raw)
    sets = trial_sets(loaded, factor, 2.0, trial_damping(loaded, 20.0, 0.0))
    run = geompm.run(raw, out=tmp_path / f"h{h:g}_c{cohesion:g}_F{factor:.4f}", overrides=sets, progress=False,
                     quiet=True)
    assert run.exit_code == 0
    return criterion.judge(run.series, criterion.DEFAULT_RATIO, criterion.FLOOR_CELLS * h)


@pytest.mark.parametrize("cohesion", [0.0, 2000.0])
@pytest.mark.parametrize("h", [0.1, 0.05, 0.025])
def test_infinite_slope_stands_below_and_fails_above_three_percent(tmp_path, h, cohesion):
    ref = limit_equilibrium(20.0, 30.0, cohesion)
    below, above = _trial(tmp_path, h, cohesion, 0.97 * ref), _trial(tmp_path, h, cohesion, 1.03 * ref)
    assert not below["failed"], below
    assert above["failed"], above
