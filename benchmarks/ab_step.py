"""Interleaved A/B of the time per step between two checkouts of geompm ("ping-pong").

    python benchmarks/ab_step.py OLD_CHECKOUT SCENE [--chunk 10] [--rounds 16] [--set K=V ...] [--new-set K=V ...]
                                 [--new-env NAME=VALUE ...]

SCENE is a case of benchmarks/ (e.g. dp2d).  Two processes, one importing geompm from OLD_CHECKOUT
(PYTHONPATH), one from this checkout, step the same scene in turn, ``--chunk`` steps each, for
``--rounds`` rounds; prints the median step time of each and the median and quartiles of the
per-round ratio new / old.  On a machine whose memory bandwidth drifts between runs (this
project's 2-core machine measured 21 to 40 GB/s on one day) two separate `geompm bench` runs
differ by more than the change being measured; rounds a second apart see the same machine.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def worker(case: str, sets: list[str]) -> None:
    from geompm.api import scene_from_file
    from geompm.engine.scheduler import Simulation

    sim = Simulation(scene_from_file(case, sets))
    for _ in range(3):
        sim.step(sim.stable_dt())
    print("ready", flush=True)
    for line in sys.stdin:
        n = int(line)
        t = time.perf_counter()
        for _ in range(n):
            sim.step(sim.stable_dt())
        print((time.perf_counter() - t) / n, flush=True)


def main() -> int:
    if sys.argv[1:2] == ["--worker"]:
        worker(sys.argv[2], sys.argv[3:])
        return 0
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("old", type=Path)
    p.add_argument("scene")
    p.add_argument("--chunk", type=int, default=10)
    p.add_argument("--rounds", type=int, default=16)
    p.add_argument("--set", action="append", default=[], help="override for both")
    p.add_argument("--new-set", action="append", default=[], help="override for the new checkout only")
    p.add_argument("--new-env", action="append", default=[], metavar="NAME=VALUE",
                   help="environment variable for the new checkout's process only (e.g. NUMBA_SLP_VECTORIZE=1, "
                        "with its own NUMBA_CACHE_DIR so that neither loads the other's compiled code)")
    a = p.parse_args()
    old = a.old.resolve()
    procs = []
    for root, extra, more_env in ((old, [], []), (HERE.parent, a.new_set, a.new_env)):
        env = dict(os.environ, PYTHONPATH=str(root))
        env.update(kv.split("=", 1) for kv in more_env)
        case = str(root / "benchmarks" / f"{a.scene}.json")
        procs.append(subprocess.Popen([sys.executable, __file__, "--worker", case, *a.set, *extra], cwd=root,
                                      env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      stderr=subprocess.DEVNULL, text=True))
    for pr in procs:
        if pr.stdout.readline().strip() != "ready":
            raise SystemExit("a worker failed to start")
    times = ([], [])
    for r in range(a.rounds):
        for k in ((0, 1) if r % 2 == 0 else (1, 0)):
            procs[k].stdin.write(f"{a.chunk}\n")
            procs[k].stdin.flush()
            times[k].append(float(procs[k].stdout.readline()))
    for pr in procs:
        pr.stdin.close()
        pr.wait()
    ratio = [n / o for o, n in zip(*times)]
    q = statistics.quantiles(ratio, n=4)
    print(f"{a.scene} {a.set} new+{a.new_set}{a.new_env}: old {statistics.median(times[0]) * 1e3:.2f} ms/step, "
          f"new {statistics.median(times[1]) * 1e3:.2f} ms/step; new/old per round median "
          f"{statistics.median(ratio):.3f} (quartiles {q[0]:.3f}-{q[2]:.3f}), {a.rounds} rounds of {a.chunk} steps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
