"""The CUDA backend's kept work arrays (backend/cuda_scratch.py), under numba-cuda's simulator: a spare is never
the array it is to replace (a gather into its own source would read rows it has already overwritten), a pair
alternates and makes nothing new from its third use on, a new shape gets a new pair (the old one is let go); a scratch view has the shape
asked for and is cut from the same array until a larger size is asked for, which grows it by a quarter (plus 64)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
pytest.importorskip("numba_cuda")

SCRIPT = """
import json
import numpy as np
from numba import cuda
from geompm.backend.cuda_scratch import Scratch

def ptr(a):
    return a._ary.__array_interface__["data"][0]

room = Scratch()
busy = cuda.to_device(np.arange(6.0))
chain = [busy]
for _ in range(5):
    chain.append(room.spare("p_x", (6,), np.float64, chain[-1]))
other = room.spare("p_x", (7,), np.float64, chain[-1])
a = room("key", 10, np.int64)
b = room("key", (2, 5), np.int64)
c = room("key", 100, np.int64)
print(json.dumps({
    "not_busy": all(x is not y for x, y in zip(chain, chain[1:])),
    "distinct": len({id(x) for x in chain[1:]}),
    "alternate": [chain[k] is chain[k + 2] for k in range(1, 4)],
    "new_shape": other.shape == (7,) and all(other is not x for x in chain),
    "shapes": [a.shape, b.shape, c.shape],
    "same_base": ptr(a) == ptr(b),
    "grown": ptr(c) != ptr(a),
    "flat": int(room._flat["key"].shape[0]),
    "nbytes": room.nbytes()}))
"""


def test_spares_alternate_and_scratch_grows_by_a_quarter():
    r = subprocess.run([sys.executable, "-c", SCRIPT], env=dict(os.environ, NUMBA_ENABLE_CUDASIM="1"),
                       capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["not_busy"] and out["distinct"] == 2 and out["alternate"] == [True, True, True], out
    assert out["new_shape"], out
    assert out["shapes"] == [[10], [2, 5], [100]] and out["same_base"] and out["grown"], out
    assert out["flat"] == int(100 * 1.25) + 64, out  # 189 entries after growing to 100
    # what is kept: a new shape replaced the (6,) pair by the one (7,) array, and the 189-entry flat array
    assert out["nbytes"] == 8 * (7 + 189), out
