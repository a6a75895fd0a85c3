"""solver.precision "float32" (issue 21): the state and grid stored in float32, on the CPU backend.

The kernels compute in float64 registers and round what they store, on the CPU as on the CUDA backend
(tests/cuda/test_cuda_backend.py compares the two in float32 under numba-cuda's simulator).  Checked here:
- the particle and grid arrays are float32 and take half the bytes of float64 (8 of the 16 bytes of a
  position pair, etc.: every floating-point array, so nbytes halves up to the integer ids);
- the elastic bar (cases/elastic_bar.json, h = 0.5 m; closed form 4 L / c = 10 s, tests/refdata/
  analytic_bar_axial_vibration_fixed_free.csv) keeps its float64 period within 1e-6 (measured
  3.6e-8 at h = 0.5 m, 1.4e-9 at 0.25 m: benchmarks/precision/float32_errors.py) and within 1 % of
  the closed form;
- a grid far from the coordinate origin (map coordinates) is refused for float32 at solver.precision,
  with exit 2 before any work;
- a checkpoint written in float64 resumes in float32 (only time.end, solver.backend and
  solver.precision may change on --resume).
"""

import json

import numpy as np

from geompm.api import scene_from_dict
from geompm.cli import main
from geompm.engine import checkpoint
from geompm.engine.scheduler import Simulation

from tests.support.cases import tiny_case
from tests.support.elastic_bar import run_bar


def test_float32_state_and_grid_halve_the_bytes_and_keep_the_bar_period():
    c32 = tiny_case(solver={"transfer": "apic", "precision": "float32"})
    s32, s64 = scene_from_dict(c32).state, scene_from_dict(tiny_case()).state
    for name, arr in s32.arrays().items():
        if arr.dtype.kind == "f":
            assert arr.dtype == np.float32, name
    assert all(sv.dtype == np.float32 for sv in s32.p_state)
    floats = sum(a.nbytes for a in s64.arrays().values() if a.dtype.kind == "f")
    assert s64.nbytes() - s32.nbytes() == floats // 2
    sim = Simulation(scene_from_dict(c32))
    sim.step(sim.stable_dt())
    assert sim.buffers.g_mass.dtype == np.float32 and sim.buffers.c_grid.dtype == np.float32
    assert sim.state.p_x.dtype == np.float32 and np.isfinite(sim.state.p_x).all()

    p32, exact, drift32, _, _ = run_bar(("solver.precision=float32",))
    p64, _, _, _, _ = run_bar()
    assert abs(p32 / p64 - 1) < 1e-6, f"float32 period {p32:.8f} s, float64 {p64:.8f} s"
    assert abs(p32 / exact - 1) < 0.01 and drift32 < 0.01


def test_float32_far_from_the_origin_is_refused(tmp_path, capsys):
    """Easting 2.6e6 m at h = 0.1 m: float32 spacing there is 0.25 m (2.5 cells)."""
    case = tiny_case(solver={"precision": "float32"})
    case["grid"]["origin"] = [2.6e6, 1.2e6]
    case["bodies"][0]["geometry"] = {"type": "box", "min": [2.6e6 + 0.2, 1.2e6], "max": [2.6e6 + 0.6, 1.2e6 + 0.4]}
    f = tmp_path / "far.json"
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "solver.precision" in err and "float64" in err
    assert not (tmp_path / "run").exists()


def test_a_float64_checkpoint_resumes_in_float32(tmp_path):
    case = tiny_case()
    case["time"]["end"] = 0.02
    case["outputs"] = [{"writer": "series", "interval": 0.0}]
    f = tmp_path / "case.json"
    f.write_text(json.dumps(case))
    run = tmp_path / "run"
    assert main(["run", str(f), "--out", str(run), "--quiet"]) == 0
    a64, meta64 = checkpoint.load(run)
    assert a64["p_x"].dtype == np.float64
    case["time"]["end"] = 0.04
    case["solver"]["precision"] = "float32"
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--resume", str(run), "--quiet"]) == 0
    a32, meta32 = checkpoint.load(run)
    assert a32["p_x"].dtype == np.float32 and meta32["step"] > meta64["step"]
    assert meta32["time"] >= 0.04 - 1e-12
    case["materials"]["soil"]["youngs_modulus"] = 2.0e6  # anything else still may not change
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--resume", str(run), "--quiet"]) == 2
