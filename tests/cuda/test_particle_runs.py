"""Consecutive particle stages of one class that share their table run in one launch on the CUDA backend
(backend/cuda.py ``_joins``; cuda_loops.RULES, in the joined particle pass PARTICLE_STEP and in GROUP), each stage
with its own accumulator row. Two stages of a test class (``Tally``: adds prm[0] m aux[0] into slot 0 and takes the
largest x + prm[0] into slot 1, a maximum) with one shared table, weights 1 and 3, after one step of a tiny elastic
block (tests/support/cases.tiny_case): each stage's sum is its weight times the blocks' mass times 2, its maximum the
largest x plus its weight, on the CPU and on the CUDA backend under numba-cuda's simulator, joined and separate. No
shipped CUDA stage forms such a run (each obstacle's guard has its own table; probes run on the CPU only), so nothing
else would catch a run that keeps only its last stage's sums: the joined pass did, until its rules were written once
for both kernels (the flush of the accumulator sat after the loop over the run's stages)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.cases import tiny_case

ROOT = Path(__file__).resolve().parents[2]
pytest.importorskip("numba_cuda")

SCRIPT = """
import json, sys
import numpy as np
from numba import njit
from geompm.api import scene_from_dict
from geompm.contract.stages import ParticleStage
from geompm.engine.scheduler import Simulation

@njit(inline="always")
def tally_rule(prm, aux, dt, k, x, x0, v, C, m, s, work, out):
    out[0] += prm[0] * m * aux[0]
    out[1] = max(out[1], x[0] + prm[0])

class Tally(ParticleStage):
    particle_rule = tally_rule
    particle_reduction = 2
    particle_maxima = (1,)

    def __init__(self, weight, aux):
        super().__init__(None, f"tally{weight}", "test")
        self.prm, self.aux, self.got = np.array([weight]), aux, None

    def particle_args(self, dt, time):
        return self.prm, self.aux

    def particle_reduced(self, out, dt, time):
        self.got = [float(out[:, 0].sum()), float(out[:, 1].max())]

case = json.loads(sys.argv[1])
sim = Simulation(scene_from_dict(case))
sim.step(sim.stable_dt())
table = np.array([2.0])
stages = [Tally(1.0, table), Tally(3.0, table)]
be = sim.backend
be.g2p_stages_and_stress(sim.view, 1e-6, stages, sim.time, set_velocity=True)
be.settle()
st = be.host_state()
print(json.dumps({"got": [s.got for s in stages], "mass": float(st.p_mass.sum()), "x_max": float(st.p_x[:, 0].max())}))
"""


def _case(backend: str, particle_pass: str) -> dict:
    solver = {"transfer": "apic", "update": "usl", "backend": backend}
    if backend == "cuda":
        solver["particle_pass"] = particle_pass
    return tiny_case(solver=solver, outputs=[])


@pytest.mark.parametrize("backend,particle_pass", [("cpu", "joined"), ("cuda", "joined"), ("cuda", "separate")])
def test_each_stage_of_a_joined_run_keeps_its_own_sums(backend, particle_pass):
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    r = subprocess.run([sys.executable, "-c", SCRIPT, json.dumps(_case(backend, particle_pass))], env=env,
                       capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["mass"] == pytest.approx(320.0, rel=1e-12)  # 0.4 x 0.4 m of 2000 kg/m3, a metre deep
    for (total, top), weight in zip(out["got"], (1.0, 3.0)):
        assert total == pytest.approx(weight * 2.0 * out["mass"], rel=1e-12), out
        assert top == pytest.approx(out["x_max"] + weight, rel=1e-12), out
