"""The filtered peak force of the new user's 2D flume (cases/flume_impact_2d.json) at the coarse pair of its
convergence study (docs/impact-forces.md; the full study at h = 0.05 / 0.025 / 0.0125 / 0.00625 m and cfl 0.4 /
0.2 is in benchmarks/results/2026-12-05-issue57/): within 10 % between h = 0.05 and 0.025 m (measured
-5.8 %) and within 5 % between cfl 0.4 and 0.2 (measured +1.4 %); and the cause of the peak's old drift, the
artificial damping's rate tied to h: without ``reference_cell_size`` the peak at h = 0.025 m falls by more
than 15 % (measured -25.0 %: the flow that arrives is slower)."""

import json

import pytest

import geompm
from tests.support.cases import CASES


def _filtered_peak(tmp_path, name, *sets):
    run = geompm.run(CASES / "flume_impact_2d.json", out=tmp_path / name, overrides=list(sets), quiet=True)
    assert run.exit_code == 0
    return json.loads((run.folder / "status.json").read_text())["obstacles"]["wall"]


@pytest.fixture(scope="module")
def peaks(tmp_path_factory):
    d = tmp_path_factory.mktemp("flume")
    return {
        "h05": _filtered_peak(d, "h05"),
        "h05_cfl02": _filtered_peak(d, "h05c", "time.cfl=0.2"),
        "h025": _filtered_peak(d, "h025", "grid.cell_size=0.025"),
        "h025_tied": _filtered_peak(d, "h025t", "grid.cell_size=0.025", "damping.0.reference_cell_size=null"),
    }


@pytest.mark.slow
def test_the_filtered_peak_converges_in_h_and_in_the_step(peaks):
    a, b, c = (peaks[k]["filtered_peak_force"] for k in ("h05", "h025", "h05_cfl02"))
    assert abs(b / a - 1) < 0.10
    assert abs(c / a - 1) < 0.05
    assert 0 < a <= peaks["h05"]["peak_force"]


@pytest.mark.slow
def test_a_damping_tied_to_the_cell_size_slows_the_flow_that_arrives(peaks):
    tied, fixed = peaks["h025_tied"], peaks["h025"]
    assert tied["filtered_peak_force"] < 0.85 * fixed["filtered_peak_force"]
    assert tied["first_contact"] > fixed["first_contact"]  # it arrives later
