"""How thick is the sheared layer of the DP column collapse, and does it scale with h? (issue 15)

    python benchmarks/convergence/shear_layer_probe.py 0.02 0.01 0.005 0.0025 [--time 0.15] [--set K=V]

Runs cases/column_collapse.json to t = --time and, in the vertical strip --strip X0 X1 (default
0.05 < x < 0.15 m, inside the collapsing column), sorts the particles by height and takes the horizontal velocity profile u(y) (mean
of the particles in bins of 2.5 mm).  Prints, per h, the height below which u is under 50 % of the
strip's top speed (the base of the flowing layer) and the 10-90 % rise height of u (the thickness of the
shear zone), both in m and in cells.  A zone that stays a fixed number of cells thick as h halves is set
by the grid, not by the material.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402


def profile(h, t_end, sets, x0, x1):
    sim = Simulation(scene_from_file(ROOT / "cases" / "column_collapse.json",
                                     [f"grid.cell_size={h}", "outputs=[]", *sets]))
    while sim.time < t_end:
        sim.step(min(sim.stable_dt(), t_end - sim.time))
    x, v = sim.state.p_x, sim.state.p_v
    sel = (x[:, 0] > x0) & (x[:, 0] < x1)
    y, u = x[sel, 1], v[sel, 0]
    edges = np.arange(0.0, y.max() + 0.0025, 0.0025)
    idx = np.digitize(y, edges) - 1
    prof = np.array([u[idx == k].mean() if (idx == k).any() else np.nan for k in range(len(edges) - 1)])
    ymid = 0.5 * (edges[1:] + edges[:-1])
    ok = np.isfinite(prof)
    ymid, prof = ymid[ok], prof[ok]
    top = np.nanmax(prof)
    def height(frac):
        above = np.nonzero(prof >= frac * top)[0]
        return float(ymid[above[0]]) if above.size else float("nan")
    return top, height(0.5), height(0.9) - height(0.1)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cell_sizes", nargs="+", type=float)
    ap.add_argument("--time", type=float, default=0.15)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--strip", nargs=2, type=float, default=[0.05, 0.15], metavar=("X0", "X1"))
    a = ap.parse_args()
    print(f"t = {a.time} s, strip {a.strip[0]} < x < {a.strip[1]} m, sets {a.set}")
    print("h [m] | top u [m/s] | base of flowing layer (u = 50 %) [m] (cells) | 10-90 % rise [m] (cells)")
    for h in a.cell_sizes:
        top, base, rise = profile(h, a.time, a.set, *a.strip)
        print(f"{h:g} | {top:.3f} | {base:.4f} ({base / h:.2f}) | {rise:.4f} ({rise / h:.2f})", flush=True)


if __name__ == "__main__":
    main()
