"""Rigid surfaces in the ParaView output (issue 20, point 1): tessellation and the ``surfaces`` writer.

The tessellations are checked against closed-form areas and lengths; the
writer against the particle series it sits beside: the same times, moving
obstacles displaced by v t exactly, static surfaces written once, and files
that both meshio and VTK's own XML reader load.
"""

from __future__ import annotations

import json
import math
import re

import meshio
import numpy as np
import pytest

from geompm.cli import main
from geompm.contact.tessellate import (box_surface, cylinder_surface, heightfield_surface, plane_surface,
                                         sphere_surface)


def test_tessellations_have_the_closed_form_sizes():
    """Box 0.3 x 0.2 x 0.1 m: area 2(ab + bc + ca) = 0.22 m2 exactly; sphere r = 0.1 m: 4 pi r^2 within 1 %
    (an inscribed polyhedron is smaller); cylinder r = 0.05, L = 0.2 m: 2 pi r L + 2 pi r^2 within 1 %;
    2D disc r = 0.1 m: perimeter 2 pi r within 0.5 %; the plane x + y + z = 1.5 clipped to the unit cube: the
    regular hexagon of side sqrt(2)/2, area 3 sqrt(3)/4 = 1.299 m2 exactly; a 2D plane y = 0.3 across a
    1 m wide grid: 1 m.  No edge is longer than h, the pressure resolution of docs/obstacles.md."""
    h = 0.02
    box = box_surface([0.0, 0.0, 0.0], [0.3, 0.2, 0.1], h)
    assert box.sizes().sum() == pytest.approx(0.22, rel=1e-12)
    sph = sphere_surface([0.5, 0.5, 0.5], 0.1, h)
    assert sph.sizes().sum() == pytest.approx(4 * math.pi * 0.01, rel=0.01)
    cyl = cylinder_surface([0.0, 0.0, 0.0], 0.05, "x", 0.2, h)
    assert cyl.sizes().sum() == pytest.approx(2 * math.pi * 0.05 * 0.2 + 2 * math.pi * 0.05 ** 2, rel=0.01)
    assert np.ptp(cyl.vertices[:, 0]) == pytest.approx(0.2) and np.ptp(cyl.vertices[:, 1]) == pytest.approx(0.1)
    disc = sphere_surface([0.5, 0.5], 0.1, h)
    assert disc.kind == "line" and disc.sizes().sum() == pytest.approx(2 * math.pi * 0.1, rel=0.005)
    hexagon = plane_surface([0.5, 0.5, 0.5], np.ones(3) / math.sqrt(3), np.zeros(3), np.ones(3), 0.1)
    assert hexagon.sizes().sum() == pytest.approx(3 * math.sqrt(3) / 4, rel=1e-12)
    assert np.allclose(hexagon.vertices.sum(axis=1), 1.5)
    seg = plane_surface([0.0, 0.3], [0.0, 1.0], [0.0, 0.0], [1.0, 0.5], h)
    assert seg.sizes().sum() == pytest.approx(1.0, rel=1e-12) and len(seg.cells) == 50
    assert plane_surface([0.0, 2.0], [0.0, 1.0], [0.0, 0.0], [1.0, 0.5], h) is None
    for s in (box, sph, cyl, hexagon):
        p = s.vertices[s.cells]
        assert np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).max() <= h * (1 + 1e-9) or s is hexagon


def test_box_normals_point_outwards_and_heightfield_area():
    """The box's cell normals point away from its centre (the sign the face pressure will use), and a
    height field of the plane z = 0.5 x on 1 m x 1 m has the area sqrt(1 + 0.25) = 1.1180 m2 exactly."""
    box = box_surface([0.0, 0.0, 0.0], [0.3, 0.2, 0.1], 0.05)
    out = ((box.centres() - [0.15, 0.1, 0.05]) * box.normals()).sum(axis=1)
    assert (out > 0).all()
    xs = ys = np.linspace(0.0, 1.0, 11)
    z = 0.5 * xs[:, None] + 0.0 * ys[None, :]
    hf = heightfield_surface(xs, ys, z)
    assert hf.sizes().sum() == pytest.approx(math.sqrt(1.25), rel=1e-12)
    assert (hf.normals()[:, 2] > 0).all()  # up, out of the ground


