"""Impermeable rigid solids keep the pore pressure (schemes/saturated/solids.py; docs/pore-water.md, Free
surface): a saturated layer at rest on an obstacle or on the terrain holds p = rho_w g depth in its bottom
row with no particle drained; a drained obstacle lets the water go; bad input is refused.

Reference: hydrostatics, p = rho_w g (z_top - z) under a level water table at the layer's top, in a layer
drained enough (k = 1e-2 m/s) that a leak at the base would show within the run.  The three cell sizes
are in benchmarks/results/2026-12-05-issue52/solid_layers.json; the tests assert the coarse pair.
"""

import copy
import json

import numpy as np
import pytest

from geompm.errors import CaseError
from geompm.schema import parse_case
from geompm.schemes.saturated import solids
from geompm.schemes.saturated.solids import kernel_cdf
from geompm.testing.verification import solid_layers as sl

from tests.support.cases import CASES


@pytest.mark.parametrize("kind, at_half", [(0, 0.125), (1, 1.0 / 6.0), (2, 0.2005)])
def test_the_shape_functions_cumulative_share_of_a_half_space(kind, at_half):
    """F(u), the share of a node's shape function inside a solid whose surface lies u h beyond the node
    (u < 0: the node outside): 1/2 on the surface, 0 and 1 beyond the support, and at u = -1/2 the closed
    forms (linear hat: (1/2)^2 / 2 = 0.125; quadratic B-spline: 1/6; cubic: 0.2005, by integrating
    the spline)."""
    u, cdf = kernel_cdf(kind)
    assert np.interp(0.0, u, cdf) == pytest.approx(0.5, abs=1e-6)
    assert cdf[0] == 0.0 and cdf[-1] == pytest.approx(1.0)
    assert np.interp(-0.5, u, cdf) == pytest.approx(at_half, abs=2e-4)
    assert np.all(np.diff(cdf) >= 0.0)


@pytest.mark.parametrize("h", [0.1, 0.05])
def test_a_layer_on_a_box_obstacle_keeps_hydrostatic_pressure_in_its_bottom_row(h):
    """A 1 m saturated column (n = 0.4, k = 1e-2 m/s) at rest on an analytic box obstacle for 0.2 s: the
    particles touching the box hold p = rho_w g depth within 1 % (measured -0.25 % / -0.16 % at h = 0.1 /
    0.05 m, as on the grid's own wall) and none is drained; counted as empty space (as before the solids'
    fill) every one of them was drained and held p = 0."""
    r = sl.bottom_row(sl.floor_2d(h, "box"), 0.2)
    assert r["particles"] >= 4
    assert abs(r["mean_error"]) < 0.01 and r["max_error"] < 0.01, r
    assert r["drained"] == 0.0, r


def test_without_the_solids_share_the_bottom_row_is_drained(monkeypatch):
    """The same column with the solids' fill switched off (the box counted as empty space): the bottom row
    is flagged drained and holds no pressure, the defect the fill removes."""
    monkeypatch.setattr(solids.SolidFill, "__bool__", lambda self: False)
    r = sl.bottom_row(sl.floor_2d(0.1, "box"), 0.05)
    assert r["drained"] == 1.0 and r["mean_error"] == pytest.approx(-1.0), r


@pytest.mark.slow
@pytest.mark.parametrize("floor", ["stl", "terrain"])
def test_a_3d_layer_on_an_stl_floor_or_a_terrain_dem_keeps_hydrostatic_pressure(tmp_path, floor):
    """3D: a 1 m column on a floor given as an STL mesh, and a 0.3 m layer on a level terrain DEM (walls
    around both): the bottom row within 1 % of rho_w g depth at h = 0.1 and 0.05 m and none drained
    (measured: STL -0.25 / -0.16 %, terrain +0.69 / see docs at h = 0.1 / 0.05 m)."""
    for h in (0.1, 0.05):
        where = tmp_path / f"h{h}"
        where.mkdir()
        case = sl.floor_3d(where, h) if floor == "stl" else sl.terrain_3d(where, h, slope_deg=0.0)
        r = sl.bottom_row(case, 0.2, base_dir=where)
        assert abs(r["mean_error"]) < 0.01 and r["max_error"] < 0.01, (h, r)
        assert r["drained"] == 0.0, (h, r)


def test_a_drained_obstacle_lets_the_water_leave():
    """The column on a drained box (a permeable floor): its bottom row is drained (p = 0 at the face) and
    the water seeps out through it, so that after 0.2 s the pressure at mid-depth is far below hydrostatic
    (unit-gradient downward seepage through a column drained at both ends holds p = 0 throughout: the
    column's mean p falls below 30 % of hydrostatic), where the impermeable box holds it within 1 %."""
    case = sl.floor_2d(0.1, "box")
    case["obstacles"][0]["drainage"] = "drained"
    r = sl.bottom_row(case, 0.2)
    assert r["drained"] == 1.0, r
    assert r["all_max_error"] > 0.7, r


def test_a_drained_obstacle_without_pore_water_is_refused():
    """'drainage': 'drained' in a dry case is refused before any work, at its JSON path."""
    case = json.loads((CASES / "debris_obstacle.json").read_text())
    case["obstacles"][0]["drainage"] = "drained"
    with pytest.raises(CaseError) as err:
        parse_case(case, CASES)
    assert any(p == "obstacles.0.drainage" and "pore_water" in m for p, m in err.value.problems), err.value.problems


def test_a_fluid_body_beside_saturated_soil_is_refused():
    """A fluid body in a case with saturated soil is refused at its body's material path."""
    case = json.loads((CASES / "terzaghi_consolidation.json").read_text())
    case["materials"]["water"] = {"model": "newtonian", "density": 1000.0, "viscosity": 1e-3, "sound_speed": 30.0}
    body = copy.deepcopy(case["bodies"][0])
    body["material"] = "water"
    body.pop("pore_pressure", None)
    body.pop("initial_stress", None)
    case["bodies"].append(body)
    with pytest.raises(CaseError) as err:
        parse_case(case, CASES)
    assert any(p == "bodies.1.material" and "fluid" in m for p, m in err.value.problems), err.value.problems
