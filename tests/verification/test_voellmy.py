"""Voellmy basal friction (contact/voellmy.py) against its closed forms.

A layer 0.2 m deep sliding from rest on a Voellmy bed at 30 deg (mu 0.2, xi 50 m/s2; periodic along the
slope, gravity tilted; geompm/testing/verification/voellmy_layer.py) follows u = u_T tanh(t / tau),
u_T = sqrt(xi H (sin beta - mu cos beta)) = 1.808 m/s.  Measured (benchmarks/results/2026-12-05-issue58/
voellmy-layer.txt): at t = 0.25 / 0.5 / 1 / 2.5 s within 0.02 % at h = 0.05 and 0.025 m and within 0.08 % at
0.0125 m.  A 1 m block on a 30 deg plane (not aligned with the grid) at t = 1 s: -2.8 / -1.3 / -0.4 % at
h = 0.05 / 0.025 / 0.0125 m (converging; its ends are free).  The node's implicit update solves
|u'| + K |u'|^2 = |u| exactly."""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.contact.voellmy import turbulent_drag
from geompm.engine.scheduler import Simulation
from geompm.errors import CaseError
from geompm.schema.load import parse_case
from geompm.testing.verification.voellmy_layer import DEPTH, G, MU, XI, layer_case, layer_speeds, speed


def test_the_node_update_is_the_implicit_drag():
    """v = (3, 4, 0) m/s on a bed with normal z: |u| = 5; K = drag dt / (xi m) = 2 s/m: |u'| = (sqrt(41) - 1)/4,
    the direction kept and the normal part untouched (v_z = -1 stays)."""
    v = np.array([3.0, 4.0, -1.0])
    normal = np.array([0.0, 0.0, 1.0])
    turbulent_drag(v, normal, 0, 2.0, 10.0, 0.5, 0.05)  # K = 2 * 0.5 / (10 * 0.05) = 2
    u = (math.sqrt(1 + 4 * 2 * 5) - 1) / (2 * 2)
    assert np.hypot(v[0], v[1]) == pytest.approx(u, rel=1e-14) and v[0] / v[1] == pytest.approx(0.75)
    assert v[2] == -1.0 and u + 2 * u * u == pytest.approx(5.0, rel=1e-14)


@pytest.mark.parametrize("h", [0.05, 0.025])
def test_a_layer_reaches_the_voellmy_speed(h):
    for t, u in layer_speeds(h, times=(0.5, 2.5)):
        assert u == pytest.approx(speed(t), rel=0.002), (h, t)


def _plane_case(h):
    th = math.radians(30)
    t, n = np.array([math.cos(th), -math.sin(th)]), np.array([math.sin(th), math.cos(th)])
    p0 = np.array([0.0, 2.8])
    a, b = p0 + 0.3 * t, p0 + 1.3 * t
    case = layer_case(h)
    case.update(grid={"origin": [0, 0], "extent": [4.0, 3.2], "cell_size": h}, gravity=[0.0, -G])
    case["time"]["end"] = 1.0
    case["bodies"][0].update(geometry={"type": "polygon", "vertices": [list(v) for v in (a, b, b + DEPTH * n,
                                                                                         a + DEPTH * n)]},
                             surface_normal=list(n))
    case["boundaries"] = [{"type": "plane", "point": list(p0), "normal": list(n), "condition": "voellmy",
                           "friction": MU, "xi": XI}]
    return case, t


@pytest.mark.slow
def test_a_block_on_an_inclined_plane_converges_on_the_voellmy_speed():
    errors = []
    for h in (0.05, 0.025):
        case, t = _plane_case(h)
        sim = Simulation(scene_from_dict(case))
        st = sim.state
        while sim.time < 1.0 - 1e-12:
            sim.step(min(sim.stable_dt(), 1.0 - sim.time))
        u = float((st.p_mass * (st.p_v @ t)).sum() / st.p_mass.sum())
        errors.append(abs(u / speed(1.0) - 1))
    assert errors[0] < 0.04 and errors[1] < 0.02 and errors[1] < errors[0]


@pytest.mark.parametrize("change, needle", [
    ({"condition": "voellmy", "friction": 0.2}, "needs 'xi'"),
    ({"condition": "friction", "friction": 0.2, "xi": 500.0}, "belong to condition 'voellmy'"),
])
def test_voellmy_input_is_checked(change, needle):
    case = layer_case(0.05)
    case["boundaries"][1] = {"type": "wall", "side": "y-", **change}
    with pytest.raises(CaseError) as err:
        parse_case(case, ".")
    assert any(needle in text and path.startswith("boundaries.1") for path, text in err.value.problems)


