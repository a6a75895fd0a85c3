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
    """At rest (u_inf (1 - exp(-t / 0.1))): its last-quarter increment is u_inf e^-15, stable; a steady
    slide at 0.05 m/s moves 25 mm in the last 0.5 s, failed at a 10 mm threshold and stable at 30 mm;
    an accelerating one (0.1 t^2) failed with an increment ratio (2^2 - 1.5^2) / (1.5^2 - 1) = 1.4."""
    rest = judge(_series(lambda t: 0.02 * (1 - np.exp(-t / 0.1))), creep=0.01)
    assert not rest["failed"] and rest["last_increment"] == pytest.approx(0.02 * (np.exp(-15) - np.exp(-20)), rel=1e-3)
    slide = judge(_series(lambda t: 0.05 * t), creep=0.01)
    assert slide["failed"] and slide["last_increment"] == pytest.approx(0.025) and slide["ratio"] == pytest.approx(1.0)
    assert not judge(_series(lambda t: 0.05 * t), creep=0.03)["failed"]
    fast = judge(_series(lambda t: 0.1 * t * t), creep=0.01)
    assert fast["failed"] and fast["ratio"] == pytest.approx(1.4)
