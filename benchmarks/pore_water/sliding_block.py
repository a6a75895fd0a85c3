"""A saturated elastic layer sliding on an impermeable plane at 25 degrees (periodic along the plane, so it is
the infinite slope's layer): friction on the effective normal force against a = g (sin b - (1 - lambda) mu cos b)
(geompm/testing/verification/sliding_block.py), at three cell sizes, for the dry twin, the table at the top
and a uniform excess pore pressure.

    python benchmarks/pore_water/sliding_block.py [OUT.json] [--shapes linear,quadratic] [--transfer pic]

Raw output: benchmarks/results/2026-12-05-issue52/sliding_block.json.
"""

from __future__ import annotations

import argparse
import json
import time

from geompm.testing.verification import sliding_block as sb

SIZES = (0.05, 0.025, 0.0125)
#: the excess that makes lambda = 0.7 at the base
EXCESS = sb.excess_for(0.7)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?", default="sliding_block.json")
    ap.add_argument("--shapes", default="linear,quadratic")
    ap.add_argument("--transfer", default="pic")
    ap.add_argument("--end", type=float, default=0.4)
    args = ap.parse_args()
    rows = []
    for shape in args.shapes.split(","):
        for label, saturated, excess in (("dry", False, 0.0), ("table at top", True, 0.0),
                                         ("excess", True, EXCESS)):
            lam = sb.block_lambda(excess) if saturated else 0.0
            expected = sb.closed_form(lam)
            for h in SIZES:
                t0 = time.perf_counter()
                try:
                    r = sb.block_acceleration(sb.block_case(h, saturated, excess, end=args.end, shape=shape,
                                                            transfer=args.transfer))
                except Exception as exc:  # a blow-up is a measurement too
                    r = {"h": h, "error": f"{type(exc).__name__}: {exc}"[:300]}
                r.update(shape=shape, transfer=args.transfer, case=label, lambda_closed=lam,
                         a_closed=expected, seconds=round(time.perf_counter() - t0, 1))
                if "acceleration" in r and expected > 0:
                    r["a_error"] = r["acceleration"] / expected - 1.0
                print(json.dumps(r), flush=True)
                rows.append(r)
    with open(args.out, "w") as f:
        json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
