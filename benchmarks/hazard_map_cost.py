"""Cost of the hazard-map accumulation per step against the step (issue 18 target: under 5 %).

    python benchmarks/hazard_map_cost.py [CELL_SIZE] [--steps 40]

The sliding block of tests/verification/test_terrain.py (30 deg DEM incline, pixel = cell size), made 4 x 4 times
larger in plan (1.2 m x 1.2 m x 0.15 m), stepped through the Python API; the hazard-map writer's
per-step pass (binning the particles into the DEM's pixels and updating the maxima) is timed apart.
"""

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np


import geompm.testing.verification.terrain_block as T
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.writers.hazard_maps import HazardMapParams, HazardMapWriter


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("h", nargs="?", type=float, default=0.025)
    ap.add_argument("--steps", type=int, default=40)
    a = ap.parse_args()
    tmp = Path(tempfile.mkdtemp())
    case, down, height = T.block_case(tmp, 30.0, 0.0, 0.3, "terrain")
    import trimesh

    th = math.radians(30.0)
    normal = np.array([math.sin(th), 0.0, math.cos(th)])
    block = trimesh.creation.box(extents=[1.2, 1.2, 0.15])
    rot = np.eye(4)
    rot[:3, :3] = np.stack([down, np.cross(normal, down), normal], axis=1)
    block.apply_transform(rot)
    block.apply_translation(np.array([0.9, 0.9, 1.2]) + 0.076 * normal)
    block.export(tmp / "block.stl")
    n = int(round(2.2 / a.h))
    T.write_dem(tmp / "slope.tif", height, -0.2, -0.2, n, n, a.h)
    case["grid"]["cell_size"] = a.h
    sim = Simulation(scene_from_dict(case, base_dir=tmp))
    writer = HazardMapWriter(HazardMapParams(), 0.0)
    writer.open(tmp, sim)
    for _ in range(3):
        sim.step(sim.stable_dt())
        writer.write(sim)
    step = maps = 0.0
    for _ in range(a.steps):
        t0 = time.perf_counter()
        sim.step(sim.stable_dt())
        t1 = time.perf_counter()
        writer.write(sim)
        t2 = time.perf_counter()
        step += t1 - t0
        maps += t2 - t1
    cells = writer.depth.size
    print(f"h = {a.h:g} m: {sim.state.n} particles, {cells} map cells; step {1e3 * step / a.steps:.2f} ms, "
          f"maps {1e3 * maps / a.steps:.3f} ms per step ({100 * maps / step:.2f} % of the step)")


if __name__ == "__main__":
    main()
