"""The wet-bed entrainment case, wet bed against dry bed, at three cell sizes
(geompm/testing/verification/wet_bed.py; docs/validation/wet-bed-entrainment.md).

    python benchmarks/pore_water/wet_bed.py [OUT.json] [--sizes 0.04,0.0267,0.02] [--end 1.5]

Raw output: benchmarks/results/2026-12-05-issue52/wet_bed.json.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from geompm.testing.verification.wet_bed import run


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?", default="wet_bed.json")
    ap.add_argument("--sizes", default="0.04,0.0267,0.02")
    ap.add_argument("--end", type=float, default=1.5)
    args = ap.parse_args()
    rows = []
    for h in (float(s) for s in args.sizes.split(",")):
        for bed in ("wet", "dry"):
            t0 = time.perf_counter()
            r = run(h, bed, args.end)
            r["seconds"] = round(time.perf_counter() - t0, 1)
            rows.append(r)
            print(json.dumps({k: v for k, v in r.items() if k != "history"}), flush=True)
            Path(args.out).write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
