"""Every shipped case's series.csv before and after a change that must not change behaviour.

    python benchmarks/refactor/series_compare.py record OUT [--steps 300]   # plan and run, write OUT/plan.json
    python benchmarks/refactor/series_compare.py replay PLAN OUT            # the same runs with this checkout
    python benchmarks/refactor/series_compare.py compare BEFORE AFTER [--rtol 1e-12]

``record`` runs each case of cases/ and cases/seed/ for about ``--steps`` steps: the end time is that many
first stable steps (never past the case's own end), the series writer writes 20 rows and the vtu writer
only at the start and the end.  The end time and overrides go to OUT/plan.json, so ``replay`` needs none
of geompm's Python API (which the change may move): it runs ``python -m geompm.cli run`` with the same
``--set`` lines.  Runs use 1 numba thread, so a parallel reduction's order cannot differ between the two.
``compare`` reads every column of each pair of series.csv and prints the largest relative difference,
|a - b| / max(|b|, tiny), per case; it exits 1 if any exceeds ``--rtol``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def shipped_cases() -> list[Path]:
    return sorted((ROOT / "cases").glob("*.json")) + sorted((ROOT / "cases" / "seed").glob("*.json"))


def plan_case(path: Path, steps: int) -> list[str]:
    from geompm.api import scene_from_dict
    from geompm.engine.scheduler import Simulation

    raw = json.loads(path.read_text())
    dt0 = Simulation(scene_from_dict(raw, base_dir=path.parent)).stable_dt()
    end = min(float(raw["time"]["end"]), steps * dt0)
    sets = [f"time.end={end!r}"]
    for i, out in enumerate(raw.get("outputs", [])):
        if out.get("writer") == "series":
            sets.append(f"outputs.{i}.interval={end / 20!r}")
        elif "interval" in out:
            sets.append(f"outputs.{i}.interval={end!r}")
    return sets


def run(case: str, sets: list[str], out: Path) -> int:
    argv = [sys.executable, "-m", "geompm.cli", "run", str(ROOT / case), "--out", str(out), "--quiet"]
    for s in sets:
        argv += ["--set", s]
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    return subprocess.run(argv, env=env, cwd=ROOT).returncode


def replay(plan: dict, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for name, item in plan.items():
        code = run(item["case"], item["sets"], out / name)
        print(f"{name}: exit {code}", flush=True)


def read(path: Path) -> tuple[list[str], np.ndarray]:
    lines = path.read_text().splitlines()
    head = lines[0].split(",")
    return head, np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])


def compare(before: Path, after: Path, rtol: float) -> int:
    plan = json.loads((before / "plan.json").read_text())
    worst_all = 0.0
    for name in plan:
        a, b = before / name / "series.csv", after / name / "series.csv"
        if not (a.is_file() and b.is_file()):
            print(f"{name}: missing series.csv ({'before' if not a.is_file() else 'after'})")
            worst_all = np.inf
            continue
        (ha, va), (hb, vb) = read(a), read(b)
        if ha != hb or va.shape != vb.shape:
            print(f"{name}: columns or rows differ ({len(ha)} x {len(va)} against {len(hb)} x {len(vb)})")
            worst_all = np.inf
            continue
        rel = np.abs(va - vb) / np.maximum(np.abs(va), 1e-300)
        rel[(va == 0) & (vb == 0)] = 0.0
        k = np.unravel_index(int(np.argmax(rel)), rel.shape) if rel.size else (0, 0)
        worst = float(rel[k]) if rel.size else 0.0
        worst_all = max(worst_all, worst)
        print(f"{name}: {va.shape[0]} rows x {va.shape[1]} columns, largest relative difference {worst:.3g}"
              + (f" ({ha[k[1]]}, row {k[0]})" if worst > 0 else ""))
    print(f"largest over all cases: {worst_all:.3g} (tolerance {rtol:g})")
    return 0 if worst_all <= rtol else 1


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("record")
    r.add_argument("out", type=Path)
    r.add_argument("--steps", type=int, default=300)
    rp = sub.add_parser("replay")
    rp.add_argument("plan", type=Path)
    rp.add_argument("out", type=Path)
    c = sub.add_parser("compare")
    c.add_argument("before", type=Path)
    c.add_argument("after", type=Path)
    c.add_argument("--rtol", type=float, default=1e-12)
    args = p.parse_args()
    if args.cmd == "compare":
        return compare(args.before, args.after, args.rtol)
    if args.cmd == "replay":
        replay(json.loads(args.plan.read_text()), args.out)
        return 0
    plan = {}
    for path in shipped_cases():
        name = str(path.relative_to(ROOT / "cases")).removesuffix(".json").replace("/", "_")
        plan[name] = {"case": str(path.relative_to(ROOT)), "sets": plan_case(path, args.steps)}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "plan.json").write_text(json.dumps(plan, indent=1) + "\n")
    replay(plan, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
