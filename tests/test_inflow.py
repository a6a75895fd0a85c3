"""Inflow hydrographs (sources/hydrograph.py, sources/inflow.py): the hydrograph's integral and its inverse,
the injected volume against that integral at every step, the gate on a plane in 3D, the input checks, and a
restart that continues the injection.  The steady depth on a Voellmy bed is in
tests/verification/test_inflow_steady.py."""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.errors import CaseError
from geompm.schema.load import parse_case
from geompm.sources.hydrograph import Hydrograph, read_hydrograph

#: a triangular hydrograph: 0 -> 0.4 m2/s at 0.5 s -> 0 at 1.5 s (volume 0.3 m2 per metre)
TRIANGLE = [[0.0, 0.0, 2.0], [0.5, 0.4, 2.0], [1.5, 0.0, 2.0]]


def test_volume_and_its_inverse_are_exact_for_a_piecewise_linear_discharge():
    """V(t) of the triangle: 0.4 t^2 for t <= 0.5 s (0.1 m2 at 0.5 s), 0.3 m2 in all; time_of inverts it."""
    hg = Hydrograph(*np.asarray(TRIANGLE).T, "velocity")
    assert hg.total == pytest.approx(0.3, rel=1e-15)
    assert hg.volume(0.25) == pytest.approx(0.4 * 0.25 ** 2, rel=1e-14)
    # after the peak: V = 0.3 - 0.2 (1.5 - t)^2
    assert hg.volume(1.0) == pytest.approx(0.3 - 0.2 * 0.25, rel=1e-14)
    for t in (0.1, 0.25, 0.5, 0.8, 1.2, 1.49):
        assert hg.time_of(hg.volume(t)) == pytest.approx(t, rel=1e-9)
    assert hg.discharge(2.0) == 0.0 and hg.discharge(-1.0) == 0.0 and math.isinf(hg.time_of(0.31))


def test_a_plateau_of_zero_discharge_is_skipped_by_the_inverse():
    """Q = 1 for 1 s, 0 for 1 s, 1 again: the volume 1 m2 is reached at t = 1 s, 1.5 m2 at t = 2.5 s."""
    hg = Hydrograph([0, 1, 1, 2, 2, 3], [1, 1, 0, 0, 1, 1], [1] * 6, "velocity")
    assert hg.time_of(1.0) == pytest.approx(1.0) and hg.time_of(1.5) == pytest.approx(2.5)


@pytest.mark.parametrize("text, needle", [
    ("t,q,v\n0,1,1\n1,1,1\n", "must name the columns"),
    ("time,discharge,velocity\n0,1,1\n", "at least two rows"),
    ("time [s],discharge [m3/s],velocity [m/s]\n0,1,1\n2,1,1\n1,1,1\n", "must not decrease (row 3"),
    ("time,discharge,depth\n0,1,1\n1,-2,1\n", "discharge must be >= 0 (row 2"),
    ("time;discharge;velocity\n0;1;0\n1;1;1\n", "the velocity must be > 0 where the discharge is (row 1"),
    ("time,discharge,velocity\n0,1,1\n1,one,1\n", "data row 2"),
])
def test_a_bad_hydrograph_file_is_refused_with_its_line(tmp_path, text, needle):
    f = tmp_path / "hg.csv"
    f.write_text(text)
    hg, bad = read_hydrograph(f)
    assert hg is None and any(needle in b for b in bad), bad


def test_a_csv_hydrograph_reads_its_columns_in_any_order(tmp_path):
    f = tmp_path / "hg.csv"
    f.write_text("# gauge 3\ndepth_m,time_s,discharge_m3s\n0.5,0,2\n0.5,10,4\n")
    hg, bad = read_hydrograph(f)
    assert not bad and hg.kind == "depth" and hg.total == pytest.approx(30.0) and hg.column(5.0) == 0.5


