"""geompm.run from a script started by mpiexec, on a communicator of the script's own (docs/python-api.md):
three ranks split into two that share a run and one that runs the same case alone, each with
``comm=MpiComm(sub)``; both runs finish and agree to 1e-10."""

from __future__ import annotations

import json
import os
import subprocess
import sys

from geompm.testing.verification.mpi_scenes import BOUND, SCENES
from geompm.testing.verification import mpi_runs as mpi

SCRIPT = """
import sys
from mpi4py import MPI
import geompm
from geompm.parallel.comm import MpiComm

world = MPI.COMM_WORLD
pair = world.Split(0 if world.Get_rank() < 2 else 1, world.Get_rank())
out = sys.argv[2] if world.Get_rank() < 2 else sys.argv[3]
run = geompm.run(sys.argv[1], out=out, progress=False, quiet=True, comm=MpiComm(pair))
assert run.exit_code == 0 and run.finished, run.status
"""


def test_a_script_shares_runs_among_ranks_of_its_own_communicators(tmp_path):
    case = tmp_path / "case.json"
    case.write_text(json.dumps(SCENES["dam_break"]()))
    script = tmp_path / "script.py"
    script.write_text(SCRIPT)
    cmd = [str(mpi.mpiexec()), "-n", "3", sys.executable, str(script), str(case), str(tmp_path / "two"),
           str(tmp_path / "one")]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600,
                          env=dict(os.environ, NUMBA_NUM_THREADS="1"))
    assert done.returncode == 0, done.stdout + done.stderr
    two = json.loads((tmp_path / "two" / "status.json").read_text())
    one = json.loads((tmp_path / "one" / "status.json").read_text())
    assert two["mpi"]["ranks"] == 2 and "mpi" not in one and two["steps"] == one["steps"] == 203
    diff = mpi.differences(tmp_path / "one", tmp_path / "two")
    assert max(diff.values()) <= BOUND
