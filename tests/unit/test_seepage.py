"""The steady seepage state (triggers.water_table.seepage; mpm/seepage.py).

- Confined flow through a saturated box between two heads is linear in x, H = h1 - (h1 - h2) x / L, and the
  bilinear elements reproduce a linear field exactly: the head to round-off, the inflow k (h1 - h2) D / L.
- Unconfined flow through a rectangular dam between reservoirs h1 and h2 (a phreatic surface and a seepage
  face on the downstream side): the discharge is Dupuit's q = k (h1^2 - h2^2) / (2 L) exactly (Charny 1951;
  see Bear 1972, Dynamics of Fluids in Porous Media), though the free surface is not Dupuit's parabola.  With the
  variable-permeability method the unsaturated fringe conducts a little: q converges at first order,
  +4.43 / +2.03 / +1.00 % at h = 0.5 / 0.25 / 0.125 m (measured; the test asserts the two coarse sizes and
  that the error halves).
- Under a pond with no other head the state is hydrostatic at the pond's level.
- Bad input is refused with its JSON path."""

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.errors import CaseError
from geompm.mpm.seepage import solve_seepage
from geompm.schema.load import parse_case
from geompm.setup.assemble import assemble

G, RHO_W = 9.81, 1000.0


def _points(length, height, h):
    xs, ys = np.arange(h / 4, length, h / 2), np.arange(h / 4, height, h / 2)
    x, y = np.meshgrid(xs, ys, indexing="ij")
    return np.column_stack([x.ravel(), y.ravel()])


def test_confined_flow_is_linear_and_its_inflow_exact():
    """The soil fills the grid's height (its top on the grid's side: impermeable), heads 6 and 5 m."""
    length, depth, h = 10.0, 4.0, 0.5
    head, report = solve_seepage(_points(length, depth, h), np.zeros(2), h, np.array([20, 8]),
                                 [(0, False, 6.0), (0, True, 5.0)], None)
    x = np.arange(21) * h
    assert head == pytest.approx(np.repeat((6.0 - x / length)[:, None], 9, axis=1), abs=1e-9)
    assert report["inflow_per_k"][0] == pytest.approx(1.0 * depth / length, rel=1e-9)
    assert report["settled"] and report["seepage_nodes"] == 0


def test_unconfined_flow_through_a_dam_has_dupuits_discharge():
    length, h1, h2 = 10.0, 6.0, 1.0
    dupuit = (h1 ** 2 - h2 ** 2) / (2.0 * length)
    errors = []
    for h in (0.5, 0.25):
        _, report = solve_seepage(_points(length, 8.0, h), np.zeros(2), h, np.array([int(length / h), int(9.0 / h)]),
                                  [(0, False, h1), (0, True, h2)], None)
        assert report["settled"] and report["seepage_nodes"] > 0  # the downstream face seeps above the tailwater
        errors.append(report["inflow_per_k"][0] / dupuit - 1.0)
    assert abs(errors[0]) < 0.05 and abs(errors[1]) < 0.025, errors
    assert abs(errors[1]) < 0.6 * abs(errors[0]), errors  # first order


def _dam(top=9.0, **water):
    return {"name": "dam", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [10.0, top], "cell_size": 0.5, "shape_function": "linear"},
            "time": {"end": 0.1, "cfl": 0.4}, "gravity": [0.0, -G],
            "materials": {"soil": {"model": "drucker_prager", "density": 2000, "youngs_modulus": 2e7,
                                   "poisson_ratio": 0.3, "friction_angle": 30, "cohesion": 5000, "dilation_angle": 0}},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0], "max": [10, 4]},
                        "initial_stress": "geostatic"}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"}],
            "triggers": {"water_table": water}, "outputs": []}


def test_a_case_takes_the_seepage_pressure_at_its_particles():
    """The soil filling the grid's 4 m, heads 4.0 and 3.9 m (saturated throughout: every cell conducts k): at
    every particle p = rho_w g (H(x) - z) with H bilinear between the solved nodes (interpolated here with
    numpy), and H within 5 % of the head drop of the linear field (the x+ side above 3.9 m is a no-flux
    face, so the field is not exactly linear)."""
    scene = scene_from_dict(_dam(top=4.0, seepage={"heads": [{"side": "x-", "head": 4.0},
                                                             {"side": "x+", "head": 3.9}]}))
    st, table = scene.state, scene.water_table
    head = table.surface.head
    i = np.floor(st.p_x / 0.5).astype(int)
    f = st.p_x / 0.5 - i
    H = ((1 - f[:, 0]) * (1 - f[:, 1]) * head[i[:, 0], i[:, 1]] + f[:, 0] * (1 - f[:, 1]) * head[i[:, 0] + 1, i[:, 1]]
         + (1 - f[:, 0]) * f[:, 1] * head[i[:, 0], i[:, 1] + 1] + f[:, 0] * f[:, 1] * head[i[:, 0] + 1, i[:, 1] + 1])
    p = table.pressure(st.p_x, st.p_material, 0.0)
    assert p == pytest.approx(RHO_W * G * np.maximum(H - st.p_x[:, 1], 0.0), rel=1e-12)
    assert table.surface.report["saturated_cells"] == table.surface.report["cells"]
    assert np.abs(H - (4.0 - 0.01 * st.p_x[:, 0])).max() < 0.05 * 0.1  # measured 2.8 %, at the x+ top corner


