"""Results a user opens: the HDF5 layout (docs/output-format.md) agrees with series.csv and the
VTU files; `geompm plot` writes non-empty PNGs; `geompm info` summarises a run.

References: the files' own formats (PNG signature, HDF5 through plain h5py,
VTU through meshio) and the run's series.csv as the ground truth of the series.
"""

import json

import numpy as np
import pytest

from geompm.cli import main

from tests.support.cases import tiny_case

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("results")
    case = tiny_case()
    case["time"]["end"] = 0.1
    case["obstacles"] = [{"type": "box", "name": "wall", "min": [0.7, 0.0], "max": [0.8, 0.5]}]
    case["bodies"][0]["velocity"] = [1.0, 0.0]
    case["outputs"] = [{"writer": "series", "interval": 0.0}, {"writer": "vtu", "interval": 0.05},
                       {"writer": "hdf5", "interval": 0.05}]
    f = tmp / "case.json"
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--out", str(tmp / "run"), "--quiet"]) == 0
    return tmp / "run"


def test_hdf5_layout_matches_series_and_vtu(finished_run):
    import h5py
    import meshio

    csv = np.genfromtxt(finished_run / "series.csv", delimiter=",", names=True)
    with h5py.File(finished_run / "results.h5") as f:
        assert f.attrs["geompm_version"] and f.attrs["threads"] >= 1 and f.attrs["dimension"] == 2
        assert json.loads(f.attrs["case"])["name"] == "tiny"
        assert "geompm" in json.loads(f.attrs["plugin_versions"])
        for col in csv.dtype.names:
            np.testing.assert_allclose(f[f"series/{col}"][:], csv[col], rtol=1e-9)
        assert "wall_fn" in f["series"]
        np.testing.assert_allclose(f["times"][:], [0.0, 0.05, 0.1], atol=1e-12)
        last = f["particles/000002"]
        assert last.attrs["time"] == pytest.approx(0.1)
        vtu = meshio.read(finished_run / "particles" / "particles_000002.vtu")
        np.testing.assert_array_equal(last["position"][:], vtu.points)
        np.testing.assert_array_equal(last["stress"][:], vtu.point_data["stress"])
        assert last["velocity"].compression == "gzip"


def test_plot_writes_nonempty_pngs(finished_run, capsys):
    assert main(["plot", str(finished_run)]) == 0
    for name in ("series.png", "forces.png", "deposit.png"):
        data = (finished_run / "plots" / name).read_bytes()
        assert data.startswith(PNG_MAGIC) and len(data) > 5000, name


def test_info_summarises_the_run(finished_run, capsys):
    assert main(["info", str(finished_run)]) == 0
    out = capsys.readouterr().out
    status = json.loads((finished_run / "status.json").read_text())
    assert "finished" in out and f"{status['steps']} steps" in out and "peak force   wall:" in out
    assert "particles    64" in out and "HDF5" in out and "VTU/PVD" in out


def test_info_and_plot_refuse_a_folder_that_is_not_a_run(tmp_path, capsys):
    assert main(["info", str(tmp_path)]) == 2
    assert main(["plot", str(tmp_path)]) == 2
    assert "not a geompm run folder" in capsys.readouterr().err
