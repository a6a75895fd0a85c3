"""Failing well: a killed run leaves only readable files; unstable runs stop with exit 3 and a
diagnosis; particles leaving the grid are an error or deleted as the case asks.

References: the file formats themselves (VTU through meshio, PVD as XML, HDF5 through
h5py, CSV rows with the header's column count), and energy conservation for the
blow-up check (docs/method.md): a fixed step at Courant number 5 on an elastic body is
past the explicit stability limit (Courant <= 1), so its energy must blow up.
"""

import json
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

from geompm.cli import main

from tests.support.cases import tiny_case


def _write(tmp_path, case, name="case.json"):
    f = tmp_path / name
    f.write_text(json.dumps(case))
    return f


def test_sigkill_during_output_leaves_every_file_readable(tmp_path):
    """SIGKILL while VTU, PVD, HDF5 and CSV files are being written every few steps: every file
    a reader would open (not the hidden temporary ones) opens and is complete."""
    import h5py
    import meshio

    case = tiny_case()
    case["grid"]["cell_size"] = 0.02
    case["time"]["end"] = 50.0
    case["bodies"][0]["velocity"] = [0.0, 0.5]
    case["outputs"] = [{"writer": "vtu", "interval": 0.002}, {"writer": "series", "interval": 0.0},
                       {"writer": "hdf5", "interval": 0.002}]
    f = _write(tmp_path, case)
    run = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "geompm.cli", "run", str(f), "--out", str(run), "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while time.time() < deadline and len(list((run / "particles").glob("*.vtu"))) < 40:
        time.sleep(0.02)
    time.sleep(0.137)  # somewhere inside the stream of outputs
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    vtus = sorted((run / "particles").glob("particles_*.vtu"))
    assert len(vtus) >= 40
    for v in vtus:
        assert meshio.read(v).points.shape[1] == 3
    listed = [ds.get("file") for ds in ET.parse(run / "particles.pvd").getroot().iter("DataSet")]
    assert listed and all((run / name).is_file() for name in listed)
    lines = (run / "series.csv").read_text().splitlines()
    ncol = len(lines[0].split(","))
    assert len(lines) > 40 and all(len(ln.split(",")) == ncol for ln in lines[1:])
    with h5py.File(run / "results.h5") as res:
        n = len(res["times"])
        assert n >= 1
        for k in range(n):
            assert res[f"particles/{k:06d}/position"].shape[1] == 3
        assert len(res["series/time"]) >= n
    for h in (run / "results").glob("particles_*.h5"):
        with h5py.File(h) as one:
            assert one["velocity"].shape[1] == 3


def test_courant_5_blows_up_and_exits_3(tmp_path, capsys):
    """A fixed step 5x the wave-crossing time of a cell (c = sqrt(M/rho) for the elastic block)."""
    case = tiny_case()
    e, nu, rho, h = 1.0e6, 0.3, 2000.0, 0.1
    c = np.sqrt(e * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho)
    case["time"] = {"end": 1.0, "dt": 5 * h / c}
    case["outputs"] = [{"writer": "series", "interval": 0.0}]
    f = _write(tmp_path, case)
    run = tmp_path / "run"
    assert main(["run", str(f), "--out", str(run), "--quiet"]) == 3
    out = capsys.readouterr().out
    assert "at step" in out and "particle" in out and "body 0" in out and "material 'soil'" in out
    assert "Courant number above 1" in out
    status = json.loads((run / "status.json").read_text())
    assert status["finished"] is False and "unphysical" in status["reason"]
    lines = (run / "series.csv").read_text().splitlines()
    assert len(lines) > 2  # the output before the blow-up is kept


def test_tiny_viscous_step_stops_with_the_cause(tmp_path, capsys):
    """The Cross law with mu_0 = 1e4 mu_inf at h = 0.1 m: dt = h^2 rho / (4 mu_0) ~ 0.5 ms; with
    dt_min above it the run stops before the first step and names mu_0 and the remedy."""
    case = tiny_case()
    case["materials"] = {"mud": {"model": "cross", "density": 2000.0, "sound_speed": 20.0,
                                 "viscosity_infinity": 1.0, "viscosity_zero": 1.0e4, "time_constant": 10.0}}
    case["bodies"][0]["material"] = "mud"
    case["time"]["dt_min"] = 1e-3
    case["outputs"] = []
    f = _write(tmp_path, case)
    rc = main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"])
    out = capsys.readouterr().out
    assert rc == 3, out
    assert "below time.dt_min" in out and "viscous limit" in out and "'mud'" in out and "mu_0" in out


def _flying_case(mode):
    case = tiny_case()
    case["boundaries"] = []
    case["gravity"] = [0.0, 0.0]
    case["bodies"][0]["geometry"] = {"type": "box", "min": [0.6, 0.4], "max": [0.8, 0.6]}
    case["bodies"][0]["velocity"] = [5.0, 0.0]
    case["time"]["end"] = 0.2
    case["run"] = {"on_leave_domain": mode}
    case["outputs"] = [{"writer": "series", "interval": 0.0}]
    return case


def test_leaving_the_grid_is_an_error_by_default(tmp_path, capsys):
    f = _write(tmp_path, _flying_case("error"))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 3
    out = capsys.readouterr().out
    assert "left the grid" in out and "on_leave_domain" in out and "body 0" in out


def test_leaving_the_grid_deletes_when_asked(tmp_path, capsys):
    """A block at 5 m/s leaves the 1 m grid within 0.2 s: every particle is deleted, with one warning."""
    f = _write(tmp_path, _flying_case("delete"))
    assert main(["run", str(f), "--out", str(tmp_path / "run")]) == 0
    out = capsys.readouterr().out
    assert out.count("were deleted (run.on_leave_domain = delete)") == 1
    status = json.loads((tmp_path / "run" / "status.json").read_text())
    assert status["deleted_particles"] == 16 and status["particles"] == 0
    assert (tmp_path / "run" / "run.log").read_text().count("were deleted (run.on_leave_domain") == 1
