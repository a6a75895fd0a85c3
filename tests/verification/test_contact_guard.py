"""Nothing passes a rigid obstacle, at any grid alignment (issue 15, point 1).

A 2D elastic block (0.2 m x 0.2 m, E = 1 MPa, rho = 1000 kg/m3, no gravity)
is thrown at a plate 0.3 h thick (h = 0.02 m, so 6 mm: grid contact alone
sees it only when a node happens to fall inside), head-on and at 40 degrees
from the plate's normal, with the plate at 5 offsets against the grid (0,
0.2, 0.4, 0.6, 0.8 h).  Checked at every step against the exact signed
distance of the plate: no particle deeper than 0.25 h inside it, none past it;
and over the impact, momentum balance: the impulse recorded on the plate,
sum F dt, equals minus the block's momentum change within 5 % (both normal
and, at 40 degrees with slip, the tangential component that the plate must
not take).  A fast block (15 m/s, about half the elastic wave speed, the
largest step the CFL condition allows) is held to the same.
"""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

H = 0.02
THICK = 0.3 * H
X_PLATE = 0.5


def _case(offset, speed, angle_deg, condition="slip"):
    x0 = X_PLATE + offset * H
    a = math.radians(angle_deg)
    return {
        "name": "plate", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 1.0], "cell_size": H},
        "time": {"end": 1.0, "cfl": 0.4},
        "gravity": [0.0, 0.0],
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1e6,
                                "poisson_ratio": 0.3}},
        "bodies": [{"material": "block", "geometry": {"type": "box", "min": [x0 - 0.3, 0.3],
                                                      "max": [x0 - 0.1, 0.5]},
                    "velocity": [speed * math.cos(a), speed * math.sin(a)], "particles_per_cell": 2}],
        "obstacles": [{"type": "box", "name": "plate", "min": [x0, 0.02], "max": [x0 + THICK, 0.98],
                       "condition": condition}],
        "outputs": [],
    }


def _plate_sdf(x, x0):
    """Exact signed distance to the plate's slab (its ends are far from the block)."""
    return np.maximum(x0 - x[:, 0], x[:, 0] - (x0 + THICK))


def _throw(offset, speed, angle_deg, t_end):
    sim = Simulation(scene_from_dict(_case(offset, speed, angle_deg)))
    st, plate = sim.state, sim.scene.obstacles[0]
    x0 = X_PLATE + offset * H
    p0 = (st.p_mass[:, None] * st.p_v).sum(axis=0)
    impulse = np.zeros(2)
    deepest, passed = 0.0, 0
    while sim.time < t_end:
        sim.step(sim.stable_dt())
        impulse += plate.force * sim.dt
        phi = _plate_sdf(st.p_x, x0)
        deepest = max(deepest, float(-phi.min()))
        passed = max(passed, int((st.p_x[:, 0] > x0 + THICK).sum()))
    p1 = (st.p_mass[:, None] * st.p_v).sum(axis=0)
    return impulse, p1 - p0, deepest, passed, p0


@pytest.mark.parametrize("angle", [0.0, 40.0])
@pytest.mark.parametrize("offset", [0.0, 0.2, 0.4, 0.6, 0.8])
def test_thin_plate_stops_the_block_at_every_offset(offset, angle):
    impulse, dp, deepest, passed, p0 = _throw(offset, 2.0, angle, 0.12)
    assert passed == 0
    assert deepest < 0.25 * H, f"deepest particle {deepest / H:.3f} h inside the plate"
    assert dp[0] < -0.5 * p0[0], "the block must have been stopped (and rebounded) by the plate"
    assert impulse[0] == pytest.approx(-dp[0], rel=0.05)
    assert abs(impulse[1] + dp[1]) < 0.05 * abs(dp[0])  # slip: no tangential impulse taken, none lost


def test_fast_block_does_not_tunnel():
    """15 m/s: the block moves up to 0.4 h per step (CFL 0.4 of c + |v|)."""
    impulse, dp, deepest, passed, p0 = _throw(0.5, 15.0, 0.0, 0.04)
    assert passed == 0
    assert deepest < 0.25 * H
    assert impulse[0] == pytest.approx(-dp[0], rel=0.05)


