"""Saturated layers at rest against impermeable rigid solids (geompm/testing/verification/solid_layers.py):
the bottom row's pore pressure against rho_w g depth and its drained fraction, at three cell sizes, with the
solids' fill (schemes/saturated/solids.py) and without it (``before``: the solids counted as empty space).

    python benchmarks/pore_water/solid_layers.py [OUT.json] [--cases box2d,stl3d,terrain3d,incline3d,plane3d,
                                                                     plane2d,plane2d_si]

(plane2d_si: the 2D layer on a plane run by the semi-implicit step.)

Raw output: benchmarks/results/2026-12-05-issue52/solid_layers.json.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from geompm.schemes.saturated import solids
from geompm.testing.verification import solid_layers as sl

SIZES = {"box2d": (0.1, 0.05, 0.025), "stl3d": (0.1, 0.05, 0.04), "terrain3d": (0.1, 0.05, 0.025),
         "incline3d": (0.1, 0.05, 0.04), "plane3d": (0.1, 0.05, 0.04), "plane2d": (0.1, 0.05, 0.025),
         "plane2d_si": (0.1, 0.05, 0.025)}


def case_for(name: str, h: float, where: Path):
    if name == "box2d":
        return sl.floor_2d(h, "box")
    if name == "stl3d":
        return sl.floor_3d(where, h)
    if name == "terrain3d":
        return sl.terrain_3d(where, h, slope_deg=0.0)
    if name == "incline3d":
        return sl.terrain_3d(where, h, slope_deg=10.0)
    if name.startswith("plane2d"):
        return sl.inclined_plane_2d(h, update="saturated_semi_implicit" if name.endswith("_si") else "saturated")
    return sl.inclined_plane_3d(where, h, slope_deg=10.0)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?", default="solid_layers.json")
    ap.add_argument("--cases", default="box2d,stl3d,terrain3d,incline3d,plane3d")
    ap.add_argument("--before", action="store_true", help="also without the solids' fill, at the coarsest size")
    args = ap.parse_args()
    rows = []
    filled = solids.SolidFill.__bool__
    for name in args.cases.split(","):
        for k, h in enumerate(SIZES[name]):
            for before in ((False, True) if args.before and k == 0 else (False,)):
                solids.SolidFill.__bool__ = (lambda self: False) if before else filled
                where = Path(tempfile.mkdtemp())
                t0 = time.perf_counter()
                r = sl.bottom_row(case_for(name, h, where), 0.2, base_dir=where)
                r.update(case=name, h=h, before=before, seconds=round(time.perf_counter() - t0, 1))
                rows.append(r)
                print(json.dumps(r), flush=True)
    solids.SolidFill.__bool__ = filled
    Path(args.out).write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
