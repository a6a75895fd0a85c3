"""The CUDA step's tally (backend/cuda_tally.py) and its step-end reduction (backend/cuda_kernels.step_end) under
numba-cuda's simulator, in a subprocess: slots keep their values when a new key grows the array, one reset puts
every slot back to its own starting value, and step_end's row over random particles (one of them non-finite)
equals the host's reductions: per-axis bounds of the finite positions, the sums, the largest speed, the density
extremes and engine/health.health_sums (count of non-finite particles, kinetic energy, energy gravity released),
over more particles than one thread block holds so that the blocks' atomics are exercised; the host's own row
(kernels/step_end.end_row) equals it, and the kernel leaves its row untouched where the halt slot is set."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
pytest.importorskip("numba_cuda")

PROBE = """
import json, math
import numpy as np
from numba import cuda
from geompm.backend import cuda_kernels as K
from geompm.backend.cuda_tally import DeviceTally
from geompm.kernels.health import health_sums
from geompm.kernels.step_end import end_row

t = DeviceTally()
a = t.slots("a", [1.0, 2.0])
a.copy_to_device(np.array([5.0, 6.0]))
b = t.slots("b", [-math.inf])  # grows the array: a's values must survive
grown = t.read().tolist()
t.reset()
after_reset = t.read().tolist()

rng = np.random.default_rng(3)
n, d = 100, 3
x = rng.uniform(-1.0, 2.0, (n, d)); x0 = x + rng.normal(0.0, 0.1, (n, d))
v = rng.normal(0.0, 1.0, (n, d)); rho = rng.uniform(900.0, 1100.0, n)
s = rng.normal(0.0, 1e3, (n, 6)); m = rng.uniform(0.5, 2.0, n); g = np.array([0.0, 0.0, -9.81])
x[17, 1] = np.nan
row = t.slots("end", K.END_START)
K.step_end[K.blocks(n - 10), K.THREADS](cuda.to_device(x), cuda.to_device(x0), cuda.to_device(v), cuda.to_device(rho),
                                       cuda.to_device(s), cuda.to_device(m), cuda.to_device(g), 10, n, row,
                                       cuda.to_device(np.zeros(1)))
r = t.read()[t.where("end")]
host = np.array(K.END_START)
end_row(x, x0, v, rho, s, m, g, 10, n, host)
stopped = t.slots("stopped", K.END_START)
K.step_end[K.blocks(n), K.THREADS](cuda.to_device(x), cuda.to_device(x0), cuda.to_device(v), cuda.to_device(rho),
                                   cuda.to_device(s), cuda.to_device(m), cuda.to_device(g), 0, n, stopped,
                                   cuda.to_device(np.ones(1)))
untouched = bool((t.read()[t.where("stopped")] == np.array(K.END_START)).all())
sl = slice(10, n)
finite = np.isfinite(x[sl])
lo = np.array([x[sl][finite[:, a], a].min() for a in range(d)])
hi = np.array([x[sl][finite[:, a], a].max() for a in range(d)])
bad, ek, wg = health_sums(x[sl], x0[sl], v[sl], s[sl], m[sl], g)
print(json.dumps({"grown": grown, "after_reset": after_reset, "blocks": K.blocks(n - 10),
                  "lo": float(np.abs(-r[0:3] - lo).max()), "hi": float(np.abs(r[3:6] - hi).max()),
                  "sum_nan": bool(np.isnan(r[7])), "sum": float(abs(r[6] - x[sl][:, 0].sum())),
                  "speed": float(abs(r[9] - np.sqrt((v[sl] ** 2).sum(axis=1)).max())),
                  "rho": [float(abs(-r[10] - rho[sl].min())), float(abs(r[11] - rho[sl].max()))],
                  "health": [float(r[12]), float(bad), float(abs(r[13] - ek) / ek), float(abs(r[14] - wg) / wg)],
                  "host_row": float(np.nanmax(np.abs(host - r) / np.maximum(np.abs(r), 1.0))),
                  "host_nan": np.isnan(host).tolist() == np.isnan(r).tolist(), "halted_untouched": untouched}))
"""


def test_the_tally_keeps_grows_and_resets_and_step_end_equals_the_host_reductions():
    r = subprocess.run([sys.executable, "-c", PROBE], env=dict(os.environ, NUMBA_ENABLE_CUDASIM="1"),
                       capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["grown"] == [5.0, 6.0, -float("inf")]
    assert out["after_reset"] == [1.0, 2.0, -float("inf")]
    assert out["blocks"] >= 2  # several thread blocks add into one row
    assert out["lo"] < 1e-12 and out["hi"] < 1e-12 and out["speed"] < 1e-12 and max(out["rho"]) < 1e-9
    assert out["sum_nan"] and out["sum"] < 1e-9  # the NaN shows in its axis' sum only
    bad_device, bad_host, ek, wg = out["health"]
    assert bad_device == bad_host == 1.0 and ek < 1e-12 and wg < 1e-12
    # the host's row (kernels/step_end.end_row, the CPU's held-step check reads it) equals the device's
    assert out["host_row"] < 1e-12 and out["host_nan"]
    assert out["halted_untouched"]  # a halted step's reduction writes nothing (engine/held_step.py)
