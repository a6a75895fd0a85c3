"""Draw docs/figures/terrain_dam_force.png from a run of cases/terrain_debris_flow.json.

    geompm run cases/terrain_debris_flow.json --out runs/terrain_debris_flow
    python benchmarks/terrain_dam_force_plot.py runs/terrain_debris_flow docs/figures/terrain_dam_force.png

The dam's force components from series.csv [kN]: F_x (downstream), F_n (normal, into the dam) and
F_t (tangential).
"""

from __future__ import annotations

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(run_dir: str, out: str) -> None:
    with open(f"{run_dir}/series.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    t = [float(r["time"]) for r in rows]
    fig, ax = plt.subplots(figsize=(8, 3.4))
    for col, label in (("dam_fx", "F_x (downstream)"), ("dam_fn", "F_n (normal, into the dam)"),
                       ("dam_ft", "F_t (tangential)")):
        ax.plot(t, [float(r[col]) / 1e3 for r in rows], label=label)
    dt_out = t[1] - t[0] if len(t) > 1 else 0.0
    ax.set(xlabel="time [s]", ylabel="force on the check dam [kN]",
           title=f"terrain_debris_flow: force on the check dam (series.csv, every {dt_out:g} s)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main(*sys.argv[1:3])
