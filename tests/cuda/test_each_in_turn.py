"""A scheme's per-item functions run in turn in one loop (Backend.each_in_turn; backend/item_loops.py on the CPU,
cuda_loops.each_kernel on a GPU, here under numba-cuda's simulator): the run equals the functions' loops one after
the other where each reads what an earlier one wrote only at its own item, two functions whose parameters share a
name keep their own arguments, and a run of one is the plain ``each``.  The saturated scheme runs its pointwise
passes this way (the particle and node passes of schemes/saturated/passes.py that follow one another over the
same items), and its porosity follows the laws so that G2P, the particle stages and the laws join in one particle
pass (Saturated.after_particles): 23 launches a step on the saturated bench scene instead of 34."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = """
import json
import numpy as np
from numba import njit

@njit
def scaled(i, a, f, b):  # b <- f a
    b[i] = f * a[i]

@njit
def shifted(i, b, a, c):  # c <- b + a (its own 'a' and 'b': another pair of arrays than scaled's)
    c[i] = b[i] + 2.0 * a[i]

@njit
def squared(i, c):
    c[i] = c[i] * c[i]

def run(each, each_in_turn, to, back):
    a, x = np.arange(70.0), np.linspace(-1.0, 1.0, 70)
    b1, c1, b2, c2 = (np.zeros(70) for _ in range(4))
    d = {k: to(v) for k, v in dict(a=a, x=x, b1=b1, c1=c1, b2=b2, c2=c2).items()}
    each(scaled, 70, d["a"], 3.0, d["b1"])
    each(shifted, 70, d["b1"], d["x"], d["c1"])
    each(squared, 70, d["c1"])
    each_in_turn(70, ((scaled, (d["a"], 3.0, d["b2"])), (shifted, (d["b2"], d["x"], d["c2"])), (squared, (d["c2"],))))
    return [back(d[k]).tolist() for k in ("b1", "c1", "b2", "c2")]

from geompm.backend.base import Backend
name = __import__("sys").argv[1]
if name == "cpu":
    from geompm.backend.cpu import CpuBackend as B
    to = back = lambda v: v
else:
    from numba import cuda
    from geompm.backend.cuda import CudaBackend as B
    to, back = cuda.to_device, lambda v: v.copy_to_host()
be = B.__new__(B)  # the loops need no scene
be._moved = 0
print(json.dumps(run(lambda fn, n, *args: Backend.each(be, fn, n, *args), be.each_in_turn, to, back)))
"""


@pytest.mark.parametrize("backend", ["cpu", "cuda"])
def test_a_run_of_pointwise_functions_equals_their_loops_in_turn(backend):
    """b = 3 a, c = (b + 2 x)^2 over 70 items (three blocks of 32 threads on the device): the run's b and c equal
    the three loops' exactly and the closed form; ``shifted`` takes its own arrays under the names that
    ``scaled`` also uses (a, b)."""
    if backend == "cuda":
        pytest.importorskip("numba_cuda")
    r = subprocess.run([sys.executable, "-c", SCRIPT, backend], capture_output=True, text=True, cwd=ROOT, timeout=300,
                       env=dict(os.environ, NUMBA_ENABLE_CUDASIM="1"))
    assert r.returncode == 0, r.stderr[-2000:]
    b1, c1, b2, c2 = (np.array(v) for v in json.loads(r.stdout.strip().splitlines()[-1]))
    a, x = np.arange(70.0), np.linspace(-1.0, 1.0, 70)
    np.testing.assert_array_equal(b1, 3.0 * a)
    np.testing.assert_array_equal(c1, (3.0 * a + 2.0 * x) ** 2)
    np.testing.assert_array_equal(b2, b1)
    np.testing.assert_array_equal(c2, c1)


def test_the_saturated_step_takes_23_launches():
    """The saturated bench scene (3 cells a side, 2 steps, under the simulator): 23 launches a step (34 before the
    pointwise passes ran in turn: the smoothing's gather with the cavitation hold and the total stress, the node
    fill with the mixture and the node pore water, the mirror with the split, the water's gather with the
    drained flag and the pressure increment, the second gather with the increment's addition, 8 launches fewer;
    then G2P, the particle stages, the law and the step-end row in one launch with the porosity after them, 3
    fewer), still one blocking copy and no device array made."""
    pytest.importorskip("numba_cuda")
    r = subprocess.run([sys.executable, "benchmarks/device/count_launches.py", "--steps", "2", "--cells", "3",
                        "saturated3d"], env=dict(os.environ, NUMBA_ENABLE_CUDASIM="1"), capture_output=True, text=True,
                       cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    row = next(json.loads(line) for line in r.stdout.splitlines() if line.startswith("{"))
    assert row["launches"] == 23 and row["blocking"] == 1 and row["h2d"] == 0 and row["allocs"] == 0, row
