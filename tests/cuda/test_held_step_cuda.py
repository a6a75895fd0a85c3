"""The held step on the CUDA backend (engine/held_step.py, backend/cuda.py ``gate``/``release``) under numba-cuda's
simulator, against the CPU's held steps from the same case: the same steps (count and times), the same particles
and the same recorded forces, where the device's check ends batches (fraction 1: every batch ends after its
first step while the host launched four) and where batches run whole (fraction 0.9, an obstacle's recorded forces
handed per step); and the counts: one blocking copy a batch instead of a step."""

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
import json, math, sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/cuda")
from cuda_parity import scenes
from geompm.api import scene_from_dict
from geompm.engine.runner import Runner
from geompm.engine.scheduler import Simulation

folder = Path(tempfile.mkdtemp())
out = {}
for name, fraction, steps in (("elastic_apic_quadratic_usl", 1.0, 8), ("herschel_bulkley_explicit_and_box_guard", 0.9, 12)):
    runs = {}
    for backend in ("cpu", "cuda"):
        c = json.loads(json.dumps(scenes(folder)[name]))
        c.pop("parity_place", None)
        c["solver"].update(backend=backend, held_step={"steps": 4, "fraction": fraction})
        sim = Simulation(scene_from_dict(c, base_dir=folder))
        runner = Runner(sim, folder, [], progress=False)
        runner.start()
        times, rows = [], []
        while sim.step_count < steps:
            runner.advance(math.inf)
            times.append((sim.step_count, sim.time))
            rows.append(sim.series_row())
        st = sim.state
        o = np.argsort(st.p_id)
        runs[backend] = (times, rows, st.p_x[o].copy(), st.p_v[o].copy(), st.p_stress[o].copy(), runner.held_batches)
    (tc, rc, xc, vc, sc, bc), (tg, rg, xg, vg, sg, bg) = runs["cpu"], runs["cuda"]
    cols = [k for k in rc[-1] if isinstance(rc[-1][k], float)]
    series = max((abs(a[k] - b[k]) / max(max(abs(r[k]) for r in rc), 1e-30) for a, b in zip(rc, rg) for k in cols),
                 default=0.0)
    out[name] = {"steps_cpu": [s for s, _ in tc], "steps_cuda": [s for s, _ in tg],
                 "time": max(abs(a[1] - b[1]) for a, b in zip(tc, tg)), "batches": [bc, bg],
                 "x": float(np.abs(xc - xg).max() / np.abs(xc).max()), "v": float(np.abs(vc - vg).max() / np.abs(vc).max()),
                 "stress": float(np.abs(sc - sg).max() / np.abs(sc).max()), "series": float(series),
                 "force_columns": [k for k in cols if k.startswith("dam_f")]}
print(json.dumps(out))
"""


@pytest.mark.slow
def test_held_steps_on_the_device_are_the_cpus_held_steps():
    r = subprocess.run([sys.executable, "-c", PROBE], env=SIM, capture_output=True, text=True, cwd=ROOT, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    ended = out["elastic_apic_quadratic_usl"]
    # fraction 1: the block speeds up under gravity, so each batch's first check fails: one step a batch
    assert ended["steps_cpu"] == ended["steps_cuda"] == list(range(1, 9)) and ended["batches"] == [8, 8]
    whole = out["herschel_bulkley_explicit_and_box_guard"]
    assert whole["steps_cpu"] == whole["steps_cuda"] == [4, 8, 12] and whole["batches"] == [3, 3]
    assert whole["force_columns"]  # the obstacle's recorded force, handed per step from the batch's tally
    for name, row in out.items():
        assert row["time"] < 1e-15, (name, row)
        assert max(row["x"], row["v"], row["stress"], row["series"]) < 1e-9, (name, row)


@pytest.mark.slow
def test_a_held_batch_reads_the_device_once():
    r = subprocess.run([sys.executable, "benchmarks/device/count_launches.py", "--steps", "20", "--held", "10",
                        "dp2d"], env=SIM, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    row = next(json.loads(line) for line in r.stdout.splitlines() if line.startswith("{"))
    assert row["steps"] == 20 and row["batches"] == 2
    # one copy to the host a batch (the tally) and one to the device (the batch's box): 2 blocking per 10 steps
    assert row["d2h"] == pytest.approx(0.1) and row["blocking"] <= 0.2 + 1e-12, row
    assert row["implicit"] == 0, row
