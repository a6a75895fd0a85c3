"""``geompm cuda-check``: a plugin author without a GPU learns whether the kernels of a case compile for one.

A test-only law plugin (a ``.dist-info`` folder on PYTHONPATH, as pip installs one) wraps the built-in
elastic update and multiplies by ``np.sqrt(1.0)``: the same numbers on the CPU and under numba-cuda's
simulator (which runs the function as compiled CPU code), but the CUDA target has no ``np.sqrt`` of a
scalar, the error that dp_stress carried until decision 48.  The plugin does not declare the cuda backend
(its author runs this check before declaring it), so it is checked as if it did, with a note.  A case with
that law beside the built-in elastic law must report every kernel, the plugin's law kernel as failed with
numba-cuda's reason and every other one compiled with its registers, and exit 1.  Bad arguments are refused with exit 2
before any work.
"""

import json
import os
import subprocess
import sys

import pytest

from tests.support.cases import tiny_case
from .test_cuda_backend import HAS_NUMBA_CUDA, has_nvvm

PLUGIN = '''\
import numpy as np
from numba import njit

from geompm.materials.linear_elastic import LinearElastic, elastic_stress


@njit(cache=False)
def rooted_stress(prm, dt, L, rho, s, state):
    elastic_stress(prm, dt, L, rho, s, state)
    s[0] = s[0] * np.sqrt(1.0)  # fine on the CPU; not a CUDA device function


class RootedElastic(LinearElastic):
    """Linear elasticity through np.sqrt (test plugin)."""
    name = "rooted_elastic"
    description = "test plugin: linear elastic, np.sqrt in the update"
    backends = ("cpu",)  # not declared for cuda yet: cuda-check is what tells its author whether to
    particle_stress = rooted_stress
'''


def write_plugin(folder):
    info = folder / "rooted_plugin-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: rooted-plugin\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[geompm.materials]\nrooted_elastic = rooted_plugin:RootedElastic\n")
    (folder / "rooted_plugin.py").write_text(PLUGIN)


def cuda_check(args, folder):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    env["PYTHONPATH"] = os.pathsep.join([str(folder), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "geompm.cli", "cuda-check", *args], capture_output=True, text=True,
                          env=env, cwd=folder, timeout=600)


@pytest.mark.slow
@pytest.mark.skipif(not HAS_NUMBA_CUDA, reason="numba-cuda is not installed (pip install 'geompm[cuda]')")
@pytest.mark.skipif(not has_nvvm(), reason="NVVM/NVRTC not installed (the test extra's cuda-toolkit wheels)")
def test_cuda_check_names_the_plugin_function_that_cannot_compile(tmp_path):
    write_plugin(tmp_path)
    case = tiny_case(outputs=[])
    case["materials"]["rooted"] = {"model": "rooted_elastic", "density": 2000.0, "youngs_modulus": 1.0e6,
                                   "poisson_ratio": 0.3}
    case["bodies"].append({"material": "rooted", "geometry": {"type": "box", "min": [0.6, 0.0], "max": [0.8, 0.2]},
                           "particles_per_cell": 2})
    (tmp_path / "case.json").write_text(json.dumps(case))
    res = cuda_check(["case.json", "--steps", "1", "--json"], tmp_path)
    assert res.returncode == 1, res.stderr[-3000:]
    rows = [json.loads(line) for line in res.stdout.splitlines()]
    failed = [r for r in rows if not r["ok"]]
    # the rooted block's G2P, wall rule and law in one kernel (cuda_loops.PARTICLE_STEP), named by its law first
    assert [r["kernel"].split(",")[0] for r in failed] == ["particle_step:rooted_plugin.rooted_stress"], failed
    assert "sqrt" in failed[0]["error"]
    assert "materials 'rooted_elastic' does not declare the cuda backend; checked as if it did" in res.stderr
    kernels = {r["kernel"] for r in rows if r["ok"]}
    assert "p2g" in kernels and "particle_step:linear_elastic.elastic_stress,cuda_kernels.g2p_particle,cuda_kernels." \
        "end_start,cuda_kernels.end_add,step_end.particle_row,halfspace.halfspace_particle_rule" in kernels, kernels
    # the grid update joined to the wall's node rule (cuda_loops.UPDATE_GROUP)
    assert "update_group:halfspace.halfspace_node_rule,cuda_kernels.update_node" in kernels, kernels
    assert all(r["registers"] > 0 and r["spill_store_bytes"] == 0 for r in rows if r["ok"]), rows


@pytest.mark.parametrize("args,says", [
    (["case.json", "--cc", "nine"], "--cc"),
    (["case.json", "--steps", "0"], "--steps"),
    (["missing.json"], "missing.json"),
])
def test_cuda_check_refuses_bad_arguments_before_any_work(tmp_path, args, says):
    (tmp_path / "case.json").write_text(json.dumps(tiny_case()))
    res = cuda_check(args, tmp_path)
    assert res.returncode == 2 and says in res.stderr, res.stderr
