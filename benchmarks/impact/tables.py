"""Markdown tables of an impact convergence study (geompm study --metric impact): the raw and filtered peak,
the impulse, the final load and alpha by cell size and cfl, and the targets of docs/impact-forces.md: the
filtered peak and the impulse within 10 % between the two finest grids and within 5 % across cfl.

    python benchmarks/impact/tables.py benchmarks/results/2026-12-05-issue57/main3d_ref-study.csv dam
"""

from __future__ import annotations

import csv
import sys

KEYS = ("peak_force", "filtered_peak_force", "impulse", "final_force", "alpha")


def table(path: str, label: str) -> str:
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    val = {(float(r["grid.cell_size"]), float(r["time.cfl"])): {k: float(r[f"{k}:{label}"]) for k in KEYS} for r in rows}
    hs = sorted({h for h, _ in val}, reverse=True)
    cfls = sorted({c for _, c in val}, reverse=True)
    out = ["| h [m] | cfl | raw peak | filtered peak | impulse | load at the end | alpha |", "|---|---|---|---|---|---|---|"]
    for h in hs:
        for c in cfls:
            v = val[(h, c)]
            out.append(f"| {h:g} | {c:g} | {v['peak_force']:.1f} | {v['filtered_peak_force']:.1f} | {v['impulse']:.1f} | "
                       f"{v['final_force']:.1f} | {v['alpha']:.2f} |")
    fine, finer = hs[-2], hs[-1]
    out.append("")
    for k in ("peak_force", "filtered_peak_force", "impulse"):
        grids = ", ".join(f"cfl {c:g}: {100 * (val[(finer, c)][k] / val[(fine, c)][k] - 1):+.1f} %" for c in cfls)
        steps = ", ".join(f"h {h:g}: {100 * (val[(h, cfls[-1])][k] / val[(h, cfls[0])][k] - 1):+.1f} %" for h in hs)
        out.append(f"- {k}: h {finer:g} against {fine:g} ({grids}); cfl {cfls[-1]:g} against {cfls[0]:g} ({steps})")
    return "\n".join(out)


if __name__ == "__main__":
    print(table(sys.argv[1], sys.argv[2]))