def test_two_densities_need_the_voellmy_density():
    case = layer_case(0.05)
    case["materials"]["light"] = dict(case["materials"]["debris"], density=1500.0)
    case["bodies"].append({"material": "light", "geometry": {"type": "box", "min": [0.0, 0.2], "max": [0.2, 0.3]},
                           "particles_per_cell": 2})
    with pytest.raises(CaseError) as err:
        scene_from_dict(case)
    assert "'density'" in err.value.problems[0][1]
    case["boundaries"][1]["density"] = 1800.0
    assert scene_from_dict(case) is not None


@pytest.mark.slow
def test_the_terrain_offers_the_same_law(tmp_path):
    """A 0.3 x 0.3 x 0.15 m block on a 30 deg DEM incline with 'voellmy' slides as on the analytic plane (to
    0.5 % at t = 0.25 s, h = 0.05 m); a block this small at this h is 6.6 % slower than the closed form: the
    basal nodes one cell beyond its edges take the drag too (docs/basal-friction.md)."""
    from geompm.testing.verification.terrain_block import block_case

    speeds = []
    for floor in ("terrain", "plane"):
        (tmp_path / floor).mkdir()
        case, down, _ = block_case(tmp_path / floor, 30.0, 0.0, MU, floor)
        stage = case["obstacles"][0] if floor == "terrain" else case["boundaries"][0]
        stage.update(condition="voellmy", xi=XI)
        sim = Simulation(scene_from_dict(case, base_dir=tmp_path / floor))
        st = sim.state
        while sim.time < 0.25 - 1e-12:
            sim.step(min(sim.stable_dt(), 0.25 - sim.time))
        speeds.append(float((st.p_mass * (st.p_v @ down)).sum() / st.p_mass.sum()))
    assert speeds[0] == pytest.approx(speeds[1], rel=0.005)
    assert speeds[0] == pytest.approx(speed(0.25, depth=0.15) * (1 - 0.066), rel=0.02)


@pytest.mark.slow
def test_an_obstacle_as_the_bed_gives_the_voellmy_speed():
    """The sliding layer of test_a_layer_reaches_the_voellmy_speed on a box obstacle (its top face the bed,
    lifted 0.1 m off the grid's edge) instead of the y- wall: the same u_T tanh(t / tau) within 0.5 % at 0.5 and
    1 s (h = 0.05 m; 94 % of u_T at 1 s): the obstacles' contact takes the turbulent drag on the same first layer of
    nodes."""
    from geompm.api import scene_from_dict

    case = layer_case(0.05)
    case["grid"]["extent"] = [0.2, 0.5]
    case["bodies"][0]["geometry"] = {"type": "box", "min": [0.0, 0.1], "max": [0.2, 0.1 + DEPTH]}
    case["boundaries"] = [case["boundaries"][0], {"type": "wall", "side": "y-"}]
    case["obstacles"] = [{"type": "box", "name": "bed", "min": [-0.2, -0.1], "max": [0.4, 0.1],
                          "condition": "voellmy", "friction": MU, "xi": XI}]
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    for t in (0.5, 1.0):
        while sim.time < t - 1e-12:
            sim.step(min(sim.stable_dt(), t - sim.time))
        u = float((st.p_mass * st.p_v[:, 0]).sum() / st.p_mass.sum())
        assert u == pytest.approx(speed(t), rel=0.005), t


@pytest.mark.slow
def test_a_voellmy_dam_break_follows_the_depth_averaged_model():
    """A 1 m x 0.4 m block of a near-plug viscous fluid released on a 30 deg Voellmy bed (mu 0.2, xi 100 m/s2)
    against the depth-averaged model of the same flow (geompm/testing/verification/voellmy_dam_break.py, 9 600
    cells): at 0.5, 1 and 1.5 s the centroid within 2 %, its speed within 5 % and the front (depth 0.02 m)
    within 3 % plus a cell.  Three MPM sizes against the reference on four grids and its extrapolation in
    benchmarks/results/2026-12-06-issue58/voellmy-dam-break.txt (within 1.6 / 3.6 / 3.3 %)."""
    from geompm.testing.verification.voellmy_dam_break import mpm_dam_break, reference

    times = (0.5, 1.0, 1.5)
    for (t, xc, uc, front), (_, rx, ru, rf) in zip(mpm_dam_break(0.05, times), reference(times, 9600)):
        assert xc == pytest.approx(rx, rel=0.02), t
        assert uc == pytest.approx(ru, rel=0.05), t
        assert abs(front - rf) <= 0.03 * rf + 0.05, t
