"""Cost per particle-step across scene sizes in one process, interleaved: issue 38's size figure on a noisy machine.

    python benchmarks/size_spread.py [--scene scaling] [--rounds 10] [--budget 4e6] [--only 25k 400k]

Builds every variant of a scene of benchmarks/scenes.json (default ``scaling``: dp3d at 26k, 103k, 410k and
1.59M particles) in one process, then steps them through ``Runner.advance`` (what ``geompm bench`` times per
step) in turn, round after round, the order rotating each round, so that a drift of the machine falls on every
size alike.  A visit runs about ``--budget`` particle-steps (at least one step), so each takes about as long.
Separate ``geompm bench`` processes per size gave a largest / smallest ratio of 1.30 one day and 1.37 another,
with the smallest scene dearest (docs/performance.md); this says how much of that is the machine.
Prints one JSON object: each size's particles and median ns per particle-step, the ratio of the largest median
to the smallest, and the median and quartiles of that ratio taken round by round.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.runner import Runner  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="scaling")
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--budget", type=float, default=4e6, help="particle-steps per visit")
    ap.add_argument("--only", nargs="+", default=None, metavar="VARIANT", help="these variants only")
    a = ap.parse_args()
    bench = ROOT / "benchmarks"
    spec = json.loads((bench / "scenes.json").read_text())[a.scene]
    runners, names = [], []
    for name, sets in spec["variants"].items():
        if a.only and name not in a.only:
            continue
        sim = Simulation(scene_from_file(str(bench / spec["case"]), ["outputs=[]", "time.end=1e9", *sets]))
        runner = Runner(sim, None, [], progress=False)
        runner.start()
        for _ in range(3):
            runner.advance(math.inf)
        runners.append(runner)
        names.append(name)
    sizes = [r.sim.state.n for r in runners]
    steps = [max(1, round(a.budget / n)) for n in sizes]
    times = [[] for _ in runners]
    for r in range(a.rounds):
        for k in [(i + r) % len(runners) for i in range(len(runners))]:
            t = time.perf_counter()
            for _ in range(steps[k]):
                runners[k].advance(math.inf)
            times[k].append((time.perf_counter() - t) / steps[k] / sizes[k] * 1e9)
    medians = [statistics.median(t) for t in times]
    per_round = [max(row) / min(row) for row in zip(*times)]
    q = statistics.quantiles(per_round, n=4)
    print(json.dumps({"scene": a.scene, "rounds": a.rounds,
                      "sizes": {nm: {"particles": n, "steps_per_visit": s, "ns_median": m,
                                     "ns_quartiles": statistics.quantiles(t, n=4)[::2]}
                                for nm, n, s, m, t in zip(names, sizes, steps, medians, times)},
                      "largest_over_smallest_median": max(medians) / min(medians),
                      "per_round_ratio_median": statistics.median(per_round),
                      "per_round_ratio_quartiles": [q[0], q[2]]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