def test_under_a_pond_alone_the_state_is_hydrostatic_at_its_level():
    scene = scene_from_dict(_dam(seepage={}, pond={"times": [0.0], "levels": [6.0]}))
    st = scene.water_table
    p = st.pressure(scene.state.p_x, scene.state.p_material, 0.0)
    assert p == pytest.approx(RHO_W * G * (6.0 - scene.state.p_x[:, 1]), rel=1e-9)


@pytest.mark.parametrize("water, path, words", [
    ({"seepage": {"heads": [{"side": "z-", "head": 1.0}]}}, "triggers.water_table.seepage.heads.0.side", "no side z-"),
    ({"seepage": {"heads": [{"side": "x-", "head": 20.0}]}}, "triggers.water_table.seepage.heads.0.head",
     "above the grid's top"),
])
def test_bad_seepage_input_is_refused_with_its_json_path(water, path, words):
    with pytest.raises(CaseError) as exc:
        assemble(parse_case(_dam(**water), "."))
    assert any(p == path and words in t for p, t in exc.value.problems), exc.value.problems


@pytest.mark.parametrize("water, words", [
    ({"seepage": {"heads": [{"side": "x-", "head": 1.0}]}, "heights": [1.0]}, "solved from its heads"),
    ({"seepage": {}}, "needs a head somewhere"),
])
def test_contradictory_seepage_input_is_refused(water, words):
    with pytest.raises(CaseError) as exc:
        parse_case(_dam(**water), ".")
    assert any("triggers.water_table" in p and words in t for p, t in exc.value.problems), exc.value.problems


def test_a_two_phase_body_starts_in_the_seepage_state():
    """bodies.N.pore_pressure.seepage: a saturated body's initial pore pressure is the solved state's, the same
    as the drained trigger's on the same particles; particles above the phreatic surface start dry; a side the
    grid does not have is refused."""
    heads = [{"side": "x-", "head": 3.0}, {"side": "x+", "head": 1.0}]
    drained = scene_from_dict(_dam(seepage={"heads": heads}))
    expected = drained.water_table.pressure(drained.state.p_x, drained.state.p_material, 0.0).copy()
    case = _dam()
    del case["triggers"]
    case["materials"]["soil"]["pore_water"] = {"porosity": 0.4, "hydraulic_conductivity": 1e-5,
                                               "fluid": {"density": RHO_W, "bulk_modulus": 2e7, "viscosity": 1e-3}}
    case["solver"] = {"transfer": "pic", "update": "saturated"}
    case["bodies"][0]["pore_pressure"] = {"seepage": {"heads": heads}}
    st = scene_from_dict(case).state
    order = np.lexsort((st.p_x[:, 1], st.p_x[:, 0]))
    mine = np.lexsort((drained.state.p_x[:, 1], drained.state.p_x[:, 0]))
    assert st.p_pore[order] == pytest.approx(expected[mine], rel=1e-9, abs=1e-6)
    assert 0.0 < st.p_sat.mean() < 1.0 and not st.p_pore[st.p_sat == 0.0].any()
    case["bodies"][0]["pore_pressure"]["seepage"]["heads"][0]["side"] = "z-"
    with pytest.raises(CaseError) as exc:
        assemble(parse_case(case, "."))
    assert any(p == "bodies.0.pore_pressure.seepage.heads.0.side" for p, _ in exc.value.problems)


def test_a_rising_head_solves_the_state_again():
    """A head schedule (seepage.times, a list per head): at t = 10 s the pressure is the state solved with the
    head at its value then (3.5 m), and the state was not solved again for a change below a tenth of a cell."""
    moving = scene_from_dict(_dam(seepage={"times": [0.0, 10.0], "heads": [{"side": "x-", "head": [3.0, 3.5]},
                                                                           {"side": "x+", "head": 1.0}]}))
    fixed = scene_from_dict(_dam(seepage={"heads": [{"side": "x-", "head": 3.5}, {"side": "x+", "head": 1.0}]}))
    st = moving.state
    table = moving.water_table
    table.pressure(st.p_x, st.p_material, 0.4)  # 0.02 m: below a tenth of the 0.5 m cell
    assert table.surface.solves == 1
    p = table.pressure(st.p_x, st.p_material, 10.0).copy()
    assert table.surface.solves == 2
    assert p == pytest.approx(fixed.water_table.pressure(st.p_x, st.p_material, 0.0), rel=1e-9, abs=1e-6)
