"""The infinite-slope case of docs/slope-stability.md (geompm/testing/verification/slopes.py), written to a file.

    python benchmarks/slope_stability/infinite_slope.py OUT.json --cell-size 0.05 [--cohesion 2000] [--dilation 30]
"""

from __future__ import annotations

import argparse
import json

from geompm.testing.verification.slopes import infinite_slope_case, limit_equilibrium

if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--cell-size", type=float, default=0.05)
    ap.add_argument("--cohesion", type=float, default=0.0)
    ap.add_argument("--dilation", type=float, default=30.0)
    ap.add_argument("--model", default="drucker_prager")
    a = ap.parse_args()
    with open(a.out, "w") as fh:
        json.dump(infinite_slope_case(a.cell_size, cohesion=a.cohesion, dilation=a.dilation, model=a.model), fh, indent=1)
    print("limit equilibrium F =", limit_equilibrium(20.0, 30.0, a.cohesion))
