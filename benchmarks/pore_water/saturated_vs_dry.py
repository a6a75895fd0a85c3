"""The main job (cases/debris_obstacle.json) against its saturated twin (cases/saturated_debris_obstacle.json):
the dam's peak force, the runout (the front's largest x), the time each took, and the basal pore pressure
(docs/pore-water.md).

    python benchmarks/pore_water/saturated_vs_dry.py DRY_RUN_FOLDER SATURATED_RUN_FOLDER

Reads each folder's series.csv, status.json and last VTU; prints one table.
"""

import csv
import json
import sys
from pathlib import Path

import meshio
import numpy as np


def series(folder):
    with open(Path(folder) / "series.csv") as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def last_vtu(folder):
    files = sorted((Path(folder) / "particles").glob("particles_*.vtu"))
    return meshio.read(files[-1])


def basal(mesh, h=0.05):
    """Pore pressure [Pa] of the particles within one cell of the bed (the inclined plane through (0, 2.2)
    falling 35 deg, and the floor y = 0)."""
    x = mesh.points
    n = np.array([0.573576, 0.819152])
    d_plane = (x[:, 0] - 0.0) * n[0] + (x[:, 1] - 2.2) * n[1]
    near = (np.minimum(d_plane, x[:, 1]) < h)
    p = mesh.point_data.get("pore_pressure")
    return None if p is None else p[near]


def main(dry, wet):
    out = {}
    for label, folder in (("dry", dry), ("saturated", wet)):
        s = series(folder)
        force = np.sqrt(s["dam_fx"] ** 2 + s["dam_fy"] ** 2 + s["dam_fz"] ** 2)
        k = int(np.argmax(force))
        row = {"peak_force_N": float(force[k]), "peak_time_s": float(s["time"][k]),
               "runout_front_x_m": float(s["front_x"][-1]), "steps": int(s["step"][-1])}
        if "max_excess_pore_pressure" in s:
            j = int(np.argmax(s["max_excess_pore_pressure"]))
            row["max_excess_pore_pressure_Pa"] = float(s["max_excess_pore_pressure"][j])
            row["its_time_s"] = float(s["time"][j])
            pb = basal(last_vtu(folder))
            if pb is not None and pb.size:
                row["final_basal_pore_pressure_mean_Pa"] = float(pb.mean())
                row["final_basal_pore_pressure_max_Pa"] = float(pb.max())
        out[label] = row
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
