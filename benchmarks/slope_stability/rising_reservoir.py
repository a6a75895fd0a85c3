"""A reservoir rising behind the new user's slope with a pond at its toe (docs/slope-stability.md, "Water in
slopes"): the steady seepage state (triggers.water_table.seepage) solved again as the head on the back (x-)
side rises, the pond fixed at the toe; the slope fails when its factor of safety passes 1.  The onset's head
against Bishop's: the head at which Bishop's simplified F with the same solved state is 1.

    python benchmarks/slope_stability/rising_reservoir.py [--cell-sizes 1 0.5 0.25] [--pond 1] [--out FILE]

The run: heads 4 m until 1 s, then rising by 0.5 m/s to 10 m at 13 s; the trials' viscous damping (zeta = 20
1/s), so that past its limit the slope slides at v = a / zeta with an acceleration growing with the head, and
the onset is the zero of a line fitted to its surface speed between 5 and 30 mm/s
(slopes.onset_from_velocity).  Prints and appends one JSON line per cell size.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np

import geompm
from geompm.testing.rows import emit
from geompm.api import scene_from_dict
from geompm.kernels.lattice import bilinear
from geompm.testing.verification.slopes import onset_from_velocity
from geompm.testing.verification.water_slopes import bishop_with_line, slope_case

T0, H0, T1, H1 = 1.0, 4.0, 13.0, 10.0


def case(h: float, pond: float, head) -> dict:
    raw = slope_case(h, end=T1, back_head=8.0, pond={"times": [0.0], "levels": [pond]})
    raw["triggers"]["water_table"]["seepage"] = {"times": [0.0, T0, T1] if isinstance(head, list) else [0.0],
                                                 "heads": [{"side": "x-", "head": head}]}
    return raw


def bishop_curve(h: float, pond: float, heads) -> list[float]:
    """Bishop's F with the state solved at cell size h for each back head (the pond's excess and buoyancy)."""
    out = []
    for head in heads:
        nodal = scene_from_dict(case(h, pond, float(head))).water_table.surface.head

        def field(x, y, v=nodal):
            return float(bilinear(v, 0.0, 0.0, h, h, x, y))

        out.append(bishop_with_line(None, pond=pond, head=field)[0])
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cell-sizes", type=float, nargs="+", default=[1.0, 0.5, 0.25])
    ap.add_argument("--pond", type=float, default=1.0)
    ap.add_argument("--dilation", type=float, default=None, help="the soil's dilation angle [deg] (default 0)")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    for h in a.cell_sizes:
        heads = np.arange(H0, H1 + 1e-9, 0.5)
        F = np.array(bishop_curve(h, a.pond, heads))
        below = np.flatnonzero(F < 1.0)
        k = int(below[0]) if len(below) else None
        ref = None if not k else float(heads[k - 1] + (heads[k] - heads[k - 1]) * (F[k - 1] - 1.0) / (F[k - 1] - F[k]))
        raw = case(h, a.pond, [H0, H0, H1])
        if a.dilation is not None:
            raw["materials"]["soil"]["dilation_angle"] = a.dilation
        rate = 20.0
        raw["damping"] = [{"model": "artificial", "xi": 1e-3,
                           "reference_cell_size": 1e-3 * math.sqrt(2.0e7 / raw["materials"]["soil"]["density"]) / rate}]
        raw["outputs"] = [{"writer": "series", "interval": 0.05, "displacement": True}]
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory() as work:
            run = geompm.run(raw, out=Path(work) / "run", progress=False, quiet=True)
            onset_t = onset_from_velocity(run.series, after=T0)
            steps = run.steps
        onset = H0 + (onset_t - T0) * (H1 - H0) / (T1 - T0)
        row = {"cell_size": h, "pond": a.pond, "dilation": a.dilation, "bishop_heads": heads.tolist(), "bishop_F": F.tolist(),
               "bishop_onset_head": ref, "onset_time": onset_t, "onset_head": onset,
               "error": None if ref is None else onset / ref - 1.0, "exit_code": run.exit_code, "steps": steps,
               "wall_seconds": time.perf_counter() - t0}
        emit(row, a.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
