"""`geompm stability` on a 3D slope: Griffiths & Lane's (1999) first example extruded between end walls
(geompm/testing/verification/slopes.griffiths_lane_case_3d), against the same slope in plane strain.

    python benchmarks/slope_stability/slope3d.py WORK_FOLDER [--cell-sizes 1 0.5] > table.txt

Smooth ("slip") end walls are symmetry planes: the 3D factor must equal the 2D one at the same cell size, at
any width.  Rough ("fixed") end walls hold the slide at its ends: the factor exceeds the 2D one and falls
towards it as the slope widens (L / H = 1, 2, 4 at the coarse cell size).  Each line: the factor, its bracket,
against the 2D factor, the trials, the steps and the wall time of the search on this machine (2 trials in
flight, one thread each).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

from geompm.testing.verification.slopes import griffiths_lane_case, griffiths_lane_case_3d


def search(work: Path, name: str, case: dict) -> dict:
    path = work / f"{name}.json"
    path.write_text(json.dumps(case))
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "geompm.cli", "stability", str(path), "--json", "--overwrite",
                          "--out", str(work / name), "--workers", "2", "--threads", "1"], capture_output=True, text=True)
    if out.returncode:
        raise SystemExit(out.stderr[-2000:])
    d = json.loads(out.stdout.strip().splitlines()[-1])
    d["wall"] = time.perf_counter() - t0
    d["steps"] = sum(json.loads((Path(t["run_dir"]) / "status.json").read_text()).get("steps", 0)
                     for t in d["trials"] if (Path(t["run_dir"]) / "status.json").exists())
    return d


def line(label: str, d: dict, ref: float | None) -> str:
    f, (lo, hi) = d["factor_of_safety"], d["bracket"]
    against = f"  against 2D {100 * (f / ref - 1):+.2f} %" if ref else ""
    return (f"{label:34s} F = {f:.4f} [{lo:.4f}, {hi:.4f}]{against}  {len(d['trials'])} trials, {d['steps']} steps, "
            f"{d['wall']:.0f} s")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("work")
    ap.add_argument("--cell-sizes", type=float, nargs="+", default=[1.0, 0.5])
    a = ap.parse_args()
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    print("Griffiths & Lane (1999) example 1 (c' = 10 kPa, phi' = 20 deg, psi = 0, drucker_prager), trials 3 s, "
          "the stability defaults; 2-core machine, 2 trials in flight, 1 thread each\n")
    for k, h in enumerate(a.cell_sizes):
        two = search(work, f"gl2d_h{h:g}", griffiths_lane_case(h))
        ref = two["factor_of_safety"]
        print(line(f"h = {h:g} m, plane strain", two, None), flush=True)
        rows = [("slip", 5.0)] + ([("fixed", 10.0), ("fixed", 20.0), ("fixed", 40.0)] if k == 0 else [("fixed", 10.0)])
        for ends, width in rows:
            d = search(work, f"gl3d_h{h:g}_{ends}_{width:g}", griffiths_lane_case_3d(h, width, ends))
            print(line(f"h = {h:g} m, {ends} ends, L/H = {width / 10.0:g}", d, ref), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
