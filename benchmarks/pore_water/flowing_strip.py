"""A saturated Drucker-Prager layer flowing down a periodic strip of a 31 degree slope at three cell sizes
(geompm/testing/verification/flowing_strip.py): its acceleration against the effective-friction closed form
with the basal ratio it carries, the ratio itself and the normal stress on the bed.

    python benchmarks/pore_water/flowing_strip.py [OUT.json] [--sizes 0.04,0.02,0.01]

Raw output: benchmarks/results/2026-12-05-issue52/flowing_strip.json.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from geompm.testing.verification.flowing_strip import flow


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?", default="flowing_strip.json")
    ap.add_argument("--sizes", default="0.04,0.02,0.01")
    args = ap.parse_args()
    rows = []
    for h in (float(s) for s in args.sizes.split(",")):
        t0 = time.perf_counter()
        r = flow(h)
        r["seconds"] = round(time.perf_counter() - t0, 1)
        rows.append(r)
        print(json.dumps(r), flush=True)
        Path(args.out).write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