def _case(tmp_path):
    """A 2D elastic block falling onto a box that moves at 0.5 m/s in x, over a plane floor."""
    raw = {
        "name": "surf", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 0.6], "cell_size": 0.05},
        "time": {"end": 0.1, "cfl": 0.4}, "gravity": [0.0, -9.81],
        "materials": {"m": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1e5,
                            "poisson_ratio": 0.3}},
        "bodies": [{"material": "m", "geometry": {"type": "box", "min": [0.4, 0.3], "max": [0.6, 0.4]}}],
        "boundaries": [{"type": "plane", "point": [0.0, 0.05], "normal": [0.0, 1.0]}],
        "obstacles": [{"type": "box", "name": "sled", "min": [0.2, 0.1], "max": [0.4, 0.2], "velocity": [0.5, 0.0]}],
        "outputs": [{"writer": "vtu", "interval": 0.025}, {"writer": "surfaces", "interval": 0.025}],
    }
    path = tmp_path / "surf.json"
    path.write_text(json.dumps(raw))
    return path


def _pvd(path):
    return re.findall(r'timestep="([^"]+)" group="" part="(\d+)" file="([^"]+)"', path.read_text())


def test_surfaces_writer_series(tmp_path):
    """`geompm run` with the surfaces writer: surfaces.pvd has the particle PVD's times, each with the plane
    and the box as parts; the box moves by v t = 0.5 t m exactly at every output and the plane is one file
    listed at every time; meshio and VTK's XML reader both load each file with its cell count and a unit
    normal per cell (the floor's normal is +y)."""
    vtk = pytest.importorskip("vtk")
    out = tmp_path / "run"
    assert main(["run", str(_case(tmp_path)), "--out", str(out), "--quiet"]) == 0
    surf = _pvd(out / "surfaces.pvd")
    times = sorted({float(t) for t, _, _ in _pvd(out / "particles.pvd")})
    assert sorted({float(t) for t, _, _ in surf}) == times and len(times) == 5
    plane_files = {f for t, p, f in surf if p == "0"}
    assert len(plane_files) == 1
    floor = meshio.read(out / plane_files.pop())
    assert np.allclose(floor.points[:, 1], 0.05) and np.allclose(floor.cell_data["normal"][0], [0, 1, 0])
    box0 = None
    for t, p, f in surf:
        if p != "1":
            continue
        m = meshio.read(out / f)
        box0 = m.points if box0 is None else box0
        assert np.allclose(m.points[:, 0] - box0[:, 0], 0.5 * float(t), atol=1e-12)
        assert np.allclose(m.points[:, 1], box0[:, 1])
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(str(out / f))
        r.Update()
        grid = r.GetOutput()
        assert grid.GetNumberOfCells() == len(m.cells[0].data) == 12  # perimeter 0.6 m in 0.05 m pieces
        assert grid.GetCellData().GetArray("normal").GetNumberOfComponents() == 3
    assert box0[:, 0].min() == pytest.approx(0.2)


def test_pressure_fields_hot_spot_and_plot(tmp_path, capsys):
    """The box of the writer test carries its face pressures: the last file's max_normal_pressure peaks at
    the value, face centre and time that status.json and `geompm info` name as the hot spot, every
    normal_pressure is at most the running maximum, and `geompm plot` draws pressure.png."""
    out = tmp_path / "run"
    assert main(["run", str(_case(tmp_path)), "--out", str(out), "--quiet"]) == 0
    status = json.loads((out / "status.json").read_text())["obstacles"]["sled"]
    last = sorted(f for t, p, f in _pvd(out / "surfaces.pvd") if p == "1")[-1]
    m = meshio.read(out / last)
    pmax, p = m.cell_data["max_normal_pressure"][0], m.cell_data["normal_pressure"][0]
    assert status["peak_pressure"] == pytest.approx(pmax.max(), rel=1e-12) and pmax.max() > 0.0
    assert (p <= pmax + 1e-9).all()
    k = int(np.argmax(pmax))
    centre = m.points[m.cells[0].data[k]].mean(axis=0)
    t_peak = m.cell_data["time_of_max"][0][k]
    assert status["peak_pressure_time"] == pytest.approx(t_peak)
    # the file is at t = 0.1 s; the hot spot is where the face was at t_peak (the box moves at 0.5 m/s)
    assert np.allclose(status["peak_pressure_at"], centre[:2] - [0.5 * (0.1 - t_peak), 0.0], atol=1e-9)
    capsys.readouterr()
    assert main(["info", str(out)]) == 0
    assert f"hot spot     sled: face pressure {status['peak_pressure']:.4g} Pa" in capsys.readouterr().out
    pytest.importorskip("matplotlib")
    assert main(["plot", str(out)]) == 0
    assert (out / "plots" / "pressure.png").stat().st_size > 10_000