def test_validate_warns_about_a_plate_thinner_than_two_cells(tmp_path, capsys):
    """`geompm validate` names the obstacle, its thickness in cells and a cell size that resolves it."""
    import json

    from geompm.cli import main

    f = tmp_path / "plate.json"
    f.write_text(json.dumps(_case(0.0, 2.0, 0.0)))
    assert main(["validate", str(f)]) == 0
    out = capsys.readouterr().out
    assert "obstacle 'plate' (obstacles.0) is 0.006 m thick at its thinnest, 0.30 cells" in out
    assert "grid.cell_size <= 0.003 m" in out


def test_mesh_thickness_of_the_check_dam():
    """The STL check dam is two closed blocks 0.1 m x 0.7 m x 0.2 m (cases/meshes/make_check_dam.py): its
    thinnest chord is the 0.1 m block thickness, found by casting rays inward from every face.  The STL holds
    float32 coordinates: +-0.05 m is +-0.0500000007 m, so the faces are 0.1000000015 m apart."""
    from geompm.api import scene_from_file

    from tests.support.cases import CASES

    scene = scene_from_file(CASES / "debris_obstacle.json", ["grid.cell_size=0.1"])
    dam = scene.obstacles[0]
    assert dam.thinnest() == pytest.approx(float(np.float32(0.05)) * 2, abs=1e-12)
    assert "1.00 cells" in dam.warnings()[0]  # 0.1 m = one cell at h = 0.1
    scene = scene_from_file(CASES / "debris_obstacle.json", ["grid.cell_size=0.07"])
    assert "1.43 cells" in scene.obstacles[0].warnings()[0]


def test_no_particle_ends_behind_a_plane():
    """A block thrown at 12 m/s onto a 30 degree plane that cuts the cells between nodes: after every step
    every particle's signed distance (x - point) . n is >= -1e-12 m (the half-space guard is exact)."""
    case = _case(0.0, 0.0, 0.0)
    case.pop("obstacles")
    n = np.array([-math.sin(math.radians(30)), math.cos(math.radians(30))])
    point = np.array([0.5, 0.2037])
    case["boundaries"] = [{"type": "plane", "point": point.tolist(), "normal": n.tolist(), "condition": "friction",
                           "friction": 0.3}]
    case["bodies"][0]["geometry"] = {"type": "box", "min": [0.4, 0.45], "max": [0.6, 0.6]}
    case["bodies"][0]["velocity"] = [0.0, -12.0]
    sim = Simulation(scene_from_dict(case))
    worst = 0.0
    while sim.time < 0.05:
        sim.step(sim.stable_dt())
        worst = min(worst, float(((sim.state.p_x - point) @ n).min()))
    assert worst >= -1e-12


def _dam_run(h):
    """cases/debris_obstacle.json at cell size h: (peak |F| on the dam [N], deepest particle inside a block
    at any 0.05 s sample [m], exact distance from the placed STL by trimesh)."""
    import json

    import trimesh

    from geompm.api import scene_from_file

    from tests.support.cases import CASES

    case = json.loads((CASES / "debris_obstacle.json").read_text())
    ob = case["obstacles"][0]
    mesh = trimesh.load(CASES / ob["file"], force="mesh")
    mesh.apply_translation(ob["translate"])
    sim = Simulation(scene_from_file(CASES / "debris_obstacle.json", [f"grid.cell_size={h}", "outputs=[]",
                                                                      "time.end=2.0"]))
    dam, st = sim.scene.obstacles[0], sim.state
    deepest, next_check = 0.0, 0.05
    while sim.time < sim.scene.end_time:
        sim.step(min(sim.stable_dt(), sim.scene.end_time - sim.time))
        if sim.time >= next_check:
            deepest = max(deepest, float(trimesh.proximity.signed_distance(mesh, st.p_x).max()))
            next_check += 0.05
    return dam.peak[0], deepest


@pytest.mark.slow
@pytest.mark.parametrize("h", [0.1, 0.085, 0.07, 0.06])
def test_check_dam_carries_load_at_every_resolution(h):
    """The STL check dam of cases/debris_obstacle.json (blocks 0.1 m thick: 1 to 1.7 cells here) at
    h = 0.1, 0.085, 0.07, 0.06 m: it takes the debris' load at every h (before the guard, 0.9 N at
    h = 0.07 m against ~500 N at 0.1 and 0.05 m; issue 15) and no particle is ever deeper than 0.25 h
    inside a block (exact distance to the STL, sampled every 0.05 s)."""
    peak, deepest = _dam_run(h)
    assert peak > 300.0, f"peak force {peak:.1f} N"
    assert deepest < 0.25 * h, f"deepest {deepest / h:.3f} h"
