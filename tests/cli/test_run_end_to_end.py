"""`geompm run` on a tiny case: run folder contents, VTU read back with meshio, PVD times.

The tiny case is a 0.4 m x 0.4 m elastic block (rho = 2000 kg/m3) on a slip
floor: 64 particles, total mass rho * area = 320 kg per metre of thickness.
"""

import json
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from geompm.cli import main

from tests.support.cases import tiny_case


def test_run_writes_readable_vtu_and_matching_pvd(tmp_path):
    case = tmp_path / "tiny.json"
    case.write_text(json.dumps(tiny_case()))
    out = tmp_path / "run"
    assert main(["run", str(case), "--out", str(out), "--quiet"]) == 0
    for name in ("case.json", "series.csv", "run.log", "particles.pvd"):
        assert (out / name).is_file(), name
    assert json.loads((out / "case.json").read_text())["name"] == "tiny"

    entries = ET.parse(out / "particles.pvd").getroot().find("Collection").findall("DataSet")
    times = np.array([float(e.get("timestep")) for e in entries])
    np.testing.assert_allclose(times, np.arange(6) * 0.01, atol=1e-12)
    for e in entries:
        mesh = meshio.read(out / e.get("file"))
        pd = mesh.point_data
        assert mesh.points.shape == (64, 3)
        assert np.all(mesh.points[:, 2] == 0.0)
        assert pd["stress"].shape == (64, 6) and pd["velocity"].shape == (64, 3)
        mass = (pd["density"] * pd["volume"]).sum()
        assert mass == pytest.approx(320.0, rel=1e-9)  # mass is exactly conserved
        p = pd["mean_stress_p"]
        np.testing.assert_allclose(p, -pd["stress"][:, :3].sum(axis=1) / 3, rtol=1e-12)
    # after 0.05 s of gravity the block has compressed: mean stress at the base is compressive
    last = meshio.read(out / entries[-1].get("file"))
    assert last.point_data["mean_stress_p"].max() > 0.0

    series = np.genfromtxt(out / "series.csv", delimiter=",", names=True)
    assert series["time"][0] == 0.0 and series["time"][-1] == pytest.approx(0.05, abs=1e-12)
    assert np.all(np.diff(series["step"]) == 1)  # interval 0: one row per step
    assert series["kinetic_energy"][0] == 0.0 and series["kinetic_energy"][-1] > 0.0


def test_run_refuses_to_overwrite(tmp_path, capsys):
    case = tmp_path / "tiny.json"
    case.write_text(json.dumps(tiny_case()))
    out = tmp_path / "run"
    assert main(["run", str(case), "--out", str(out), "--quiet"]) == 0
    assert main(["run", str(case), "--out", str(out), "--quiet"]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert main(["run", str(case), "--out", str(out), "--quiet", "--overwrite"]) == 0


def test_series_normalised_columns(tmp_path):
    """T_star = t sqrt(g/h0), X_star = (x_front - l0)/l0, K_star = E_k/(m g h0) (source study, section 3.1).

    Tiny case: block 0.4 x 0.4 m from x = 0.2 m, rho = 2000 kg/m3 -> m = 320 kg/m; l0 = 0.4, h0 = 0.4,
    front measured along +x from x = 0.2 m.
    """
    case = tiny_case()
    case["outputs"] = [{"writer": "series", "interval": 0.01, "normalise": {
        "length": 0.4, "height": 0.4, "origin": [0.2, 0.0], "direction": [2.0, 0.0]}}]
    f = tmp_path / "tiny.json"
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    s = np.genfromtxt(tmp_path / "run" / "series.csv", delimiter=",", names=True)
    g = 9.81
    np.testing.assert_allclose(s["T_star"], s["time"] * np.sqrt(g / 0.4), rtol=1e-9)
    np.testing.assert_allclose(s["X_star"], (s["front_x"] - 0.2 - 0.4) / 0.4, atol=1e-9)  # CSV keeps 10 digits
    np.testing.assert_allclose(s["K_star"], s["kinetic_energy"] / (320.0 * g * 0.4), rtol=1e-9)
    assert s["X_star"][0] == pytest.approx(-0.0625, abs=1e-12)  # front particle at 0.575 m: half a spacing inside