def channel_case(h=0.05, table=TRIANGLE, end=1.0):
    """A 2D channel 3 m long at 10 deg with a frictional bed and end walls; a viscous debris enters at x = 0.2 m."""
    b = math.radians(10.0)
    return {"name": "inflow_channel", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [3.0, 2.0], "cell_size": h},
            "time": {"end": end, "cfl": 0.4}, "gravity": [9.81 * math.sin(b), -9.81 * math.cos(b)],
            "materials": {"debris": {"model": "newtonian", "density": 1800.0, "viscosity": 1.0,
                                     "sound_speed": 30.0}},
            "inflows": [{"name": "gate", "material": "debris", "section": [[0.2, 0.0]], "direction": [1.0, 0.0],
                         "table": table}],
            "boundaries": [{"type": "wall", "side": "x-"}, {"type": "wall", "side": "x+"},
                           {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.3}]}


def test_the_injected_volume_follows_the_hydrograph_to_one_particle_at_every_step():
    """A scene that starts empty: after every step N V_p <= V(t) < (N + 1) V_p (V_p = (h/2)^2 = 6.25e-4 m2), the
    particles carry mass N V_p rho, the last one enters at the end of the hydrograph and the total is
    floor(0.3 / V_p) = 480 particles; the run keeps stepping while it is empty (the first 0.04 s: V < V_p)."""
    sim = Simulation(scene_from_dict(channel_case(end=1.6)))
    gate = sim.scene.inflows[0]
    vp = gate.vp
    assert sim.state.n == 0 and vp == pytest.approx(0.025 ** 2)
    worst = 0.0
    while sim.time < 1.6 - 1e-12:
        sim.step(min(sim.stable_dt(), 1.6 - sim.time))
        v = gate.hydrograph.volume(sim.time)
        held = float(sim.state.p_vol0.sum())
        assert held <= v * (1 + 1e-12) and v - held < vp, (sim.time, held, v)
        assert float(sim.state.p_mass.sum()) == pytest.approx(1800.0 * held, rel=1e-12)
        worst = max(worst, (v - held) / vp)
    assert sim.state.n == gate.total == 480 and len(np.unique(sim.state.p_id)) == 480
    assert 0.5 < worst < 1.0  # the volume in the hydrograph not yet a whole particle
    assert gate.series()["gate_volume_in"] == pytest.approx(480 * vp)


def test_slices_enter_as_a_lattice_at_the_gate():
    """Q = 0.4 m2/s at 2 m/s: h = 0.2 m = 8 spacings of 0.025 m.  The 64 particles due at 0.1 s (V = 0.04 m2) are
    8 slices of 8 at (i + 1/2) s above the bed, spaced s apart along the flow, each where its middle has travelled
    since it crossed the gate; they move at 2 m/s and start with the stress of a layer at rest (sigma_yy = -rho g_n (h - y))."""
    scene = scene_from_dict(channel_case(table=[[0.0, 0.4, 2.0], [1.0, 0.4, 2.0]]))
    gate = scene.inflows[0]
    packet = gate.supply(scene.state, 0.1)
    x, v, stress = (packet["arrays"][k] for k in ("p_x", "p_v", "p_stress"))
    assert packet["counts"] == [64] and len(x) == 64 and gate.pending(0.1)
    assert x[:, 1].reshape(8, 8) == pytest.approx(np.tile((np.arange(8) + 0.5) * 0.025, (8, 1)), abs=1e-12)
    stations = x[::8, 0]
    assert (x[:, 0].reshape(8, 8) == stations[:, None]).all()
    assert np.diff(stations) == pytest.approx(np.full(7, -0.025), abs=1e-12)  # a lattice, older slices ahead
    # the last slice is whole at 0.1 s: its middle crossed half a slice (s / 2v) earlier, s / 2 downstream now
    assert stations[-1] == pytest.approx(0.2 + 0.0125, abs=1e-12)
    assert v == pytest.approx(np.tile([2.0, 0.0], (64, 1)))
    gn = 9.81 * math.cos(math.radians(10.0))
    assert stress[:, 1] == pytest.approx(-1800.0 * gn * (0.2 - x[:, 1]), rel=1e-12)
    assert gate.supply(scene.state, 0.1) is None  # nothing more is due


