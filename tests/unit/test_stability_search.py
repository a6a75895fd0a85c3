"""The factor-of-safety search (geompm/stability/search.py) and failure criterion (criterion.py).

The search is checked against oracles with a known critical factor: the bracket it returns must hold
the critical factor and be no wider than the tolerance, and it must say F < lowest / F > highest when
the oracle fails or stands everywhere.  The criterion is checked on synthetic displacement histories
(an exponential approach to rest, a steady slide, an accelerating one)."""

import math

import numpy as np
import pytest

from geompm.stability.criterion import judge
from geompm.stability.search import Search


def _run(search: Search, critical: float, k: int) -> int:
    rounds = 0
    while not search.done():
        for f in search.next_factors(k):
            search.record(f, f > critical)
        rounds += 1
        assert rounds < 50
    return rounds


@pytest.mark.parametrize("critical", [0.437, 0.999, 1.0001, 1.2345, 3.71])
@pytest.mark.parametrize("k", [1, 2, 3])
def test_bracket_holds_the_critical_factor(critical, k):
    s = Search(tolerance=0.01)
    rounds = _run(s, critical, k)
    res = s.result()
    lo, hi = res["bracket"]
    assert lo <= critical < hi
    assert hi - lo <= 0.01 + 1e-12
    assert res["factor_of_safety"] == pytest.approx(0.5 * (lo + hi))
    assert abs(res["factor_of_safety"] - critical) <= 0.005 + 1e-12
    # k-section: each round with a bracket shrinks it by k + 1; a start near 1 needs few rounds to bracket
    assert rounds <= 6 + math.ceil(math.log(1.0 / 0.01) / math.log(k + 1))


def test_out_of_range_is_reported_as_a_bound():
    s = Search(tolerance=0.01)
    _run(s, 0.0, 2)  # fails at every F
    res = s.result()
    assert res["factor_of_safety"] is None and res["bound"] == f"F < {s.lowest:g}"
    s = Search(tolerance=0.01)
    _run(s, 1e9, 2)  # stands at every F
    res = s.result()
    assert res["factor_of_safety"] is None and res["bound"] == f"F > {s.highest:g}"


def test_inconsistent_trials_are_named():
    s = Search()
    s.record(1.5, False)
    s.record(1.2, True)
    s.record(1.8, True)
    assert s.inconsistent() == [(1.5, 1.2)]
    assert s.bracket() == (1.5, 1.8)


def _series(u):
    t = np.linspace(0.0, 2.0, 41)
    return {"time": t, "max_displacement": u(t), "kinetic_energy": np.gradient(u(t), t) ** 2}


def test_criterion_on_synthetic_histories():
    """At rest (u_inf (1 - exp(-t / 0.4))): its increments shrink by exp(-0.5 / 0.4) = 0.287 per quarter,
    stable at ratio 0.7; a steady slide at 0.05 m/s has ratio 1, failed, but not with a floor above its
    25 mm; an accelerating one (0.1 t^2) has ratio (2^2 - 1.5^2) / (1.5^2 - 1) = 1.4; a slope at rest
    whose last increments are round-off (1e-12 m, ratio 1) is stable under the floor."""
    rest = judge(_series(lambda t: 0.02 * (1 - np.exp(-t / 0.4))), ratio=0.7, floor=1e-4)
    assert not rest["failed"] and rest["ratio"] == pytest.approx(np.exp(-0.5 / 0.4), rel=1e-2)
    assert judge(_series(lambda t: 0.02 * (1 - np.exp(-t / 0.4))), ratio=0.25, floor=1e-4)["failed"]
    slide = judge(_series(lambda t: 0.05 * t), ratio=0.7, floor=1e-4)
    assert slide["failed"] and slide["last_increment"] == pytest.approx(0.025) and slide["ratio"] == pytest.approx(1.0)
    assert not judge(_series(lambda t: 0.05 * t), ratio=0.7, floor=0.03)["failed"]
    fast = judge(_series(lambda t: 0.1 * t * t), ratio=0.7, floor=1e-4)
    assert fast["failed"] and fast["ratio"] == pytest.approx(1.4)
    assert not judge(_series(lambda t: 0.01 + 1e-12 * t), ratio=0.7, floor=1e-4)["failed"]
