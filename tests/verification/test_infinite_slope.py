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


def _trial(tmp_path, h, cohesion, factor, relaxation=None, **kw):
    raw = infinite_slope_case(h, cohesion=cohesion, **kw)
    loaded = parse_case(raw)
    sets = trial_sets(loaded, factor, 2.0, trial_damping(loaded, 20.0, 0.0), relaxation)
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


@pytest.mark.parametrize("model", ["mohr_coulomb", "drucker_prager"])
@pytest.mark.parametrize("h", [0.1, 0.05, 0.025])
def test_non_associated_slope_with_the_trials_regularisation(tmp_path, h, model):
    """psi = 0 (the soil of most slope analyses) under the trials' default Duvaut-Lions time T/800
    (kernels/viscoplastic.py; stability/trial.viscoplastic_time): the trial stands at 0.97 and fails at 1.03
    times the one-dimensional column's factor with the same law, schedule and regularisation
    (geompm/testing/verification/slope_column.py: 1.4847 Mohr-Coulomb, 1.4778 Drucker-Prager; Davis 1968:
    1.4775), at three cell sizes.  Without the regularisation Mohr-Coulomb failed at 0.88 of it at h = 0.025 m
    through vertical bands one cell wide (docs/slope-stability.md, The cause)."""
    from geompm.contract.registry import get
    from geompm.testing.verification.slope_column import column_factor

    tau = 2.0 / 800.0
    params = dict(density=2000.0, youngs_modulus=2e6, poisson_ratio=0.3, friction_angle=30.0, dilation_angle=0.0,
                  cohesion=0.0, dilation_cutoff=1.0)
    ref, _ = column_factor(get("materials", model), params, low=1.3, high=1.7, elements=20, viscoplastic_time=tau)
    kw = dict(dilation=0.0, model=model)
    below, above = _trial(tmp_path, h, 0.0, 0.97 * ref, tau, **kw), _trial(tmp_path, h, 0.0, 1.03 * ref, tau, **kw)
    assert not below["failed"], below
    assert above["failed"], above


@pytest.mark.parametrize("case", [
    pytest.param(dict(h=0.02, depth=0.2, model="mohr_coulomb", slope=20.0, friction=30.0, dilation=0.0), id="strip-0.02"),
    pytest.param(dict(h=0.01, depth=0.2, model="mohr_coulomb", slope=20.0, friction=30.0, dilation=0.0), id="strip-0.01"),
    pytest.param(dict(h=0.1, depth=1.0, model="drucker_prager", slope=36.0, friction=40.0, dilation=40.0), id="steep-0.1"),
    pytest.param(dict(h=0.05, depth=1.0, model="drucker_prager", slope=36.0, friction=40.0, dilation=40.0), id="steep-0.05"),
])
def test_strip_and_steep_slopes_against_their_column(tmp_path, case):
    """The issue's other set-ups with the trials' viscoplastic time T/800, 2 s trials: the 0.2 m strip (psi = 0,
    Mohr-Coulomb) at h = 0.02 and 0.01 m and the steep associated slope (beta = 36 deg, phi = psi = 40 deg) at
    h = 0.1 and 0.05 m stand at 0.97 and fail at 1.03 times the one-dimensional column's factor for the same
    trial (1.4885 and 1.1066: slope_column.py; the searches gave +0.15 % and +0.13 % at three cell sizes).  The
    steep slope's column is 4 % below tan(phi)/tan(beta) = 1.1547 because a 2 s trial is short
    (docs/slope-stability.md, The reference)."""
    from geompm.contract.registry import get
    from geompm.testing.verification.slope_column import column_factor

    tau = 2.0 / 800.0
    params = dict(density=2000.0, youngs_modulus=2e6, poisson_ratio=0.3, friction_angle=case["friction"],
                  dilation_angle=case["dilation"], cohesion=0.0, dilation_cutoff=1.0)
    ref, _ = column_factor(get("materials", case["model"]), params, low=0.8, high=2.0, elements=20,
                           slope=case["slope"], depth=case["depth"], viscoplastic_time=tau)
    kw = dict(dilation=case["dilation"], model=case["model"], slope=case["slope"], friction=case["friction"],
              depth=case["depth"])
    h = case["h"]
    below, above = _trial(tmp_path, h, 0.0, 0.97 * ref, tau, **kw), _trial(tmp_path, h, 0.0, 1.03 * ref, tau, **kw)
    assert not below["failed"], below
    assert above["failed"], above
