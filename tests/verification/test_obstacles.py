"""Rigid obstacles: impact of an elastic body, impulse of the reported force, STL import errors.

Momentum balance (no gravity): the force the obstacle reports is minus the force
it exerts on the body, so  integral(F_obstacle) dt = -(p_end - p_start)  of the body.
"""

import json

import numpy as np
import pytest
import trimesh

from geompm.api import scene_from_dict
from geompm.cli import main
from geompm.engine.scheduler import Simulation


def _drop(dim, obstacle, h, end=0.2, v0=-2.0):
    body_lo = [0.4, 0.5] if dim == 2 else [0.24, 0.36, 0.24]
    body_hi = [0.6, 0.6] if dim == 2 else [0.36, 0.48, 0.36]
    vel = [0.5, v0] if dim == 2 else [0.5, v0, 0.0]
    return {
        "name": "drop", "dimension": dim,
        "grid": {"origin": [0.0] * dim, "extent": [1.0, 1.0] if dim == 2 else [0.6, 0.6, 0.6], "cell_size": h},
        "time": {"end": end, "cfl": 0.4}, "gravity": [0.0] * dim,
        "materials": {"m": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e6,
                            "poisson_ratio": 0.3}},
        "bodies": [{"material": "m", "geometry": {"type": "box", "min": body_lo, "max": body_hi},
                    "velocity": vel}],
        "obstacles": [obstacle],
    }


def _impact(case, h):
    sim = Simulation(scene_from_dict(case["raw"], case.get("base", ".")))
    st = sim.state
    obst = sim.scene.obstacles[0]
    p0 = (st.p_mass[:, None] * st.p_v).sum(axis=0)
    impulse = np.zeros(sim.scene.dim)
    deepest = np.inf
    while sim.time < sim.scene.end_time:
        dt = min(sim.stable_dt(), sim.scene.end_time - sim.time)
        sim.step(dt)
        impulse += obst.force * dt
        deepest = min(deepest, obst.signed_distance(st.p_x).min())
    p1 = (st.p_mass[:, None] * st.p_v).sum(axis=0)
    dp = p1 - p0
    return impulse, dp, deepest, obst


@pytest.mark.parametrize("condition", ["slip", "friction"])
def test_2d_block_hits_box(condition):
    h = 0.02
    raw = _drop(2, {"type": "box", "name": "wall", "min": [0.2, 0.1], "max": [0.8, 0.3],
                    "condition": condition, "friction": 0.3}, h)
    impulse, dp, deepest, obst = _impact({"raw": raw}, h)
    assert deepest > -0.5 * h, f"a particle went {-deepest / h:.2f} cells into the obstacle"
    assert abs(dp[1]) > 0.5 * abs(-2.0 * 1000 * 0.02)  # it did hit (body momentum 40 kg m/s per m)
    np.testing.assert_allclose(impulse, -dp, rtol=0.05, atol=0.05 * np.abs(dp).max())
    if condition == "slip":
        assert abs(dp[0]) < 1e-6 * abs(dp[1])  # no tangential force on a slip surface
    else:
        assert dp[0] < -0.01 * abs(dp[1])  # friction slowed the sliding
    assert obst.peak[0] > 0 and 0.05 < obst.peak[1] < 0.2


def test_3d_block_hits_stl_obstacle(tmp_path):
    h = 0.04
    trimesh.creation.box(extents=[0.4, 0.12, 0.4]).export(tmp_path / "slab.stl")
    raw = _drop(3, {"type": "rigid_mesh", "name": "slab", "file": "slab.stl", "translate": [0.3, 0.14, 0.3],
                    "condition": "slip"}, h)
    impulse, dp, deepest, obst = _impact({"raw": raw, "base": tmp_path}, h)
    assert deepest > -0.5 * h
    assert abs(dp[1]) > 0.5 * 2.0 * 1000 * 0.12 ** 3
    np.testing.assert_allclose(impulse, -dp, rtol=0.05, atol=0.05 * np.abs(dp).max())


def _run_drop_with_series(tmp_path):
    """`geompm run` of the 2D drop onto a box named 'wall', series every step; returns series.csv."""
    raw = _drop(2, {"type": "box", "name": "wall", "min": [0.2, 0.1], "max": [0.8, 0.3]}, 0.02, end=0.15)
    raw["outputs"] = [{"writer": "series", "interval": 0.0}]
    f = tmp_path / "case.json"
    f.write_text(json.dumps(raw))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    return tmp_path / "run" / "series.csv"


def test_force_columns_in_series(tmp_path):
    s = np.genfromtxt(_run_drop_with_series(tmp_path), delimiter=",", names=True)
    for col in ("wall_fx", "wall_fy", "wall_fn", "wall_ft", "wall_mz"):
        assert col in s.dtype.names
    assert s["wall_fy"].min() < 0.0  # the falling block pushes the obstacle down
    assert s["wall_fn"].max() > 0.0
    assert "peak force" in (tmp_path / "run" / "run.log").read_text()


def _stl_case(tmp_path, mesh_file, translate=(0.3, 0.14, 0.3)):
    raw = _drop(3, {"type": "rigid_mesh", "name": "slab", "file": mesh_file, "translate": list(translate)}, 0.04)
    f = tmp_path / f"case_{mesh_file}_{translate[0]}.json"
    f.write_text(json.dumps(raw))
    return f


def test_stl_errors_are_refused_before_any_work(tmp_path, capsys):
    holed = trimesh.creation.box(extents=[0.4, 0.12, 0.4])
    holed.update_faces(np.arange(len(holed.faces)) != 0)
    holed.export(tmp_path / "holed.stl")
    (tmp_path / "empty.stl").write_text("")
    trimesh.creation.box(extents=[0.4, 0.12, 0.4]).export(tmp_path / "ok.stl")
    cases = [
        (_stl_case(tmp_path, "holed.stl"), "not watertight"),
        (_stl_case(tmp_path, "empty.stl"), "empty.stl"),
        (_stl_case(tmp_path, "missing.stl"), "not found"),
        (_stl_case(tmp_path, "ok.stl", translate=(5.0, 5.0, 5.0)), "outside the grid"),
    ]
    for f, words in cases:
        assert main(["validate", str(f)]) == 2
        err = capsys.readouterr().err
        assert "obstacles.0" in err and words in err, err


def test_force_history_plot(tmp_path):
    """geompm.plots.run draws an obstacle's force history to a non-empty PNG."""
    from geompm.plots.run import obstacle_names, plot_obstacle_forces

    series = _run_drop_with_series(tmp_path)
    assert obstacle_names(np.genfromtxt(series, delimiter=",", names=True).dtype.names) == ["wall"]
    png = plot_obstacle_forces(series, tmp_path / "force.png")
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
