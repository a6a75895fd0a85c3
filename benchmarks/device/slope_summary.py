"""The numbers docs/slope-stability.md gives for a run of cases/slope_failure.json, from its run folder.

    python benchmarks/device/slope_summary.py RUN_DIR [RUN_DIR ...]

One JSON line per run: the cell size, particles, steps and wall time (status.json); the failure time, when
the particles' mean displacement passes 1 cm and 10 cm, and F(t) then; the front (largest x [m]) before
and at the end; when the slide is at rest (kinetic energy below 1 J per metre of slope, after the failure);
and from the last VTU the deposit: the surface height (largest y [m]) against the back wall (x < 1 m) and
at x = 48-52 m, and the share of particles whose plastic strain is past the end of softening at that
cell size (eps_2 h_ref / h).
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import numpy as np


def crossing(t, y, level):
    """The first time y reaches level (linear between rows), NaN if never."""
    above = np.nonzero(y >= level)[0]
    if not above.size:
        return float("nan")
    k = int(above[0])
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (level - y[k - 1]) * (t[k] - t[k - 1]) / (y[k] - y[k - 1]))


def summary(run: Path) -> dict:
    import meshio

    rows = list(csv.DictReader((run / "series.csv").open()))
    col = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    t, mean, ke = col["time"], col["mean_displacement"], col["kinetic_energy"]
    case = json.loads((run / "case.json").read_text()) if (run / "case.json").exists() else {}
    status = json.loads((run / "status.json").read_text()) if (run / "status.json").exists() else {}
    fail1, fail10 = crossing(t, mean, 0.01), crossing(t, mean, 0.1)
    moving = np.nonzero(ke >= 1.0)[0]
    rest = float(t[moving[-1] + 1]) if moving.size and moving[-1] + 1 < len(t) else float("nan")
    out = {"run": str(run), "finished": status.get("finished"), "steps": status.get("steps"),
           "wall_s": status.get("wall_seconds"),
           "fail_1cm_s": fail1, "F_at_1cm": float(np.interp(fail1, t, col["strength_factor"])),
           "fail_10cm_s": fail10, "F_at_10cm": float(np.interp(fail10, t, col["strength_factor"])),
           "front_start_m": float(col["front_x"][0]), "front_end_m": float(col["front_x"][-1]),
           "at_rest_s": rest, "time_end_s": float(t[-1])}
    vtus = sorted(run.rglob("*.vtu"))
    if vtus:
        mesh = meshio.read(vtus[-1])
        x, y = mesh.points[:, 0], mesh.points[:, 1]
        out["particles"] = int(len(x))
        out["deposit_back_wall_m"] = float(y[x < 1.0].max()) if (x < 1.0).any() else float("nan")
        far = (x >= 48.0) & (x <= 52.0)
        out["deposit_48_52_m"] = float(y[far].max()) if far.any() else 0.0
        strain = next((v for k, v in mesh.point_data.items() if "plastic_strain" in k), None)
        mat = case.get("materials", {}).get("soil", {})
        soft = mat.get("softening")
        h = case.get("grid", {}).get("cell_size")
        if strain is not None and soft and h:
            end = soft["end"] * (soft.get("reference_cell_size") or h) / h
            out["share_past_residual"] = float(np.mean(np.asarray(strain).ravel() >= end))
    return out


def main(argv) -> int:
    for folder in argv:
        print(json.dumps(summary(Path(folder))), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
