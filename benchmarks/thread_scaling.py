"""2 threads against 1 in one process, interleaved: issue 38's thread-scaling figure on a noisy machine.

    python benchmarks/thread_scaling.py benchmarks/fluid3d.json [--set solver.transfer=mls] [--rounds 12] [--steps 5]

Steps the case through ``Runner.advance`` (what ``geompm run`` and ``geompm bench`` time per step: time-step
control, the step, health and domain checks), switching numba's thread count with ``numba.set_num_threads``
between rounds of ``--steps`` steps, 1 and 2 (or ``--threads``) in turn, the order alternating, so that a
drift of the machine falls on both.  The particle chunks stay as made for the largest count, so each round
does the same work.  Prints one JSON object: the median ns per particle-step at each count, the median of the
per-round speed-up and its quartiles.  Separate ``geompm bench`` runs at 1 and 2 threads on this project's
2-core machine gave 1.42-1.54x one day and 1.9-2.1x an hour later: the second core is not always ours.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

import numba

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.runner import Runner  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--rounds", type=int, default=12)
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--threads", type=int, nargs=2, default=(1, numba.config.NUMBA_NUM_THREADS))
    a = ap.parse_args()
    sim = Simulation(scene_from_file(a.case, ["outputs=[]", *a.set]))
    runner = Runner(sim, None, [], progress=False)
    runner.start()
    for _ in range(3):
        runner.advance(math.inf)
    n = sim.state.n
    few, many = a.threads
    times = {few: [], many: []}
    for r in range(a.rounds):
        for k in ((few, many) if r % 2 == 0 else (many, few)):
            numba.set_num_threads(k)
            t = time.perf_counter()
            for _ in range(a.steps):
                runner.advance(math.inf)
            times[k].append((time.perf_counter() - t) / a.steps / n * 1e9)
    speedup = [s / m for s, m in zip(times[few], times[many])]
    q = statistics.quantiles(speedup, n=4)
    print(json.dumps({"case": a.case, "sets": a.set, "particles": n, "rounds": a.rounds, "steps": a.steps,
                      f"ns_{few}_thread": statistics.median(times[few]),
                      f"ns_{many}_threads": statistics.median(times[many]),
                      "speedup_median": statistics.median(speedup), "speedup_quartiles": [q[0], q[2]]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
