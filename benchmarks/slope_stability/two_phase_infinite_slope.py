"""`geompm.stability` on two-phase soil: the saturated infinite slope (table at the surface, seepage parallel to
the slope) as two-phase soil, its trials drained (the pore pressure held at its initial state), against
(gamma' / gamma_sat) tan(phi) / tan(beta) at three cell sizes and two hydraulic conductivities
(docs/slope-stability.md, "Saturated soil").

    python benchmarks/slope_stability/two_phase_infinite_slope.py [--cell-sizes 0.2 0.1 0.05] [--k 1e-5 1e-2]
        [--duration 3] [--out FILE]

Prints one JSON line per run (cell size, k, F, bracket, error, trials, wall time) and writes them to --out.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import geompm
from geompm.testing.verification.slopes import saturated_limit_equilibrium, two_phase_infinite_slope_case


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cell-sizes", type=float, nargs="+", default=[0.2, 0.1, 0.05])
    ap.add_argument("--k", type=float, nargs="+", default=[1e-5, 1e-2], help="hydraulic conductivities [m/s]")
    ap.add_argument("--duration", type=float, default=3.0, help="a trial's simulated time [s]")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    ref = saturated_limit_equilibrium(20.0, 40.0)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for k in a.k:
            for h in a.cell_sizes:
                case = Path(work) / f"slope_{h:g}_{k:g}.json"
                case.write_text(json.dumps(two_phase_infinite_slope_case(h, end=a.duration, conductivity=k)))
                t0 = time.perf_counter()
                res = geompm.stability(case, out=Path(work) / f"stab_{h:g}_{k:g}", tolerance=0.01,
                                       duration=a.duration, workers=a.workers, threads=1)
                f = res["factor_of_safety"]
                row = {"cell_size": h, "hydraulic_conductivity": k, "factor_of_safety": f, "bracket": res["bracket"],
                       "closed_form": ref, "error": None if f is None else f / ref - 1.0,
                       "trials": len(res["trials"]), "message": res["message"],
                       "drained_water": res["drained_water"], "wall_seconds": time.perf_counter() - t0}
                print(json.dumps(row), flush=True)
                rows.append(row)
    if a.out:
        Path(a.out).write_text("".join(json.dumps(r) + "\n" for r in rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
