"""Measure the check dam of cases/debris_obstacle.json at several cell sizes (issue 15, point 1).

For each h: `geompm run cases/debris_obstacle.json --set grid.cell_size=h`, then from every VTU output
the exact signed distance of each particle to the dam (trimesh, on the STL placed as in the case), and
from series.csv the dam's peak force.  Prints one row per h: particles, peak force [N] and its time,
particles past the dam's downstream face (x > 2.75 m; the 0.1 m slit lets some through legitimately),
particles ever inside a block deeper than 0.25 h, and the deepest [h].

    python benchmarks/contact/debris_obstacle_guard.py 0.1 0.085 0.07 0.06 --out runs/guard
"""

from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
from pathlib import Path

import meshio
import numpy as np
import trimesh

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "debris_obstacle.json"


def dam_mesh() -> trimesh.Trimesh:
    case = json.loads(CASE.read_text())
    ob = case["obstacles"][0]
    mesh = trimesh.load(CASE.parent / ob["file"], force="mesh")
    mesh.apply_scale(ob.get("scale", 1.0))
    mesh.apply_translation(ob["translate"])
    return mesh


def measure(h: float, out: Path, mesh) -> dict:
    run = out / f"h{h:g}"
    cmd = [sys.executable, "-m", "geompm.cli", "run", str(CASE), "--set", f"grid.cell_size={h}", "--out",
           str(run), "--quiet"] + (["--overwrite"] if run.exists() else [])
    subprocess.run(cmd, check=True)
    rows = list(csv.DictReader(open(run / "series.csv")))
    fn = np.array([float(r["dam_fn"]) for r in rows])
    fmag = np.array([np.linalg.norm([float(r[f"dam_f{c}"]) for c in "xyz"]) for r in rows])
    k = int(fmag.argmax())
    deepest, inside, past, n = 0.0, 0, 0, 0
    for vtu in sorted((run / "particles").glob("*.vtu")):
        x = meshio.read(vtu).points
        n = len(x)
        depth = trimesh.proximity.signed_distance(mesh, x)  # positive inside
        deepest = max(deepest, float(depth.max()))
        inside = max(inside, int((depth > 0.25 * h).sum()))
        past = int((x[:, 0] > 2.75).sum())
    return {"h": h, "particles": n, "peak_force_N": float(fmag[k]), "peak_time_s": float(rows[k]["time"]),
            "peak_fn_N": float(fn.max()), "past_face_at_end": past, "deeper_than_quarter_h": inside,
            "deepest_over_h": deepest / h}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cell_sizes", nargs="+", type=float)
    ap.add_argument("--out", default="runs/guard")
    args = ap.parse_args()
    mesh = dam_mesh()
    out = Path(args.out)
    print("h [m] | particles | peak |F| [N] | at t [s] | peak f_n [N] | past x > 2.75 m at the end | "
          "deeper than 0.25 h (any output) | deepest [h]")
    for h in args.cell_sizes:
        r = measure(h, out, mesh)
        print(f"{r['h']:g} | {r['particles']} | {r['peak_force_N']:.1f} | {r['peak_time_s']:.3f} | "
              f"{r['peak_fn_N']:.1f} | {r['past_face_at_end']} | {r['deeper_than_quarter_h']} | "
              f"{r['deepest_over_h']:.3f}", flush=True)


if __name__ == "__main__":
    main()
