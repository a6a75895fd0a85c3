"""DEM incline against the closed form at three cell sizes (issue 18 verification, docs/terrain.md).

    python benchmarks/terrain_incline_convergence.py [0.1 0.05 0.025]

The block of tests/verification/test_terrain.py (30 deg, mu = 0.3, slope turned 37 deg about the vertical) on the
terrain and on the analytic plane, with the DEM pixel equal to the cell size; prints the distance slid
in 0.4 s against s = g (sin theta - mu cos theta) t^2 / 2, the time-mean normal force against
M g cos theta, and the deepest particle below the ground in cells.
"""

import math
import sys
import tempfile
import time
from pathlib import Path


import geompm.testing.verification.terrain_block as T


def main():
    sizes = [float(a) for a in sys.argv[1:]] or [0.1, 0.05, 0.025]
    th = math.radians(30.0)
    exact = 9.81 * (math.sin(th) - 0.3 * math.cos(th)) * 0.4 ** 2 / 2
    for h in sizes:
        t0 = time.perf_counter()
        s_dem, sim, low, fn = T.slide(Path(tempfile.mkdtemp()), 37.0, "terrain", h=h)
        wall = time.perf_counter() - t0
        s_pl, _, _, _ = T.slide(Path(tempfile.mkdtemp()), 37.0, "plane", h=h)
        m = float(sim.state.p_mass.sum())
        print(f"h = {h:g} m: {sim.state.n} particles, {sim.step_count} steps, {wall:.1f} s; slid {s_dem:.4f} m "
              f"(plane {s_pl:.4f}, exact {exact:.4f}: {100 * (s_dem / exact - 1):+.2f} %); mean F_n {fn:.2f} N "
              f"(M g cos theta {m * 9.81 * math.cos(th):.2f}: {100 * (fn / (m * 9.81 * math.cos(th)) - 1):+.2f} %); "
              f"deepest {-min(low, 0.0) / h:.3f} h", flush=True)


if __name__ == "__main__":
    main()
