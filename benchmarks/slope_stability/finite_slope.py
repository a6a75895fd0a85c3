"""A slope of Griffiths & Lane's first example's geometry against Bishop's simplified method, at three cell sizes
(docs/slope-stability.md, "Verification: finite slopes").

    python benchmarks/slope_stability/finite_slope.py --cohesion 5000 --friction 30 [--cell-sizes 1 0.5 0.25] [--work DIR]
        [--model mohr_coulomb] [--viscoplastic-time 0]

Prints Bishop's factor and critical circle (geompm/testing/verification/bishop.py, the search of
tests/verification/test_finite_slopes.py), then runs `geompm stability` with its defaults on
geompm/testing/verification/slopes.griffiths_lane_case at each cell size and prints its factor, bracket, the error against
Bishop, the number of trials and of steps.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from geompm.testing.verification.bishop import critical_circle, surface_from_points
from geompm.testing.verification.slopes import griffiths_lane_case


def bishop(c: float, phi: float):
    s = surface_from_points([-100.0, 12.0, 32.0, 200.0], [10.0, 10.0, 0.0, 0.0])
    return critical_circle(s, c, phi, 20000.0, (np.linspace(0, 40, 11), np.linspace(5, 40, 11)),
                           np.linspace(5, 50, 16), base=0.0, lo=0.0, hi=200.0)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cohesion", type=float, required=True, help="c' [Pa]")
    ap.add_argument("--friction", type=float, required=True, help="phi' [deg]")
    ap.add_argument("--cell-sizes", type=float, nargs="+", default=[1.0, 0.5, 0.25])
    ap.add_argument("--model", default="drucker_prager", help="the soil's law (psi = 0 either way)")
    ap.add_argument("--viscoplastic-time", default=None, help="geompm stability's option (default: its own, T/800)")
    ap.add_argument("--work", default=None, help="folder for the cases and the stability runs (default: a temporary one)")
    a = ap.parse_args()
    ref, (xc, yc, r) = bishop(a.cohesion, a.friction)
    print(f"{a.model}, viscoplastic time {a.viscoplastic_time or 'T/800 (default)'}")
    print(f"c' = {a.cohesion:g} Pa (c'/(gamma H) = {a.cohesion / 2e5:g}), phi' = {a.friction:g} deg")
    print(f"  Bishop: F = {ref:.4f}, circle centre ({xc:.2f}, {yc:.2f}) m, R = {r:.2f} m", flush=True)
    work = Path(a.work or tempfile.mkdtemp(prefix="geompm-finite-slope-"))
    work.mkdir(parents=True, exist_ok=True)
    for h in a.cell_sizes:
        case = work / f"slope_h{h:g}.json"
        case.write_text(json.dumps(griffiths_lane_case(h, friction=a.friction, cohesion=a.cohesion, model=a.model)))
        extra = [] if a.viscoplastic_time is None else ["--viscoplastic-time", a.viscoplastic_time]
        out = subprocess.run([sys.executable, "-m", "geompm.cli", "stability", str(case), "--json", "--overwrite",
                              "--out", str(work / f"stability_h{h:g}"), *extra], capture_output=True, text=True)
        d = json.loads(out.stdout.strip().splitlines()[-1])
        steps = 0
        for t in d["trials"]:
            status = Path(t["run_dir"]) / "status.json"
            if status.exists():
                steps += json.loads(status.read_text()).get("steps", 0)
        f = d["factor_of_safety"]
        print(f"  h = {h:g} m: F = {f:.4f} [{d['bracket'][0]:.4f}, {d['bracket'][1]:.4f}], against Bishop "
              f"{100 * (f / ref - 1):+.2f} %, {len(d['trials'])} trials, {steps} steps", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
