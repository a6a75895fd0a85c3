"""A new user's mistakes, each answered before any work: the table of the first-contact report, as tests.

Each scene is a small variant of a shipped case; each test says what the user did and what geompm must
now say (exit code, JSON path, the number that explains it).  References are the inputs themselves: the
mesh's true size, the stable step cfl h / c with c the P-wave speed sqrt((lambda + 2G) / rho), the
particles' volume (h / ppc)^d.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from geompm.cli import main

from tests.support.cases import CASES, tiny_case


def _write(tmp_path, case, name="case.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(case))
    return path


def _debris(tmp_path, **obstacle) -> Path:
    raw = json.loads((CASES / "debris_obstacle.json").read_text())
    raw["obstacles"][0].update(obstacle)
    raw["outputs"] = []
    return _write(tmp_path, raw)


def test_cylinder_pier_validates_within_memory(tmp_path):
    """trimesh.creation.cylinder(radius=0.1, height=0.6) as a rigid_mesh pier in the main job's flume: before,
    `geompm validate` grew past 20 GB (thinnest part 3e-10 m); now it validates in a child process whose peak
    resident memory stays under 1 GiB (measured in a second child, after the first filled numba's cache), and the pier's thinnest part is its 0.2 m diameter (32 sections:
    2 r cos(pi/32) = 0.19904 m), which the thin-obstacle warning does not mention (two cells at h = 0.05 m)."""
    trimesh.creation.cylinder(radius=0.1, height=0.6).export(tmp_path / "pier.stl")
    case = _debris(tmp_path, file="pier.stl", rotate=[90.0, 0.0, 0.0], translate=[2.7, 0.3, 0.25])
    code = ("import resource, sys; from geompm.cli import main; rc = main(['validate', sys.argv[1]]); "
            "print('RSS', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024); sys.exit(rc)")
    subprocess.run([sys.executable, "-c", code, str(case)], capture_output=True, timeout=600)  # fills the cache
    out = subprocess.run([sys.executable, "-c", code, str(case)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    rss = int(out.stdout.split("RSS")[-1])
    assert rss < 2**30, f"peak {rss / 2**20:.0f} MiB"
    from geompm.api import scene_from_file

    pier = scene_from_file(case).obstacles[0]
    assert pier.thickness == pytest.approx(0.2 * np.cos(np.pi / 32), rel=1e-6)  # float32 STL coordinates
    assert pier.guard_h == pytest.approx(0.05 / 4)


def test_mesh_in_millimetres_is_refused_with_the_scale(tmp_path, capsys):
    """A 100 x 300 x 100 box STL drawn in millimetres without `scale`: before, a traceback asking for 180 GiB;
    now exit 2 at obstacles.0.scale, naming its 300 m height against the 3.6 m grid and scale 0.001."""
    box = trimesh.creation.box([100.0, 300.0, 100.0])
    box.apply_translation([50.0, 150.0, 50.0])
    box.export(tmp_path / "box_mm.stl")
    case = _debris(tmp_path, file="box_mm.stl", translate=[2.65, 0.0, 0.2])
    assert main(["validate", str(case)]) == 2
    err = capsys.readouterr().err
    assert "obstacles.0.scale" in err and "300 m along y" in err and '"scale": 0.001' in err


def test_memory_cap_refuses_before_allocating(tmp_path, monkeypatch, capsys):
    """With GEOMPM_MAX_MEMORY=1M the main job's dam lattices do not fit: exit 2 at obstacles.0, with the GiB
    the lattice would need and what to change; a malformed cap is itself refused."""
    monkeypatch.setenv("GEOMPM_MAX_MEMORY", "1M")
    assert main(["validate", str(CASES / "debris_obstacle.json")]) == 2
    err = capsys.readouterr().err
    assert "obstacles.0" in err and "GiB" in err and "GEOMPM_MAX_MEMORY cap" in err and "cell_size" in err
    monkeypatch.setenv("GEOMPM_MAX_MEMORY", "lots")
    assert main(["validate", str(CASES / "debris_obstacle.json")]) == 2
    assert "GEOMPM_MAX_MEMORY" in capsys.readouterr().err


def test_body_inside_an_obstacle_or_behind_a_plane_is_refused(tmp_path, capsys):
    """A box obstacle over the initial debris: before, 343 957 guard corrections and a spurious 49.3 kN/m
    peak; now exit 2 with both JSON paths and the overlapping volume.  The box [0.3, 0.6] x [1.7, 2.2] x
    [0.1, 0.4] m takes 1 632 particles of (0.025 m)^3 = 0.0255 m3.  A 2D block sunk 0.2 m below a wall's
    plane: its particles behind the plane are counted the same way (0.2 x 0.4 m = 0.08 m2 per metre)."""
    raw = json.loads((CASES / "debris_obstacle.json").read_text())
    raw["obstacles"] = [{"type": "box", "name": "wall", "min": [0.3, 1.7, 0.1], "max": [0.6, 2.2, 0.4]}]
    raw["outputs"] = []
    assert main(["validate", str(_write(tmp_path, raw))]) == 2
    err = capsys.readouterr().err
    assert "bodies.0.geometry: 1632 particles (0.0255 m3) start inside obstacles.0 ('wall')" in err
    case = tiny_case(boundaries=[{"type": "plane", "point": [0.0, 0.2], "normal": [0.0, 1.0], "condition": "slip"}])
    assert main(["validate", str(_write(tmp_path, case, "sunk.json"))]) == 2
    err = capsys.readouterr().err
    assert "bodies.0.geometry" in err and "boundaries.0" in err and "(0.08 m2 (per metre of depth))" in err


def test_wrong_units_are_warned_with_their_paths(tmp_path, capsys):
    """Friction angle 0.576 (radians), cohesion 2 (kPa meant), density 1.9 (t/m3 meant) on the landslide: each
    warned at its JSON path with the likely unit and the converted value (0.576 rad = 33 deg)."""
    sets = ["materials.slope.friction_angle=0.576", "materials.slope.cohesion=2", "materials.slope.density=1.9"]
    assert main(["validate", str(CASES / "landslide.json"), *[x for s in sets for x in ("--set", s)]]) == 0
    out = capsys.readouterr().out
    assert "warning: materials.slope.friction_angle: friction_angle = 0.576: below 1.6 deg, which looks like " \
           "radians (0.576 rad is 33 deg)" in out
    assert "warning: materials.slope.cohesion:" in out and "kPa?" in out.replace("given in kPa?", "kPa?")
    assert "warning: materials.slope.density:" in out and "1900 kg/m3" in out
    assert "materials.foundation" not in out  # its 50 kPa cohesion and 35 deg are plausible


def test_a_soft_modulus_is_explained_before_the_interval_is_blamed(tmp_path, capsys):
    """Young's modulus 20 (MPa meant) on the landslide: the refusal of outputs.0.interval now says the step is
    the wave limit and that the wave is slow (c = sqrt((lambda + 2G)/rho) = 0.116 m/s at E = 20 Pa,
    rho = 2000 kg/m3, nu = 0.3), and the modulus warning names youngs_modulus and MPa."""
    sets = [x for m in ("slope", "weak_clay", "foundation") for x in ("--set", f"materials.{m}.youngs_modulus=20")]
    assert main(["validate", str(CASES / "landslide.json"), *sets]) == 2
    err = capsys.readouterr().err
    lam_2g = 20 * 0.7 / (1.3 * 0.4)
    c = np.sqrt(lam_2g / 2000.0)
    assert f"c = {c:.3g} m/s" in err and "wave limit" in err and "outputs.0.interval" in err
    assert "warning: materials.slope.youngs_modulus" in err and "MPa" in err


def test_fixed_step_above_the_stable_step_is_refused_by_validate(tmp_path, capsys):
    """time.dt = 0.01 s on the landslide, 29x the stable 3.45e-4 s (cfl 0.4, h = 0.1 m, c = 116 m/s): validate
    exits 2 at time.dt with the stable value; a fixed step below it validates."""
    assert main(["validate", str(CASES / "landslide.json"), "--set", "time.dt=0.01"]) == 2
    err = capsys.readouterr().err
    assert "time.dt: 0.01 s is 29x the stable step 0.000345 s" in err and "time.dt <= 0.000345 s" in err
    assert main(["validate", str(CASES / "landslide.json"), "--set", "time.dt=0.0003"]) == 0


def test_info_reports_each_bodys_front(tmp_path, capsys):
    """The landslide after 0.3 s: series.csv has a front column per body and per material, and `geompm info`
    marks the slope's toe (bodies.2, from 4.975 m) as the runout, not the foundation's edge at 13.975 m."""
    run = tmp_path / "ls"
    assert main(["run", str(CASES / "landslide.json"), "--set", "time.end=0.3", "--set", "outputs=[]",
                 "--quiet", "--out", str(run)]) == 0
    head = (run / "series.csv").read_text().splitlines()[0].split(",")
    assert {"front_x_body0", "front_x_body1", "front_x_body2", "front_x_slope", "front_x_foundation"} <= set(head)
    capsys.readouterr()
    assert main(["info", str(run)]) == 0
    out = capsys.readouterr().out
    toe = [ln for ln in out.splitlines() if "<- the runout" in ln]
    assert len(toe) == 1 and "bodies.2 (slope)" in toe[0] and "from 4.975 m" in toe[0]
    assert "bodies.0 (foundation): front x = 13.975 m" in out
    from geompm.study.metrics import read_run, scalar_metrics

    metrics = scalar_metrics(*read_run(run))
    assert metrics["runout"] == pytest.approx(metrics["runout:body2"]) and metrics["runout:foundation"] == pytest.approx(13.975, abs=1e-4)


def test_study_summary_is_strict_json():
    """The strict writer turns NaN and infinities into null (study_summary.json held bare NaN)."""
    from geompm.files.atomic import strict_json

    text = strict_json({"order": float("nan"), "runs": [np.float64(np.inf), np.int64(3)]})
    assert json.loads(text) == {"order": None, "runs": [None, 3]} and "NaN" not in text


def test_zero_area_faces_are_dropped_before_the_watertight_check(tmp_path):
    """A closed box STL with two zero-area triangles (as CAD exports leave them) was refused as 'not
    watertight'; the degenerate faces enclose nothing, so they are dropped and the 12 real faces load."""
    from geompm.files.mesh import load_surface_mesh

    box = trimesh.creation.box([0.3, 0.2, 0.1])
    bad = trimesh.Trimesh(box.vertices, np.vstack([box.faces, [[0, 0, 1], [2, 3, 3]]]), process=False)
    bad.export(tmp_path / "deg.stl")
    mesh = load_surface_mesh(tmp_path / "deg.stl", 1.0, [0.0, 0.0, 0.0], "obstacles.0.file")
    assert len(mesh.faces) == 12 and mesh.is_watertight
    assert mesh.volume == pytest.approx(0.3 * 0.2 * 0.1, rel=1e-6)
