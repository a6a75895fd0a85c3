"""The limit-equilibrium reference of the stability tests (geompm/testing/verification/bishop.py), against published values.

- A vertical cut in undrained clay (phi = 0): the critical circle through the toe gives H_c = 3.83 c / gamma,
  Taylor's stability number c / (F gamma H) = 0.261 (Taylor 1948, Fundamentals of Soil Mechanics, ch. 16).
- A dry cohesionless slope: the critical surfaces are shallow and long, and F tends to the infinite slope's
  tan(phi) / tan(beta) from above (2:1, phi = 30 deg: 1.1547).
- Griffiths & Lane's (1999, Geotechnique 49(3):387) first example, a 2:1 slope on a rigid base at the toe's
  level with phi' = 20 deg and c' / (gamma H) = 0.05: the Bishop & Morgenstern (1960) charts they quote give
  F = 1.380.
- F depends on c, gamma and H only through c / (gamma H)."""

import numpy as np
import pytest

from geompm.testing.verification.bishop import critical_circle, surface_from_points

TWO_TO_ONE = ([-100.0, 0.0, 20.0, 200.0], [10.0, 10.0, 0.0, 0.0])  # H = 10 m, crest at x = 0, toe at x = 20 m
GRID = ((np.linspace(-10, 30, 11), np.linspace(5, 40, 11)), np.linspace(5, 50, 16))


def test_vertical_cut_in_clay():
    s = surface_from_points([-100.0, 0.0, 1e-9, 100.0], [10.0, 10.0, 0.0, 0.0])
    F, circle = critical_circle(s, 10.0, 0.0, 1.0, *GRID, base=0.0, lo=-100.0, hi=100.0)
    assert F == pytest.approx(3.83 * 10.0 / (1.0 * 10.0), rel=0.01)


def test_cohesionless_slope_tends_to_the_infinite_slope():
    s = surface_from_points(*TWO_TO_ONE)
    F, _ = critical_circle(s, 0.0, 30.0, 20.0, (np.linspace(-10, 60, 11), np.linspace(5, 200, 11)),
                           np.linspace(5, 250, 16), base=0.0, lo=-100.0, hi=200.0)
    ref = np.tan(np.radians(30.0)) / 0.5
    assert ref <= F <= 1.005 * ref


def test_griffiths_and_lane_first_example():
    s = surface_from_points(*TWO_TO_ONE)
    F, (xc, yc, R) = critical_circle(s, 10.0, 20.0, 20.0, *GRID, base=0.0, lo=-100.0, hi=200.0)
    assert F == pytest.approx(1.380, rel=0.01)
    assert yc - R >= -1e-9  # the critical circle stays above the rigid base


def test_only_c_over_gamma_h_matters():
    s = surface_from_points(*TWO_TO_ONE)
    s2 = surface_from_points([x * 2 for x in TWO_TO_ONE[0]], [y * 2 for y in TWO_TO_ONE[1]])
    F1, _ = critical_circle(s, 10.0, 20.0, 20.0, *GRID, base=0.0, lo=-100.0, hi=200.0, refine=2)
    F2, _ = critical_circle(s2, 10.0, 20.0, 10.0, (GRID[0][0] * 2, GRID[0][1] * 2), GRID[1] * 2, base=0.0,
                            lo=-200.0, hi=400.0, refine=2)
    assert F2 == pytest.approx(F1, rel=1e-6)
