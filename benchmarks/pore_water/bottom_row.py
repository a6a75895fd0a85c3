"""The bottom row of a saturated flow on a bed aligned with the grid (docs/pore-water.md, Walls and the bottom
row; schemes/saturated/mirror.py): the 2D twin of the main job on a 35 degree slope written as a horizontal
bed under turned gravity (geompm/testing/verification/bottom_row.py), h = 0.05 m unless --h is given.  Every 0.1 s: the
centroid, the mean downslope speed, the pore pressure (largest, least, mean) and the basal friction force
(the x-momentum the boundary stages take per second, N/m); at 0.4 s the particles' mean pore pressure in
0.1 m x 0.05 m bins (rows from the bed up).

    python benchmarks/pore_water/bottom_row.py [--no-mirror] [--end=T] [--h=H] [--bed=wall|box] [KEY=VALUE ...]

--no-mirror: the walls' and solids' rule alone behind the bed (no mirrored velocity: the version before
mirror.py); --bed=box: the bed an analytic box obstacle instead of the grid's face.
"""

import sys
import time

import numpy as np

from geompm.schemes.saturated.passes import SaturatedPasses
from geompm.testing.verification import bottom_row as br


def table(st):
    x, p = st.p_x, st.p_pore
    xb, yb = np.arange(0.2, 1.61, 0.1), np.arange(0.0, 0.26, 0.05)
    lines = ["bins x from 0.2 m by 0.1 m; rows y [m] from the bed up; mean p [Pa]"]
    for j in range(len(yb) - 2, -1, -1):
        row = []
        for i in range(len(xb) - 1):
            m = (x[:, 0] >= xb[i]) & (x[:, 0] < xb[i + 1]) & (x[:, 1] >= yb[j]) & (x[:, 1] < yb[j + 1])
            row.append(f"{p[m].mean():6.0f}" if m.any() else "     .")
        lines.append(f"y {yb[j]:.2f} " + " ".join(row))
    return "\n".join(lines)


def main(argv):
    if "--no-mirror" in argv:
        SaturatedPasses.mirror = lambda self, view: None
    end = float(next((a.split("=", 1)[1] for a in argv if a.startswith("--end=")), 0.6))
    h = float(next((a.split("=", 1)[1] for a in argv if a.startswith("--h=")), 0.05))
    bed = next((a.split("=", 1)[1] for a in argv if a.startswith("--bed=")), "wall")
    sim = br.simulation(h, [a for a in argv if not a.startswith("--")], bed)
    friction = br.friction_meter(sim)
    t0, due, shown = time.perf_counter(), 0.1, False
    while sim.time < end - 1e-9:
        sim.step(sim.stable_dt())
        if sim.time >= due - 1e-9:
            st = sim.state
            p = st.p_pore
            print(f"t {sim.time:.2f} steps {sim.step_count} centroid {st.p_x[:, 0].mean():.3f} m "
                  f"speed {st.p_v[:, 0].mean():.3f} m/s  p max {p.max():6.0f} min {p.min():7.0f} "
                  f"mean {p.mean():6.0f} Pa"
                  f"  basal friction {friction[0] / 0.1:6.1f} N/m", flush=True)
            friction[0] = 0.0
            if not shown and sim.time >= 0.4 - 1e-9:
                print(table(st), flush=True)
                bottom, above = br.rows(st, h)
                print(f"x 0.5-1.1 m: bottom row (y < h) mean p {bottom:.0f} Pa, the row above {above:.0f} Pa",
                      flush=True)
                shown = True
            due += 0.1
    print(f"wall {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
