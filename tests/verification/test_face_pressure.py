"""The contact force spread onto an obstacle's faces (issue 20, point 2; docs/obstacles.md).

Each contact node's and guard correction's force is shared among the faces
of its surface patch (sdf_field.face_lattice_ids, contact/force.record_on_face),
so the faces' forces add up to the obstacle's force by construction; the
tests check that bookkeeping, and the pressures against closed forms.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

from .test_obstacles import _drop

SURFACES = [{"writer": "surfaces", "interval": 0.05}]


class Balance:
    """After each step: the largest |sum of the faces' forces - the stage's force| / |force| so far, and
    the number of loaded steps."""

    def __init__(self, stage):
        self.stage, self.worst, self.loaded = stage, 0.0, 0

    def __call__(self):
        f = np.linalg.norm(self.stage.force)
        if f > 0.0:
            self.loaded += 1
            self.worst = max(self.worst, np.linalg.norm(self.stage.face_force.sum(axis=0) - self.stage.force) / f)


def _step_to(sim, end, each=None):
    while sim.time < end * (1 - 1e-12):
        sim.step(min(sim.stable_dt(), end - sim.time))
        if each is not None:
            each()


@pytest.mark.parametrize("dim", [2, 3])
def test_face_forces_add_up_to_the_obstacle_force(dim, tmp_path):
    """An elastic block thrown onto a box (2D) and onto an STL slab (3D, trimesh box 0.4 x 0.12 x 0.4 m):
    at every step the faces' forces sum to the force in series.csv within 1e-9 of |F| (the issue asks
    2 %), the guard's corrections included, and the largest pressure is on the struck top face."""
    if dim == 2:
        raw = _drop(2, {"type": "box", "name": "wall", "min": [0.2, 0.1], "max": [0.8, 0.3]}, 0.02, end=0.15)
        top = 0.3
    else:
        trimesh.creation.box(extents=[0.4, 0.12, 0.4]).export(tmp_path / "slab.stl")
        raw = _drop(3, {"type": "rigid_mesh", "name": "slab", "file": str(tmp_path / "slab.stl"),
                        "translate": [0.3, 0.14, 0.3]}, 0.04, end=0.12)
        top = 0.2
    raw["outputs"] = SURFACES
    sim = Simulation(scene_from_dict(raw))
    ob = sim.scene.obstacles[0]
    check = Balance(ob)
    _step_to(sim, raw["time"]["end"], check)
    assert check.loaded > 10 and check.worst < 1e-9
    peak, where, when = ob.hot_spot()
    assert peak > 0.0 and where[1] == pytest.approx(top) and 0.0 < when <= raw["time"]["end"]


@pytest.mark.slow
def test_check_dam_faces_add_up_at_every_step():
    """cases/debris_obstacle.json at h = 0.1 m (the STL check dam of cases/meshes, 590 particles) to 2 s,
    with its surfaces writer: the dam's faces add up to its force within 1e-9 at every step of the impact,
    and the hot spot lies on the dam's upstream face (x = 2.6 m, the face the debris reaches first)."""
    import json
    from pathlib import Path

    from geompm.schema.load import apply_overrides

    root = Path(__file__).resolve().parents[2]
    raw = json.loads((root / "cases" / "debris_obstacle.json").read_text())
    raw = apply_overrides(raw, ["grid.cell_size=0.1", "time.end=2.0"])
    sim = Simulation(scene_from_dict(raw, root / "cases"))
    dam = sim.scene.obstacles[0]
    check = Balance(dam)
    _step_to(sim, 2.0, check)
    assert check.loaded > 100 and check.worst < 1e-9
    assert dam.hot_spot()[1][0] == pytest.approx(2.6, abs=1e-9)


