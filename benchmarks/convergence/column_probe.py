"""Probe the DP column collapse's runout under refinement (issue 15, point 2): one line per cell size.

    python benchmarks/convergence/column_probe.py 0.02 0.01 0.005 --set KEY=VALUE ... [--end 0.8]

Runs cases/column_collapse.json (a = H0/L0 = 0.5) through the Python API to t = end and prints the
runout (L - L0)/L0 by two metrics: the furthest particle, and the deposit front at a thickness of
0.05 H0 (geompm.study.deposit), plus the final height / H0, steps and wall seconds.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_file  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402
from geompm.study.deposit import deposit_front, deposit_height  # noqa: E402

L0, H0, RHO = 0.2, 0.1, 2650.0


def run(h, sets, end, extra_stages=()):
    scene = scene_from_file(ROOT / "cases" / "column_collapse.json",
                            [f"grid.cell_size={h}", f"time.end={end}", "outputs=[]", *sets])
    for stage in extra_stages:
        stage.setup(scene)
        scene.damping.append(stage)
    sim = Simulation(scene)
    t0 = time.perf_counter()
    while sim.time < end:
        sim.step(min(sim.stable_dt(), end - sim.time))
    st = sim.state
    far = st.p_x[:, 0].max()
    area = st.p_mass / RHO  # reference (solid) areas: a particle that dilated does not thicken the deposit
    front = deposit_front(st.p_x, area, 0.05 * H0, H0 / 200)
    top = deposit_height(st.p_x, area, H0 / 200)
    return far, front, top, sim.step_count, time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cell_sizes", nargs="+", type=float)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--end", type=float, default=0.8)
    ap.add_argument("--stage", action="append", default=[], help="module:Class of an extra particle stage")
    a = ap.parse_args()
    import importlib

    stages = [getattr(importlib.import_module(m), c) for m, c in (x.split(":") for x in a.stage)]
    print(f"sets: {a.set}, stages: {a.stage}, end {a.end} s")
    print("h [m] | far (L-L0)/L0 | front@0.05H0 (L-L0)/L0 | H/H0 | steps | wall s")
    for h in a.cell_sizes:
        far, front, top, steps, wall = run(h, a.set, a.end, [cls() for cls in stages])
        print(f"{h:g} | {(far - L0) / L0:.3f} | {(front - L0) / L0:.3f} | {top / H0:.3f} | {steps} | {wall:.1f}",
              flush=True)


if __name__ == "__main__":
    main()
