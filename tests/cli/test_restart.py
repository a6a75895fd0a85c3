"""Checkpoint and restart: a resumed run is bit-identical to an uninterrupted one.

Reference: the uninterrupted run itself (same case, same P2G chunk count).  The
in-process test stops at a random step through the same path a signal takes
(Runner.request_stop: checkpoint, then stop); the subprocess test sends a real
SIGTERM to `geompm run` and resumes with `geompm run --resume`.  Both compare
final particle positions and stresses bit for bit and series.csv byte for byte
(no duplicate or missing row).
"""

import json
import os
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.engine import checkpoint
from geompm.engine.runner import Interrupted, Runner
from geompm.engine.scheduler import Simulation
from geompm.writers.base import Writer

from tests.support.cases import CASES, tiny_case


class _StopAt(Writer):
    """Every step: ask the runner to stop at a given step, as the SIGINT handler does."""

    name = "stop_at"

    def __init__(self, step):
        super().__init__(None, 0.0)
        self.step = step
        self.runner = None

    def write(self, sim):
        if sim.step_count == self.step:
            self.runner.request_stop("test")


def _case():
    case = tiny_case()
    case["time"]["end"] = 0.3
    case["bodies"][0]["velocity"] = [0.5, -0.3]
    case["outputs"] = [{"writer": "vtu", "interval": 0.05}, {"writer": "series", "interval": 0.0},
                       {"writer": "hdf5", "interval": 0.1}]
    return case


def _run(run_dir, stop_at=None):
    scene = scene_from_dict(_case())
    sim = Simulation(scene)
    writers = list(scene.writers)
    stopper = None
    if stop_at is not None:
        stopper = _StopAt(stop_at)
        writers.append(stopper)
    runner = Runner(sim, run_dir, writers, progress=False)
    if stopper:
        stopper.runner = runner
    runner.run()
    return sim


def _resume(run_dir):
    scene = scene_from_dict(_case())
    nchunks = checkpoint.read_meta(run_dir)["nchunks"]
    sim = Simulation(scene, nchunks=nchunks)
    runner = Runner(sim, run_dir, list(scene.writers), progress=False)
    runner.resume()
    runner.run()
    return sim


def test_resumed_run_is_bit_identical(tmp_path):
    full_dir, cut_dir = tmp_path / "full", tmp_path / "cut"
    full_dir.mkdir()
    cut_dir.mkdir()
    full = _run(full_dir)
    stop = random.Random(os.getpid()).randrange(5, full.step_count - 5)
    with pytest.raises(Interrupted):
        _run(cut_dir, stop_at=stop)
    assert checkpoint.newest(cut_dir).name == f"step_{stop:010d}.npz"
    resumed = _resume(cut_dir)
    assert resumed.step_count == full.step_count
    assert np.array_equal(resumed.state.p_x, full.state.p_x), f"stopped at step {stop}"
    assert np.array_equal(resumed.state.p_stress, full.state.p_stress)
    assert (cut_dir / "series.csv").read_bytes() == (full_dir / "series.csv").read_bytes()
    assert (cut_dir / "particles.pvd").read_text() == (full_dir / "particles.pvd").read_text()
    import h5py

    with h5py.File(cut_dir / "results.h5") as a, h5py.File(full_dir / "results.h5") as b:
        assert np.array_equal(a["series/time"][:], b["series/time"][:])
        assert np.array_equal(a["times"][:], b["times"][:])
        last = f"particles/{len(b['times']) - 1:06d}/position"
        assert np.array_equal(a[last][:], b[last][:])


def _geompm(*args, **kw):
    return subprocess.Popen([sys.executable, "-m", "geompm.cli", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, **kw)


def test_sigterm_then_resume_matches_uninterrupted_run(tmp_path):
    """`geompm run` stopped by SIGTERM writes a checkpoint and exits 128 + 15; `--resume` finishes
    the run bit-identically to an uninterrupted one (the 2D landslide case, first 0.6 s)."""
    case = CASES / "landslide.json"
    sets = ["--set", "time.end=0.6", "--quiet"]
    full = _geompm("run", str(case), "--out", str(tmp_path / "full"), *sets)
    assert full.wait(timeout=300) == 0, full.stdout.read()
    cut = _geompm("run", str(case), "--out", str(tmp_path / "cut"), *sets)
    series = tmp_path / "cut" / "series.csv"
    deadline = time.time() + 120
    while time.time() < deadline:
        if series.is_file() and series.read_text().count("\n") > 20:
            break
        time.sleep(0.05)
    cut.send_signal(signal.SIGTERM)
    out = cut.stdout.read()
    assert cut.wait(timeout=60) == 128 + signal.SIGTERM, out
    assert "stopped by SIGTERM" in out and "--resume" in out
    status = json.loads((tmp_path / "cut" / "status.json").read_text())
    assert status["finished"] is False
    res = _geompm("run", str(case), "--resume", str(tmp_path / "cut"), *sets)
    assert res.wait(timeout=300) == 0, res.stdout.read()
    a, _ = checkpoint.load(tmp_path / "full")
    b, _ = checkpoint.load(tmp_path / "cut")
    assert np.array_equal(a["p_x"], b["p_x"]) and np.array_equal(a["p_stress"], b["p_stress"])
    assert (tmp_path / "cut" / "series.csv").read_bytes() == (tmp_path / "full" / "series.csv").read_bytes()
    assert json.loads((tmp_path / "cut" / "status.json").read_text())["finished"] is True


def test_resume_refuses_a_different_case(tmp_path):
    """Only time.end may change on --resume; a changed material is refused with exit 2."""
    from geompm.cli import main

    f = tmp_path / "case.json"
    f.write_text(json.dumps(_case()))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    changed = _case()
    changed["materials"]["soil"]["youngs_modulus"] = 2e6
    f.write_text(json.dumps(changed))
    assert main(["run", str(f), "--resume", str(tmp_path / "run"), "--quiet"]) == 2


def test_a_held_run_resumed_at_an_output_time_is_bit_identical(tmp_path):
    """With held steps (solver.held_step) a batch ends at every output time, so a run stopped there and resumed
    starts its next batch where the uninterrupted run starts its own: the same steps, bit for bit."""
    def held_case():
        case = _case()
        case["solver"]["held_step"] = {"steps": 12}
        case["outputs"] = [{"writer": "vtu", "interval": 0.05}, {"writer": "series", "interval": 0.01}]
        return case

    def runner(run_dir):
        scene = scene_from_dict(held_case())
        sim = Simulation(scene)
        return sim, Runner(sim, run_dir, list(scene.writers), progress=False)

    full_dir, cut_dir = tmp_path / "full", tmp_path / "cut"
    full_dir.mkdir()
    cut_dir.mkdir()
    full, run = runner(full_dir)
    run.run()
    assert run.held_batches < 0.5 * full.step_count  # batches of several steps
    _, run = runner(cut_dir)
    run.run(until=0.15)
    resumed, run = runner(cut_dir)
    run.resume()
    run.run()
    assert resumed.step_count == full.step_count
    assert np.array_equal(resumed.state.p_x, full.state.p_x)
    assert np.array_equal(resumed.state.p_stress, full.state.p_stress)
    assert (cut_dir / "series.csv").read_bytes() == (full_dir / "series.csv").read_bytes()
