"""Section 3.1 of the source study: the granular column down a 10 degree incline at three meshes.

    python benchmarks/seed/inclined_flow.py OUT [--h 0.02,0.01,0.005] [--sensitivity]
    python benchmarks/seed/inclined_flow.py OUT --summarise RUN_DIR [RUN_DIR ...]

Runs `geompm study cases/inclined_flow.json --vary grid.cell_size=...` into OUT/meshes (one variant at a
time with every core: the finest mesh dominates), and with --sensitivity a second study at h = 0.02 m of
the parameters the source leaves open (E x 0.5 and x 2 around 0.84 MPa; xi = 0.002, the top of the
source's 0.001-0.002) into OUT/sensitivity_*.  Then, from the run folders' series.csv (T_star, X_star,
K_star columns of the series writer's `normalise`):

- OUT/inclined_flow.png: X*(T*) and K*(T*) at every mesh in one figure (the source's Figs. 5-6);
- OUT/inclined_flow.csv: per run h, particles, steps, wall seconds, final X*, peak K* and its T*;
- printed: the spread of the final X* and of the K* peak between the two finest meshes, and the observed
  order of each over three meshes (Celik et al. 2008, geompm.study.metrics.richardson_order).

``--summarise`` skips the runs and reads existing run folders (a `geompm run` of the case with
`--set grid.cell_size=H` gives the same folder as a study variant).
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "inclined_flow.json"
#: the sensitivity variants: the open parameters, each changed alone at h = SENSITIVITY_H
SENSITIVITY = ("materials.beads.youngs_modulus=420000,1680000", "damping.0.xi=0.002")
SENSITIVITY_H = 0.02
#: the vtu writer's interval in these runs [s] (the shipped case writes every 0.1 s): t = 0, 0.3, ... 1.2 s
VTU_INTERVAL = "outputs.1.interval=0.3"


def study(out: Path, varies: list[str], sets: list[str]) -> float:
    """One `geompm study` (sequential variants, all cores each); its wall time [s]."""
    import os

    from geompm.cli import main

    argv = ["study", str(CASE), "--out", str(out), "--workers", "1", "--threads", str(os.cpu_count() or 1),
            "--resume", "--quiet", "--set", VTU_INTERVAL]
    for v in varies:
        argv += ["--vary", v]
    for s in sets:
        argv += ["--set", s]
    t0 = time.perf_counter()
    code = main(argv)
    if code != 0:
        sys.exit(f"geompm study exited {code} for {out}")
    return time.perf_counter() - t0


def read(run: Path) -> dict:
    from geompm.study.metrics import read_run

    series, status = read_run(run)
    case = json.loads((run / "case.json").read_text())
    k = int(series["K_star"].argmax())
    return {"run": str(run), "h": float(case["grid"]["cell_size"]),
            "E": float(case["materials"]["beads"]["youngs_modulus"]),
            "xi": float(case["damping"][0]["xi"]), "h_ref": case["damping"][0].get("reference_cell_size"),
            "particles": status.get("particles"),
            "steps": status.get("steps"), "wall_s": status.get("wall_seconds"),
            "final_T": float(series["T_star"][-1]), "final_X": float(series["X_star"][-1]),
            "K_peak": float(series["K_star"][k]), "T_at_K_peak": float(series["T_star"][k]),
            "series": series}


def summarise(runs: list[Path], out: Path) -> list[dict]:
    from geompm.study.metrics import richardson_order

    rows = sorted((read(r) for r in runs), key=lambda r: (r["E"], r["xi"], r["h_ref"] or 0.0, -r["h"]))
    out.mkdir(parents=True, exist_ok=True)
    keys = [k for k in rows[0] if k != "series"]
    with open(out / "inclined_flow.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: r[k] for k in keys})
    base = baseline(rows)
    for r in rows:
        print(f"h = {r['h']:<6g} E = {r['E']:<8g} xi = {r['xi']:<6g} h_ref = {r['h_ref'] or '-'} particles {r['particles']:>7} "
              f"steps {r['steps']:>6} wall {r['wall_s']:8.1f} s  final X* {r['final_X']:.4f}  "
              f"K* peak {r['K_peak']:.5f} at T* {r['T_at_K_peak']:.3f}")
    if len(base) >= 2:
        a, b = base[-2], base[-1]  # the two finest
        print(f"two finest meshes (h = {a['h']:g}, {b['h']:g}): final X* differs by "
              f"{abs(a['final_X'] - b['final_X']) / abs(b['final_X']):.2%}, K* peak by "
              f"{abs(a['K_peak'] - b['K_peak']) / abs(b['K_peak']):.2%}")
    if len(base) >= 3:
        hs = [r["h"] for r in base]
        print(f"observed order over h = {hs}: final X* {richardson_order(hs, [r['final_X'] for r in base]):.3g}, "
              f"K* peak {richardson_order(hs, [r['K_peak'] for r in base]):.3g} (nan: not monotone)")
    plot(base, out / "inclined_flow.png")
    return rows


def baseline(rows: list[dict]) -> list[dict]:
    """The shipped case's parameters (E = 0.84 MPa, xi = 0.001 at the grid's h), coarsest mesh first."""
    return [r for r in rows if r["E"] == 840000.0 and r["xi"] == 0.001 and r["h_ref"] is None]


def plot(rows: list[dict], png: Path) -> None:
    """X*(T*) and K*(T*) of the runs (the source's Figs. 5-6): solid at the grid's own damping rate, dashed
    where the rate is held at a reference cell size's (``h_ref``), one colour per cell size."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.5, 7.5), dpi=120, sharex=True)
    colors = {0.02: "tab:blue", 0.01: "tab:orange", 0.005: "tab:green"}
    for r in rows:
        fixed = r["h_ref"] is not None
        s, style = r["series"], "--" if fixed else "-"
        label = f"h = {r['h']:g} m" + (", zeta fixed" if fixed else f" ({r['particles']} particles)")
        ax1.plot(s["T_star"], s["X_star"], style, color=colors.get(r["h"], "k"), label=label)
        ax2.plot(s["T_star"], s["K_star"], style, color=colors.get(r["h"], "k"), label=label)
    ax1.set_ylabel("X* = (x_front - l0) / l0")
    ax2.set_ylabel("K* = E_k / (m g h0)")
    ax2.set_xlabel("T* = t sqrt(g / h0)")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax1.set_title("inclined flow (source sec. 3.1), DP, 3D: solid xi = 0.001, dashed zeta of h = 0.02 m", fontsize=10)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", type=Path)
    p.add_argument("--h", default="0.02,0.01,0.005", help="cell sizes [m]")
    p.add_argument("--sensitivity", action="store_true", help="also E x 0.5, x 2 and xi = 0.002 at h = 0.02 m")
    p.add_argument("--summarise", nargs="+", type=Path, metavar="RUN_DIR", help="read these runs, run nothing")
    args = p.parse_args()
    if args.summarise:
        summarise(args.summarise, args.out)
        return
    wall = study(args.out / "meshes", [f"grid.cell_size={args.h}"], [])
    runs = sorted((args.out / "meshes" / "runs").iterdir())
    if args.sensitivity:
        for v in SENSITIVITY:
            wall += study(args.out / f"sensitivity_{v.split('=')[0].split('.')[-1]}", [v],
                          [f"grid.cell_size={SENSITIVITY_H}"])
        runs += sorted(r for d in args.out.glob("sensitivity_*") for r in (d / "runs").iterdir())
    summarise(runs, args.out)
    print(f"wall time of the runs: {wall:.0f} s")


if __name__ == "__main__":
    main()