def _hydrostatic(h: float, x0: float):
    """Water (rho 1000 kg/m3, c 30 m/s, geostatic start) 0.4 m deep against a slip plate whose wet face is
    at x = x0, on a slip floor; the plate reaches below the floor, so that no seam is left between them.
    Returns the left face's centres y, its mean pressures over t = 0.4-0.6 s and their areas."""
    raw = {"name": "hydro", "dimension": 2, "grid": {"origin": [0, 0], "extent": [0.5, 0.5], "cell_size": h},
           "time": {"end": 0.6, "cfl": 0.4}, "gravity": [0, -9.81],
           "materials": {"w": {"model": "newtonian", "density": 1000.0, "viscosity": 1e-3, "sound_speed": 30.0}},
           "bodies": [{"material": "w", "geometry": {"type": "box", "min": [0, 0], "max": [x0, 0.4]},
                       "initial_stress": "geostatic"}],
           "boundaries": [{"type": "wall", "side": "x-", "condition": "slip"},
                          {"type": "wall", "side": "y-", "condition": "slip"}],
           "obstacles": [{"type": "box", "name": "plate", "min": [x0, -0.1], "max": [x0 + 0.12, 0.48],
                          "condition": "slip"}],
           "damping": [{"model": "artificial", "xi": 0.01}], "outputs": SURFACES}
    sim = Simulation(scene_from_dict(raw))
    ob = sim.scene.obstacles[0]
    wet = np.abs(ob.face_centre[:, 0] - x0) < 1e-9
    acc, n = np.zeros(wet.sum()), [0]

    def add():
        if sim.time > 0.4:
            acc[:] += ob.face_pressure[wet]
            n[0] += 1

    _step_to(sim, 0.6, add)
    return ob.face_centre[wet, 1], acc / n[0], ob.face_area[wet]


@pytest.mark.parametrize("h", [0.02, 0.01])
def test_hydrostatic_pressure_on_a_plate(h):
    """p = rho g (H - y) on the wet face within 5 % on every face from 1.5 h above the floor to below the top
    cell (measured 1.5-3.3 % at h = 0.02 m, 0.6-3.6 % at 0.01 m; at h = 0.04 m, 10 cells of depth, the
    faces scatter by +-50 %: docs/obstacles.md), the resultant rho g H^2 / 2 = 784.8 N/m within 2 %
    (measured +0.01 %, -0.11 %) and its point at H / 3 above the floor within 2 % (-1.5 %, -0.9 %)."""
    H = 0.4
    y, p, a = _hydrostatic(h, 0.3)
    closed = 1000.0 * 9.81 * (H - y)
    inner = (y > 1.5 * h) & (y < H - h)
    assert np.abs(p[inner] / closed[inner] - 1.0).max() < 0.05
    force = (p * a).sum()
    assert force == pytest.approx(0.5 * 1000.0 * 9.81 * H ** 2, rel=0.02)
    assert (p * a * y).sum() / force == pytest.approx(H / 3, rel=0.02)


def test_stream_pressure_at_the_stagnation_zone():
    """The steady stream of tests/verification/test_wall_force.py (v = 2 m/s, d = 0.1 m, h = 0.01 m) on the slip wall:
    over t = 0.2-0.45 s the face pressures integrate to the wall's mean force exactly (1e-9), and over the
    flow depth (0 < y < d) their mean and peak are within 15 % of the Bernoulli head of the turned stream,
    rho (g d + v^2 / 2) = 2981 Pa = 0.745 rho v^2 (stagnation plus the run-up's weight; the hydrostatic +
    dynamic family p = rho (k g h + alpha v^2) of Armanini 1997 with k = 1, alpha = 1/2;
    tests/refdata/debris_flow_impact_design_formulas.csv).  Measured 0.66 and 0.82 rho v^2 (at h = 0.02,
    0.01, 0.005 m: mean 0.57, 0.66, 0.66; peak 0.87, 0.82, 0.82).  The design alpha of 1 to 2.5 in the
    stream test is the force per flow depth (here 1.11): the pressure spreads over the run-up, 2.5 d."""
    from .test_wall_force import D, RHO, V, stream_case

    case = {**stream_case(), "outputs": SURFACES}
    sim = Simulation(scene_from_dict(case))
    ob = sim.scene.obstacles[0]
    acc, impulse, span = np.zeros(len(ob.face_area)), [0.0], [0.0]

    def add():
        if sim.time > 0.2:
            acc[:] += ob.face_pressure
            impulse[0] += ob.force[0]
            span[0] += 1

    _step_to(sim, 0.45, add)
    p = acc / span[0]
    c = ob.face_centre
    wet = np.abs(c[:, 0] - 1.4) < 1e-9
    assert (p[wet] * ob.face_area[wet]).sum() == pytest.approx(impulse[0] / span[0], rel=1e-9)
    zone = wet & (c[:, 1] > 0.0) & (c[:, 1] < D)
    head = RHO * (9.81 * D + 0.5 * V ** 2)
    mean = (p[zone] * ob.face_area[zone]).sum() / ob.face_area[zone].sum()
    assert mean == pytest.approx(head, rel=0.15) and p[zone].max() == pytest.approx(head, rel=0.15)


