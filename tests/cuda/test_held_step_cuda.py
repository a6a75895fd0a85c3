"""The held step on the CUDA backend (engine/held_step.py, backend/cuda.py ``gate``/``release``) under numba-cuda's
simulator, against the CPU's held steps from the same case (tests/cuda/cuda_parity.held_check): the same steps
(count and times), the same particles and the same recorded forces, where the device's check ends batches
(fraction 1: every batch ends after its first step while the host launched four) and where batches run whole
(fraction 0.9, an obstacle's recorded forces handed per step); and the counts: one blocking copy a batch instead
of a step."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
pytest.importorskip("numba_cuda")
SIM = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")

PROBE = """
import json, sys
sys.path.insert(0, "tests/cuda")
from cuda_parity import held_check
print(json.dumps(held_check()))
"""


@pytest.mark.slow
def test_held_steps_on_the_device_are_the_cpus_held_steps():
    r = subprocess.run([sys.executable, "-c", PROBE], env=SIM, capture_output=True, text=True, cwd=ROOT, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    ended = out["elastic_apic_quadratic_usl"]
    # fraction 1: the block speeds up under gravity, so each batch's first check fails: one step a batch
    assert ended["steps_cpu"] == ended["steps_cuda"] == list(range(1, 6)) and ended["batches"] == [5, 5]
    whole = out["herschel_bulkley_explicit_and_box_guard"]
    assert whole["steps_cpu"] == whole["steps_cuda"] == [4, 8] and whole["batches"] == [2, 2]
    assert whole["force_columns"]  # the obstacle's recorded force, handed per step from the batch's tally
    for name in ("elastic_apic_quadratic_usl", "herschel_bulkley_explicit_and_box_guard"):
        row = out[name]
        assert row["clock"] < 1e-15, (name, row)
        assert max(row["fields"], row["series"]) < 1e-9, (name, row)


@pytest.mark.slow
def test_a_held_batch_reads_the_device_once():
    r = subprocess.run([sys.executable, "benchmarks/device/count_launches.py", "--steps", "8", "--held", "4",
                        "--cells", "4", "dp2d"], env=SIM, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    row = next(json.loads(line) for line in r.stdout.splitlines() if line.startswith("{"))
    assert row["steps"] == 8 and row["batches"] == 2
    # one copy to the host a batch (the tally) and one to the device (the batch's box): 2 blocking per 4 steps
    assert row["d2h"] == pytest.approx(0.25) and row["blocking"] <= 0.5 + 1e-12, row
    assert row["implicit"] == 0, row
