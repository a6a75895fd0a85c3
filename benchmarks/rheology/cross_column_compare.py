"""The source's Cross column (cases/column_collapse_cross.json) explicit against elasto-viscoplastic.

    python benchmarks/rheology/cross_column_compare.py OUT_DIR [--runs NAME=--set,...]

Runs each variant with `geompm run` (one numba thread each, two at a time) into OUT_DIR/NAME, then
prints, per run: steps, wall seconds (from run.log), the deposit front (deposit.deposit_front, thickness
threshold 0.05 H0 = 5 mm, solid areas m/rho0) and height (deposit.deposit_height, window 5 mm) of the
final VTU, and the largest particle x; and each run's front and height relative to the first run.
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import meshio

from geompm.writers.deposit import deposit_front, deposit_height

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "column_collapse_cross.json"
EVP = "materials.soil.integration=elastoviscoplastic"
RUNS = {  # name -> --set overrides
    "explicit": [],
    "evp": [EVP],
    "evp_dt_explicit": [EVP, "time.dt_max=5.52e-6"],
    "evp_dt_5x": [EVP, "time.dt_max=2.76e-5"],
    "explicit_flip_tau": ["solver.transfer=flip", "solver.flip_relaxation_time=0.1"],
    "evp_flip_tau": [EVP, "solver.transfer=flip", "solver.flip_relaxation_time=0.1"],
}
H0, RHO0, DX = 0.1, 2650.0, 0.001


def run(out: Path, name: str, sets: list[str]) -> None:
    if (out / name / "run.log").is_file() and "done:" in (out / name / "run.log").read_text():
        return
    cmd = [sys.executable, "-m", "geompm.cli", "run", str(CASE), "--out", str(out / name), "--quiet", "--overwrite"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, env={**os.environ, "NUMBA_NUM_THREADS": "1"})


def measure(folder: Path) -> dict:
    last = sorted(glob.glob(str(folder / "particles" / "*.vtu")))[-1]
    m = meshio.read(last)
    area = m.point_data["volume"] * m.point_data["density"] / RHO0  # m / rho0 [m2 per m]
    done = re.search(r"done: (\d+) steps to t = \S+ s in ([\d.]+) s wall", (folder / "run.log").read_text())
    return {"steps": int(done.group(1)), "wall": float(done.group(2)),
            "front": deposit_front(m.points[:, :2], area, 0.05 * H0, DX),
            "height": deposit_height(m.points[:, :2], area, DX, 0.05 * H0), "x_max": float(m.points[:, 0].max())}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", type=Path)
    ap.add_argument("--only", nargs="*", help="run names (default all)")
    a = ap.parse_args()
    names = a.only or list(RUNS)
    with ThreadPoolExecutor(2) as pool:
        list(pool.map(lambda n: run(a.out, n, RUNS[n]), names))
    rows = {n: measure(a.out / n) for n in names}
    ref = rows[names[0]]
    print(f"{'run':20s} {'steps':>8s} {'wall s':>7s} {'front m':>8s} {'vs ' + names[0]:>12s} {'height m':>9s} "
          f"{'vs ' + names[0]:>12s} {'x_max m':>8s}")
    for n, r in rows.items():
        print(f"{n:20s} {r['steps']:8d} {r['wall']:7.1f} {r['front']:8.4f} {r['front'] / ref['front'] - 1:+12.2%} "
              f"{r['height']:9.4f} {r['height'] / ref['height'] - 1:+12.2%} {r['x_max']:8.4f}")


if __name__ == "__main__":
    main()