def test_terrain_faces_carry_the_block(tmp_path):
    """The elastic block sliding on the DEM of a 30 deg slope turned 37 deg about the vertical
    (tests/verification/test_terrain.py, h = 0.05 m, DEM pixel 0.05 m): with the surfaces writer the terrain's force is
    shared among its DEM triangles (terrain.record_on_dem_faces); at every step they add up to the
    terrain's force within 1e-9, and the running maximum of the pressure lies under the block's path
    (every face with more than 1 % of the peak is within 0.3 m of the particles' path, the block's
    diagonal)."""
    pytest.importorskip("rasterio")
    from geompm.testing.verification.terrain_block import block_case

    case, _, _ = block_case(tmp_path, 30.0, 37.0, 0.3, "terrain")
    case["outputs"] = SURFACES
    sim = Simulation(scene_from_dict(case, base_dir=tmp_path))
    ground = sim.scene.obstacles[0]
    balance, path = Balance(ground), []

    def check():
        balance()
        path.append(sim.state.p_x.mean(axis=0))

    _step_to(sim, 0.3, check)
    assert balance.loaded > 10 and balance.worst < 1e-9 and ground.face_pmax.max() > 0.0
    hot = ground.face_pmax > 0.01 * ground.face_pmax.max()
    from scipy.spatial import cKDTree

    dist = cKDTree(np.array(path)[:, :2]).query(ground.face_centre[hot, :2])[0]
    assert dist.max() < 0.3


@pytest.mark.parametrize("dim", [2, 3])
def test_traction_integrates_to_the_series_force(dim, tmp_path):
    """The surfaces writer's ``traction`` cell vector [Pa], integrated over the obstacle's surface by VTK's
    vtkIntegrateAttributes (what ParaView's Integrate Variables runs), gives the force in series.csv at the
    same output time within 1 % of |F| (the issue's bound; the faces' forces add up exactly, so the measured
    difference is round-off), at every loaded output of the 2D box and the 3D STL slab impacts."""
    import csv

    from vtkmodules.vtkFiltersParallel import vtkIntegrateAttributes
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    from geompm.cli import main

    if dim == 2:
        raw = _drop(2, {"type": "box", "name": "wall", "min": [0.2, 0.1], "max": [0.8, 0.3]}, 0.02, end=0.15)
    else:
        trimesh.creation.box(extents=[0.4, 0.12, 0.4]).export(tmp_path / "slab.stl")
        raw = _drop(3, {"type": "rigid_mesh", "name": "wall", "file": str(tmp_path / "slab.stl"),
                        "translate": [0.3, 0.14, 0.3]}, 0.04, end=0.12)
    raw["outputs"] = [{"writer": "surfaces", "interval": 0.004}, {"writer": "series", "interval": 0.004}]
    case = tmp_path / "case.json"
    case.write_text(__import__("json").dumps(raw))
    assert main(["run", str(case), "--quiet", "--out", str(tmp_path / "run")]) == 0
    with open(tmp_path / "run" / "series.csv") as fh:
        rows = list(csv.DictReader(fh))
    files = sorted((tmp_path / "run" / "surfaces").glob("wall_*.vtu"))
    assert len(files) == len(rows)
    loaded, worst = 0, 0.0
    for row, f in zip(rows, files):
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(f))
        integ = vtkIntegrateAttributes()
        integ.SetInputConnection(reader.GetOutputPort())
        integ.Update()
        total = np.array(integ.GetOutput().GetCellData().GetArray("traction").GetTuple3(0))[:dim]
        force = np.array([float(row[f"wall_f{c}"]) for c in "xyz"[:dim]])
        if np.linalg.norm(force) > 0.0:
            loaded += 1
            worst = max(worst, np.linalg.norm(total - force) / np.linalg.norm(force))
    assert loaded >= 3 and worst < 0.01, (loaded, worst)
