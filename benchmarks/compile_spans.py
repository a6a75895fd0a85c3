"""Where a cold start's time goes: numba's compile events of one case's first step, longest first.

    NUMBA_CACHE_DIR=$(mktemp -d) GEOMPM_KERNEL_DIR=$(mktemp -d) python benchmarks/compile_spans.py [CASE] [--set K=V ...]

Run it with empty caches (above), or it measures cache loading instead.  Records numba's ``numba:compile``
events (numba.core.event) while the case is assembled and its first step runs through the runner, and
prints the first step's wall time and each dispatcher's compile span; a compilation that triggers another
is counted in both lines, so the spans overlap.  Issue 38 (cold start under 30 s): the 3D transfer
kernels are most of it (docs/performance.md).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

from numba.core import event

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.runner import Runner  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("case", nargs="?", default=str(ROOT / "benchmarks" / "fluid3d.json"))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--top", type=int, default=15)
    a = ap.parse_args()
    t = time.perf_counter()
    with event.install_recorder("numba:compile") as rec:
        sim = Simulation(scene_from_file(a.case, ["outputs=[]", *a.set]))
        runner = Runner(sim, None, [], progress=False)
        runner.start()
        runner.advance(math.inf)
    total = time.perf_counter() - t
    open_spans, spans = {}, []
    for ts, ev in rec.buffer:
        key = ev.data["dispatcher"].py_func.__qualname__
        if ev.is_start:
            open_spans.setdefault(key, []).append(ts)
        else:
            t0 = open_spans[key].pop()
            if not open_spans[key]:  # the outermost compilation of this dispatcher
                spans.append((ts - t0, key))
    spans.sort(reverse=True)
    print(f"first step with compilation: {total:.1f} s; compile spans sum {sum(s for s, _ in spans):.1f} s")
    for s, key in spans[:a.top]:
        print(f"{s:7.2f} s  {key}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
