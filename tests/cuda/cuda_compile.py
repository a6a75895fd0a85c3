"""Every kernel of the CUDA backend compiled for a GPU architecture, without a GPU (issue 21).

    python tests/cuda/cuda_compile.py [--cc 9.0] [--part K/N] [LAUNCHES.json ...]

The launches come from tests/cuda/cuda_parity.py ``--record FILE`` (its tiny scenes under numba-cuda's
simulator: every built-in law, the mu_i plugin where installed, every transfer, shape function and
stage, the device sort, the tiled P2G, float32); with no file given this script records them first
(one step of every scene, in a subprocess with NUMBA_ENABLE_CUDASIM=1).  Each distinct kernel and
argument-type list is then compiled to PTX for the compute capability (9.0: H100, H200) with NVVM,
every plugin function as a device function, exactly as numba-cuda does before a GPU launch, and,
where ptxas is installed, to machine code (backend/cuda_ptx.py).  One JSON line per kernel: ok or
numba-cuda's error, registers per thread, spill bytes, stack frame, shared memory.  Exit 1 if any
kernel fails to compile.  Needs NVVM and NVRTC (``pip install 'cuda-toolkit[nvvm,nvrtc,nvcc]==13.0.*'``,
part of the ``test`` extra; nvcc brings ptxas); never the simulator.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def distinct(files) -> list:
    """The launches of every file, each kernel and type list once."""
    seen: dict = {}
    for f in files:
        for entry in json.loads(Path(f).read_text()):
            key = json.dumps({"kernel": entry["kernel"], "types": entry["types"]}, sort_keys=True)
            seen.setdefault(key, entry)
    return [seen[k] for k in sorted(seen)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("files", nargs="*", metavar="LAUNCHES.json")
    ap.add_argument("--cc", default="9.0", help="compute capability, MAJOR.MINOR (9.0: H100, H200)")
    ap.add_argument("--part", default="1/1", metavar="K/N", help="compile every N-th kernel from the K-th")
    a = ap.parse_args(argv)
    from geompm.backend.cuda_loops import simulated

    if simulated():
        ap.error("compiling needs numba-cuda's compiler, not its simulator: unset NUMBA_ENABLE_CUDASIM")
    cc = tuple(int(v) for v in a.cc.split("."))
    with tempfile.TemporaryDirectory(prefix="geompm-ptx-") as tmp:
        files = a.files
        if not files:
            files = [str(Path(tmp) / "launches.json")]
            subprocess.run([sys.executable, str(ROOT / "tests" / "cuda" / "cuda_parity.py"), "--steps", "1", "--record",
                            files[0]], env=dict(os.environ, NUMBA_ENABLE_CUDASIM="1"), check=True,
                           stdout=subprocess.DEVNULL)
        k, n = (int(v) for v in a.part.split("/"))
        launches = distinct(files)[k - 1::n]

    from geompm.backend.cuda_ptx import compile_launches, find_ptxas

    results = compile_launches(launches, cc, find_ptxas())
    for r in results:
        print(json.dumps(r), flush=True)
    return 0 if all(r["ok"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
