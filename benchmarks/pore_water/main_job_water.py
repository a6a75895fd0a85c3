"""The saturated main job against the dry one at each cell size run: the basal pore-pressure ratio in time,
the dam's peak force and the runout (docs/pore-water.md, The main job, saturated).

    python benchmarks/pore_water/main_job_water.py OUT.json H:DRY_RUN:SATURATED_RUN [...]

Each run folder is a `geompm run` of cases/debris_obstacle.json or cases/saturated_debris_obstacle.json at
cell size H (--set grid.cell_size=H).  The basal ratio at each VTU time: lambda = sum p / sum sigma_n over
the particles within one cell of the bed (the 35 degree plane through (0, 2.2) and the floor y = 0), sigma_n
the total normal stress on the bed's plane (the saturated VTU's "stress" is total), counting the particles
flagged drained (p = 0) as the bed sees them.
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import meshio
import numpy as np

PLANE_N = np.array([0.573576, 0.819152, 0.0])


def series(folder):
    with open(Path(folder) / "series.csv") as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def basal_ratio(mesh, h):
    """(time-free) lambda of one VTU and the number of basal particles, the drained share among them."""
    x = mesh.points
    d_plane = (x[:, 0] * PLANE_N[0] + (x[:, 1] - 2.2) * PLANE_N[1])
    on_plane = d_plane < h
    on_floor = (x[:, 1] < h) & ~on_plane
    s = mesh.point_data["stress"]  # Voigt xx yy zz xy yz xz, total, tension positive
    sig_plane = -(s[:, 0] * PLANE_N[0] ** 2 + s[:, 1] * PLANE_N[1] ** 2 + 2 * s[:, 3] * PLANE_N[0] * PLANE_N[1])
    sig_floor = -s[:, 1]
    sig = np.where(on_plane, sig_plane, sig_floor)
    near = on_plane | on_floor
    p = mesh.point_data["pore_pressure"]
    if not near.any():
        return float("nan"), 0, float("nan")
    drained = mesh.point_data.get("drained")
    share = float(drained[near].mean()) if drained is not None else float("nan")
    return float(p[near].sum() / max(sig[near].sum(), 1e-9)), int(near.sum()), share


def summary(folder, h, wet):
    s = series(folder)
    force = np.sqrt(s["dam_fx"] ** 2 + s["dam_fy"] ** 2 + s["dam_fz"] ** 2)
    k = int(np.argmax(force))
    out = {"peak_force_N": float(force[k]), "peak_time_s": float(s["time"][k]),
           "runout_front_x_m": float(s["front_x"][-1]), "steps": int(s["step"][-1])}
    if wet:
        lam = []
        for f in sorted((Path(folder) / "particles").glob("particles_*.vtu")):
            mesh = meshio.read(f)
            t = float(f.stem.split("_")[-1]) if "time" not in mesh.field_data else float(mesh.field_data["time"])
            r, n, share = basal_ratio(mesh, h)
            lam.append({"vtu": f.name, "lambda": r, "basal_particles": n, "drained_share": share})
        out["basal_ratio"] = lam
    return out


def main(argv):
    out_path, runs = argv[0], argv[1:]
    rows = []
    for spec in runs:
        h, dry, wet = spec.split(":")
        rows.append({"h": float(h), "dry": summary(dry, float(h), False), "saturated": summary(wet, float(h), True)})
    Path(out_path).write_text(json.dumps(rows, indent=1) + "\n")
    print(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main(sys.argv[1:])
