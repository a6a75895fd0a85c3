"""Hockey stick: a block sliding down a 30 deg DEM slope onto flat DEM ground, against the point-mass closed form.

    python benchmarks/terrain_hockey_stick.py [0.05 0.025 0.0125] [--size 0.16 0.16 0.08] [--pixel-ratio 1]

Closed form (a point mass with Coulomb friction mu everywhere, starting from rest a distance s0 up the
slope from the kink):  v1^2 = 2 g s0 (sin theta - mu cos theta) at the kink; the kink removes the
velocity normal to the flat, v1 sin theta, and with it (Coulomb on the impulse) mu v1 sin theta of the
tangential one, so v2 = v1 (cos theta - mu sin theta); it stops d = v2^2 / (2 mu g) past the kink.
Without the impulsive friction v2 = v1 cos theta.  Prints the block centre's stopping distance past
the kink at each cell size (DEM pixel = cell size) against both.
"""

import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_dict  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402
from tests.test_terrain import write_dem  # noqa: E402

G, THETA, MU, S0, KINK = 9.81, math.radians(30.0), 0.3, 2.0, 2.2
SIZE = [0.16, 0.16, 0.08]  # block along the slope, across, normal [m] (--size)
PIXEL = [1.0]  # cell size / DEM pixel (--pixel-ratio)


def closed_form():
    v1 = math.sqrt(2 * G * S0 * (math.sin(THETA) - MU * math.cos(THETA)))
    with_impulse = (v1 * (math.cos(THETA) - MU * math.sin(THETA))) ** 2 / (2 * MU * G)
    without = (v1 * math.cos(THETA)) ** 2 / (2 * MU * G)
    return with_impulse, without


def ground(x, y):
    return np.where(x < KINK, math.tan(THETA) * (KINK - x), 0.0) + 0.2


def run(h):
    import trimesh

    tmp = Path(tempfile.mkdtemp())
    px = h / PIXEL[0]
    write_dem(tmp / "stick.tif", ground, -0.2, -0.2, int(round(4.4 / px)), int(round(0.8 / px)), px)
    down = np.array([math.cos(THETA), 0.0, -math.sin(THETA)])
    normal = np.array([math.sin(THETA), 0.0, math.cos(THETA)])
    start = np.array([KINK, 0.2, 0.2]) - S0 * down + (SIZE[2] / 2 + 0.001) * normal
    rot = np.eye(4)
    rot[:3, :3] = np.stack([down, np.cross(normal, down), normal], axis=1)
    block = trimesh.creation.box(extents=SIZE)
    block.apply_transform(rot)
    block.apply_translation(start)
    block.export(tmp / "block.stl")
    case = {
        "name": "hockey_stick", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [4.0, 0.4, 1.6], "cell_size": h},
        "time": {"end": 4.0, "cfl": 0.4}, "gravity": [0.0, 0.0, -G],
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e6,
                                "poisson_ratio": 0.2}},
        "bodies": [{"material": "block", "geometry": {"type": "stl", "file": "block.stl"}, "particles_per_cell": 2}],
        "obstacles": [{"type": "terrain", "name": "ground", "dem": "stick.tif", "friction": MU}],
    }
    sim = Simulation(scene_from_dict(case, base_dir=tmp))
    st = sim.state
    t0 = time.perf_counter()
    while sim.time < 4.0:
        sim.step(min(sim.stable_dt(), 4.0 - sim.time))
        if sim.time > 1.0 and float(np.abs(st.p_v).max()) < 1e-3:
            break
    centre = float(np.average(st.p_x[:, 0], weights=st.p_mass))
    return centre - KINK, st.n, sim.step_count, time.perf_counter() - t0, sim.time


def main():
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("cell_sizes", nargs="*", type=float, default=[0.05, 0.025, 0.0125])
    ap.add_argument("--size", nargs=3, type=float, default=SIZE)
    ap.add_argument("--pixel-ratio", type=float, default=1.0)
    a = ap.parse_args()
    SIZE[:] = a.size
    PIXEL[0] = a.pixel_ratio
    sizes = a.cell_sizes
    print(f"block {SIZE} m, DEM pixel = h / {PIXEL[0]:g}")
    d_imp, d_free = closed_form()
    print(f"closed form: stops {d_imp:.4f} m past the kink (impulsive friction), {d_free:.4f} m without")
    for h in sizes:
        d, n, steps, wall, t = run(h)
        print(f"h = {h:g} m: {n} particles, {steps} steps to t = {t:.3g} s, {wall:.1f} s: stops {d:.4f} m past the "
              f"kink ({100 * (d / d_imp - 1):+.1f} % against the impulsive-friction form, "
              f"{100 * (d / d_free - 1):+.1f} % against the frictionless kink)", flush=True)


if __name__ == "__main__":
    main()
