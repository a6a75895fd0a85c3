"""The new user's slope with water (geompm/testing/verification/water_slopes.py) against Bishop's simplified
method with the same water, at several cell sizes (docs/slope-stability.md, "Water in slopes").

    python benchmarks/slope_stability/water_slopes.py [--cell-sizes 1 0.5] [--cases dry line slow4 ...]
        [--workers 2] [--out FILE]

Cases: ``dry``; ``line`` (the curved phreatic line from 6 m at the back to the toe, meeting the face near the
toe); ``deepline`` (the same line kept 1 m below the ground); ``slowL`` (a pond at L m
with the water in the slope at the pond's level: slow drawdown to L); ``rapidL`` (the pond drawn down to L m
from the crest with the slope still saturated to its surface: rapid drawdown, drained); ``seepH`` (the steady seepage state from a reservoir at H m behind the slope, its
face free to seep: Bishop with the head the run solves at each cell size).  Prints one JSON line
per run (Bishop's F and circle, geompm's F, bracket, error, trials, wall time) and appends them to --out.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import geompm
from geompm.testing.rows import emit
from geompm.testing.verification.water_slopes import (CREST_X, HEIGHT, TOE_X, bishop_with_line, phreatic_line,
                                                      slope_case)


def water_of(name: str):
    """(phreatic line, pond level) of a case name."""
    if name == "dry":
        return None, None
    if name == "line":
        return phreatic_line(back=6.0), None
    if name == "deepline":  # the same line kept 1 m below the ground: no seepage face
        return phreatic_line(back=6.0, cover=1.0), None
    if name.startswith("seep"):
        return None, None
    level = float(name[5:] if name.startswith("rapid") else name[4:])
    level = None if level <= 0.0 else level  # a pond at the toe's level or below: none
    if name.startswith("slow"):
        return None, level
    ground = [[0.0, HEIGHT], [CREST_X, HEIGHT], [TOE_X, 0.0]]  # saturated to its surface: the line on the ground
    return ground, level


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cell-sizes", type=float, nargs="+", default=[1.0, 0.5])
    ap.add_argument("--cases", nargs="+", default=["dry", "line", "slow2", "slow4", "slow8", "rapid0", "rapid4",
                                                   "rapid8"])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dilation", type=float, default=None,
                    help="the soil's dilation angle [deg] (default the case's 0; 30 = associated flow)")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as work:
        for h in a.cell_sizes:
            for name in a.cases:
                line, pond = water_of(name)
                pond_spec = None if pond is None else {"times": [0.0], "levels": [pond]}
                back = float(name[4:]) if name.startswith("seep") else None
                raw = slope_case(h, line=line, pond=pond_spec, back_head=back)
                if a.dilation is not None:
                    raw["materials"]["soil"]["dilation_angle"] = a.dilation
                head = None
                if back is not None:  # Bishop with the state the run solves at this cell size
                    from geompm.api import scene_from_dict
                    from geompm.kernels.lattice import bilinear

                    nodal = scene_from_dict(raw).water_table.surface.head
                    head = lambda x, y, v=nodal, hh=h: float(bilinear(v, 0.0, 0.0, hh, hh, x, y))  # noqa: E731
                ref, circle = bishop_with_line(line, pond=pond, head=head)
                case = Path(work) / f"{name}_{h:g}.json"
                case.write_text(json.dumps(raw))
                t0 = time.perf_counter()
                res = geompm.stability(case, out=Path(work) / f"stab_{name}_{h:g}", workers=a.workers, threads=1)
                f = res["factor_of_safety"]
                row = {"case": name if a.dilation is None else f"{name}_psi{a.dilation:g}", "cell_size": h, "bishop": ref, "bishop_circle": circle, "factor_of_safety": f,
                       "bracket": res["bracket"], "error": None if f is None else f / ref - 1.0,
                       "trials": len(res["trials"]), "message": res["message"],
                       "wall_seconds": time.perf_counter() - t0}
                emit(row, a.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
