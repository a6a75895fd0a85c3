"""The device script's dry run: `DRY=1 sh benchmarks/device/run.sh OUT` runs every command of the GPU check under
numba-cuda's simulator at tiny sizes (3 cells per side here, DRY_CELLS), so a session lent a GPU for 15 minutes
does not lose them to a broken command.  Checked: the script exits 0, no command is cut, fails or is skipped,
every bench command prints its scenes (9 commands, 12 scene rows, each in the precision, P2G, held step and
particle pass it was asked for; the dry run runs the 128- and 64-cell repeats of the 256-cell commands once), the
two parity checks agree with the CPU within 1e-9 (the issue's bound), and the count of what a step asks of the
host shows one blocking copy a step, or a batch with held steps (benchmarks/device/count_launches.py), and a step
that makes no device array and launches the previous step's kernels on the same arrays and grids."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
pytest.importorskip("numba_cuda")


@pytest.mark.slow
def test_the_device_script_runs_every_step_under_the_simulator(tmp_path):
    env = dict(os.environ, DRY="1", DRY_CELLS="3",
               PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    r = subprocess.run(["sh", "benchmarks/device/run.sh", str(tmp_path)], env=env, capture_output=True, text=True,
                       cwd=ROOT, timeout=900)
    log = (tmp_path / "gpu_check.log").read_text()
    assert r.returncode == 0, r.stderr[-3000:]
    for word in ("failed or cut", "skipped", "Traceback"):
        assert word not in log, log[-3000:]
    rows = [json.loads(line) for line in log.splitlines() if line.startswith("{")]
    bench = [row for row in rows if "particle_steps_per_s" in row]
    assert len(bench) == 12, [row.get("scene") for row in bench]
    held = [row for row in bench if any(s.startswith("solver.held_step") for s in row["sets"])]
    assert len(held) == 2 and all(row["held_batches"] >= 1 for row in held)
    assert all(row["particles"] > 0 and (row["steps"] == 1 or row in held) for row in bench)
    asked = {(row["scene"], s.split("=")[1]) for row in bench for s in row["sets"] if s.startswith("solver.precision")}
    assert {("fluid3d", "float32"), ("fluid3d", "float64"), ("dp3d", "float32"), ("dp3d", "float64"),
            ("saturated3d", "float64")} <= asked
    assert sum("solver.p2g=tiled" in row["sets"] for row in bench) == 2
    assert sum("solver.particle_pass=separate" in row["sets"] for row in bench) == 2
    parity = [row for row in rows if "fields" in row]
    assert {row["scene"] for row in parity} >= {"dam_break", "saturated_drucker_prager"}
    for row in parity:
        assert max(row["fields"].values()) < 1e-9, row
    counts = [row for row in rows if "blocking" in row]
    ordinary = [row for row in counts if row["batches"] == 0]
    assert ordinary and all(row["blocking"] == 1 and row["h2d"] == 0 for row in ordinary), counts
    batched = [row for row in counts if row["batches"]]  # 4 steps in one batch: a read and the box sent
    assert batched and all(row["blocking"] <= 2 / row["steps"] + 1e-12 for row in batched), counts
    replayed = [row for row in counts if row["replay"] is not None]  # the same kernels, arrays and grids as before
    assert replayed and all(row["replay"]["previous"]["same_topology"] == 1 and row["replay"]["previous"]["arrays"]
                            == 0 and row["allocs"] == 0 for row in replayed), replayed