def test_a_restart_continues_the_injection(tmp_path):
    """A checkpoint at 0.4 s and a resume to 0.8 s give the particles of a run through 0.4 s (count, ids, positions
    bit for bit)."""
    from geompm.engine.checkpoint import load, restore, save

    def advance(sim, t):
        while sim.time < t - 1e-12:
            sim.step(min(sim.stable_dt(), t - sim.time))

    straight = Simulation(scene_from_dict(channel_case(end=0.8)))
    advance(straight, 0.4)
    advance(straight, 0.8)
    first = Simulation(scene_from_dict(channel_case(end=0.8)))
    advance(first, 0.4)
    save(tmp_path, first, {}, [])
    again = Simulation(scene_from_dict(channel_case(end=0.8)))
    restore(again, *load(tmp_path))
    assert again.scene.inflows[0].count == first.scene.inflows[0].count > 0
    advance(again, 0.8)
    assert again.state.n == straight.state.n
    a, b = np.argsort(again.state.p_id), np.argsort(straight.state.p_id)
    assert (again.state.p_id[a] == straight.state.p_id[b]).all()
    assert np.array_equal(again.state.p_x[a], straight.state.p_x[b])  # bit for bit


def test_a_3d_gate_in_plan_is_put_on_the_plane_below():
    """A polyline given in plan, (1, 0.2) to (1, 0.8), over a plane z = 0.1 + 0.2 x: the base points stand on the
    plane at z = 0.3 m, 0.6 m wide across a flow along x: 24 points at the spacing 0.025 m."""
    n = np.array([-0.2, 0.0, 1.0])
    case = {"name": "gate3d", "dimension": 3,
            "grid": {"origin": [0.0, 0.0, 0.0], "extent": [2.0, 1.0, 1.0], "cell_size": 0.05},
            "time": {"end": 0.01}, "gravity": [0.0, 0.0, -9.81],
            "materials": {"debris": {"model": "newtonian", "density": 1800.0, "viscosity": 1.0,
                                     "sound_speed": 30.0}},
            "inflows": [{"name": "gate", "material": "debris", "section": [[1.0, 0.2], [1.0, 0.8]],
                         "direction": [1.0, 0.0, 0.2], "table": [[0.0, 0.06, 1.0], [1.0, 0.06, 1.0]]}],
            "boundaries": [{"type": "plane", "point": [0.0, 0.0, 0.1], "normal": n.tolist()}]}
    gate = scene_from_dict(case).inflows[0]
    assert gate.base.shape == (24, 3) and gate.width == pytest.approx(0.6)
    assert gate.base[:, 2] == pytest.approx(0.3, abs=1e-9) and gate.base[:, 1] == pytest.approx(
        0.2 + (np.arange(24) + 0.5) * 0.025)
    v, h = gate.speed_and_depth(0.5)
    assert v == 1.0 and h == pytest.approx(0.1)  # Q / (v w) = 0.06 / 0.6


@pytest.mark.parametrize("change, path, needle", [
    ({"section": [[0.2, 0.0], [0.2, 0.5]]}, "inflows.0.section", "one point on the bed"),
    ({"direction": [0.0, 0.0]}, "inflows.0.direction", "zero vector"),
    ({"material": "mud"}, "inflows.0.material", "no material 'mud'"),
    ({"table": [[0.0, 1.0, 0.0], [1.0, 1.0, 1.0]]}, "inflows.0.table", "velocity must be > 0"),
    ({"hydrograph": "missing.csv", "table": None}, "inflows.0.hydrograph", "not found"),
    ({"name": "wall_x-"}, "inflows.0.name", "already used"),
])
def test_inflow_input_is_checked(change, path, needle):
    case = channel_case()
    case["inflows"][0].update(change)
    case["inflows"][0] = {k: v for k, v in case["inflows"][0].items() if v is not None}
    case["boundaries"][0]["name"] = "wall_x-"
    with pytest.raises(CaseError) as err:
        parse_case(case, ".")
    assert any(p == path and needle in text for p, text in err.value.problems), err.value.problems


def test_an_inflow_is_refused_on_cuda_and_a_case_without_material_is_refused():
    case = channel_case()
    case["solver"] = {"backend": "cuda"}
    with pytest.raises(CaseError) as err:
        parse_case(case, ".")
    assert any(p == "inflows" and "CPU backend only" in t for p, t in err.value.problems)
    case = channel_case()
    del case["inflows"]
    with pytest.raises(CaseError) as err:
        parse_case(case, ".")
    assert any("no material" in t for _, t in err.value.problems)
