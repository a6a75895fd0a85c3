"""Water from below: a wall that holds a head (``drainage: "head"``, schemes/saturated/head.py) feeds a saturated
column, against Darcy's steady upward seepage (geompm/testing/verification/head_column.py for the closed form).

The column is 1 m of soil (n = 0.4, k = 1e-3 m/s, E = 20 MPa, K_w = 20 MPa) on h = 0.1 m cells; c_v = 1.8 m2/s, so
L^2 / c_v = 0.55 s: the runs end past it.  benchmarks/pore_water/head_column.py runs h = 0.1 / 0.05 / 0.025 m
(docs/pore-water.md, Water from a boundary, for the table).
"""

import copy

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.errors import CaseError
from geompm.testing.verification.head_column import column_case, run_column


def test_a_head_above_the_top_drives_the_steady_upward_seepage():
    """H = 1.5 m on the 1 m column: the mean pore pressure at 0.1 / 0.25 / 0.5 / 0.75 m within 2 % of
    rho_w g (H - (H - L) z / L - z) (measured +0.9 / 0.0 / -0.1 / -0.8 %) and the discharge n (v_w - v_s) within
    5 % of k (H - L) / L = 5e-4 m/s (measured 4.90e-4).  A base that drained instead would hold p = 0 there and
    drain the column: the pressure at 0.1 m would fall from 8.8 kPa, never rise to 13.2 kPa."""
    r = run_column(0.1, 1e-3, 1.5, end=0.8)
    assert np.abs(r["error"]).max() < 0.02, r
    assert r["flux"] == pytest.approx(r["flux_closed"], rel=0.05)


def test_a_head_at_the_top_keeps_the_column_at_rest():
    """H = L: the band's volume force balances the held layer, the column stays hydrostatic within 2 % and
    the discharge is below 5 % of the seepage case's."""
    r = run_column(0.1, 1e-3, 1.0, end=0.3)
    assert np.abs(r["error"]).max() < 0.02, r
    assert abs(r["flux"]) < 0.05 * 5e-4


@pytest.mark.slow
def test_a_rising_head_reaches_the_steady_state_of_its_last_level():
    """The head raised from 1.0 to 1.5 m over the first 0.3 s (a schedule, linear between its times): at 1.0 s
    the profile within 2 % of the steady one at 1.5 m."""
    r = run_column(0.1, 1e-3, (1.0, 1.5), (0.0, 0.3), end=1.0)
    assert np.abs(r["error"]).max() < 0.02, r


def _edit(change):
    case = copy.deepcopy(column_case(0.1, 1e-3, 1.5))
    change(case)
    return case


@pytest.mark.parametrize("change, path, words", [
    (lambda c: c["boundaries"][2].pop("head"), "boundaries.2", "give 'head'"),
    (lambda c: c["boundaries"][2].update(drainage="drained"), "boundaries.2", "give 'head'"),
    (lambda c: c["boundaries"][2].update(head=[1.0, 1.5], head_times=[0.0]), "boundaries.2", "one head per time"),
    (lambda c: c.update(solver={"update": "saturated_semi_implicit"}), "boundaries.2.drainage",
     "explicit two-phase step"),
    (lambda c: c.update(solver={"backend": "cuda"}), "boundaries.2.drainage", "CPU backend only"),
])
def test_bad_head_input_is_refused_with_its_path(change, path, words):
    with pytest.raises(CaseError) as err:
        scene_from_dict(_edit(change))
    text = str(err.value)
    assert path in text and words in text, text
