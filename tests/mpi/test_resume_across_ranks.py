"""A run checkpointed on N MPI ranks resumes on M ranks (M = 1 included) with the answers of one
uninterrupted process, and the slabs rebalance as the flow spreads (docs/parallel.md).

A checkpoint holds every rank's particles gathered on rank 0, in the one-process format (one file, each
material block ordered by particle id); each rank of the resumed run reads it and keeps its slab.  The
dam break (cases/dam_break.json) runs to t = 5 ms (an output time, where the uninterrupted run lands too)
on 2 ranks, then on to 8.6 ms once on 3 ranks and once in one process; both must match the
uninterrupted one-process run to 1e-10 of each field's largest value, as a run that never stopped does
(tests/mpi/test_same_answers.py).
"""

from __future__ import annotations

import json
import shutil

import pytest

from geompm.testing.verification.mpi_scenes import BOUND, shipped
from geompm.testing.verification import mpi_runs as mpi

T1, T2 = 0.005, 0.0086


def test_checkpoint_on_two_ranks_resumes_on_three_and_on_one(tmp_path):
    case = shipped("dam_break", **{"time.end": T2, "solver.rebalance_interval": 10})
    assert mpi.run(case, tmp_path / "whole", 1).returncode == 0
    first = dict(case, time=dict(case["time"], end=T1))
    done = mpi.run(first, tmp_path / "two", 2)
    assert done.returncode == 0, done.stdout + done.stderr
    _, meta = mpi.final_state(tmp_path / "two" / "run")
    assert meta["ranks"] == 2 and abs(meta["time"] - T1) < 1e-12
    for ranks in (3, 1):
        folder = tmp_path / f"on{ranks}"
        shutil.copytree(tmp_path / "two", folder)
        done = mpi.run(first, folder, ranks, "--set", f"time.end={T2}", resume=folder / "run")
        assert done.returncode == 0, done.stdout + done.stderr
        diff = mpi.differences(tmp_path / "whole" / "run", folder / "run")
        worst = max(diff, key=diff.get)
        assert diff[worst] <= BOUND, f"resumed on {ranks}: {worst} differs by {diff[worst]:.3g}"
        status = json.loads((folder / "run" / "status.json").read_text())
        assert status["finished"] and status["particles"] == 3200


@pytest.mark.slow
def test_slabs_rebalance_as_the_column_spreads(tmp_path):
    """With solver.rebalance_interval = 20 the cuts follow the spreading water: on 3 ranks they move from
    cells 7 and 14 (a third of the column each) as the surge runs out over the first 0.1 s (about 2500
    steps), each slab keeps at least 4 cells, and the answers still match one process to 1e-10."""
    case = shipped("dam_break", **{"time.end": 0.1, "solver.rebalance_interval": 20})
    assert mpi.run(case, tmp_path / "one", 1).returncode == 0
    done = mpi.run(case, tmp_path / "three", 3)
    assert done.returncode == 0, done.stdout + done.stderr
    report = json.loads((tmp_path / "three" / "run" / "status.json").read_text())["mpi"]
    assert report["rebalanced"] >= 1, report
    cuts = report["cuts"]
    assert all(b - a >= 4 for a, b in zip(cuts, cuts[1:]))
    diff = mpi.differences(tmp_path / "one" / "run", tmp_path / "three" / "run")
    assert max(diff.values()) <= BOUND


def test_ctrl_c_to_mpiexec_stops_every_rank_after_one_checkpoint(tmp_path):
    """SIGINT to mpiexec (MPICH forwards it to the ranks): the ranks agree at the end of a step to stop,
    write one checkpoint and exit with 130 as one process does; the run resumes on one rank from it."""
    import os
    import signal
    import subprocess
    import sys
    import time

    case = shipped("dam_break", **{"time.end": 0.25})
    (tmp_path / "case.json").write_text(json.dumps(case))
    run = tmp_path / "run"
    cmd = [str(mpi.mpiexec()), "-n", "2", sys.executable, "-m", "geompm.cli", "run", str(tmp_path / "case.json"),
           "--out", str(run), "--quiet"]
    proc = subprocess.Popen(cmd, env=dict(os.environ, NUMBA_NUM_THREADS="1"), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while not ((run / "series.csv").is_file() and len((run / "series.csv").read_text().splitlines()) > 5):
        assert proc.poll() is None and time.monotonic() < deadline, "the run ended before it could be stopped"
        time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, out + err
    assert "stopped by SIGINT" in out and "--resume" in out
    assert len(list((run / "checkpoints").glob("step_*.npz"))) == 1
    status = json.loads((run / "status.json").read_text())
    assert not status["finished"] and status["reason"] == "stopped by SIGINT"
    _, meta = mpi.final_state(run)
    done = mpi.run(case, tmp_path, 1, "--set", f"time.end={meta['time'] + 0.002}", resume=run)
    assert done.returncode == 0, done.stdout + done.stderr
    assert json.loads((run / "status.json").read_text())["finished"]
