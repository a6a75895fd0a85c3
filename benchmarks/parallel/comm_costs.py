"""What each kind of exchange costs through mpi4py on this machine (loopback), for the scaling model of
docs/parallel.md: per call, the stacked reduction of a few numbers (comm.sum, comm.rows), a pickled
gather of a (2, 3) array (the window bounds), the all-to-all of empty packets (migration with nothing to
move) and a neighbour swap of ``--bytes`` (a halo).

    mpiexec -n 2 python benchmarks/parallel/comm_costs.py OUT.json [--calls 2000] [--bytes 116928]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--bytes", type=int, default=116928)
    args = ap.parse_args()
    from geompm.engine.launch import world

    comm = world()
    assert comm is not None and comm.size == 2, "run under mpiexec -n 2"
    other = 1 - comm.rank
    halo = np.ones(args.bytes // 8)
    got = np.empty_like(halo)
    rows = np.ones((1, 20))
    bounds = np.zeros((2, 3), np.int64)
    ops = {
        "sum of 4 numbers": lambda: comm.sum([1.0, 2.0, 3.0, 4.0]),
        "rows (1, 20)": lambda: comm.rows(rows),
        "gather of (2, 3) bounds": lambda: comm.gather(bounds),
        "all-to-all of empty packets": lambda: comm.exchange([None, None]),
        f"swap of {args.bytes} bytes": lambda: comm.swap(halo, other, got, other),
    }
    out = {}
    for name, op in ops.items():
        for _ in range(50):
            op()
        comm.barrier()
        t = time.perf_counter()
        for _ in range(args.calls):
            op()
        out[name] = (time.perf_counter() - t) / args.calls
    if comm.is_root:
        Path(args.out).write_text(json.dumps({"seconds_per_call": out, "ranks": 2}, indent=1))
        for k, v in out.items():
            print(f"{k}: {v * 1e6:.1f} us")


if __name__ == "__main__":
    main()
