"""A 3D elastic block sliding on an inclined DEM (the terrain obstacle) or on the analytic plane of the same
slope (tests/verification/test_terrain.py, benchmarks/terrain_incline_convergence.py,
benchmarks/hazard_map_cost.py)."""

import math

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.dem import write_dem

G = 9.81


def block_case(tmp_path, theta_deg, turn_deg, mu, floor, h: float = 0.05):
    """A 3D elastic block on a 30 deg slope descending along direction (cos turn, sin turn); floor is
    'terrain' (a DEM of the slope, pixel h) or 'plane' (the analytic plane); cells of h [m]."""
    import trimesh

    th, turn = math.radians(theta_deg), math.radians(turn_deg)
    down = np.array([math.cos(turn) * math.cos(th), math.sin(turn) * math.cos(th), -math.sin(th)])  # along slope
    normal = np.array([math.cos(turn) * math.sin(th), math.sin(turn) * math.sin(th), math.cos(th)])
    centre_ground = np.array([0.9, 0.9, 1.2])  # a point on the slope
    tan = math.tan(th)

    def height(x, y):
        return centre_ground[2] - tan * ((x - centre_ground[0]) * math.cos(turn) + (y - centre_ground[1]) * math.sin(turn))

    side = np.cross(normal, down)
    size = np.array([0.3, 0.3, 0.15])  # along the slope, across, normal
    rot = np.eye(4)
    rot[:3, :3] = np.stack([down, side, normal], axis=1)
    block = trimesh.creation.box(extents=size)
    block.apply_transform(rot)
    start = centre_ground - 0.35 * down + (size[2] / 2 + 0.001) * normal  # just above the ground
    block.apply_translation(start)
    block.export(tmp_path / "block.stl")
    case = {
        "name": "dem_incline", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [1.8, 1.8, 2.2], "cell_size": h},
        "time": {"end": 0.5, "cfl": 0.4}, "gravity": [0.0, 0.0, -G],
        "materials": {"block": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1.0e7,
                                "poisson_ratio": 0.2}},
        "bodies": [{"material": "block", "geometry": {"type": "stl", "file": "block.stl"}, "particles_per_cell": 2}],
    }
    if floor == "terrain":
        n = int(round(2.2 / h))
        write_dem(tmp_path / "slope.tif", height, -0.2, -0.2, n, n, h)
        case["obstacles"] = [{"type": "terrain", "name": "ground", "dem": "slope.tif", "condition": "friction",
                              "friction": mu}]
    else:
        case["boundaries"] = [{"type": "plane", "point": list(centre_ground), "normal": list(normal),
                               "condition": "friction", "friction": mu}]
    return case, down, height


def slide(tmp_path, turn, floor, mu=0.3, theta=30.0, end=0.4, h: float = 0.05):
    """(distance slid along the slope [m], the simulation, the lowest gap above the ground [m], the terrain's
    time-averaged normal force once landed [N] or None) of the block released on the slope, at ``end``."""
    case, down, height = block_case(tmp_path, theta, turn, mu, floor, h)
    sim = Simulation(scene_from_dict(case, base_dir=tmp_path))
    st = sim.state
    x_start = st.p_x.copy()
    lowest = np.inf
    fn = []  # the terrain's normal force once the block has landed [N], with each step's dt
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
        gap = st.p_x[:, 2] - height(st.p_x[:, 0], st.p_x[:, 1])
        lowest = min(lowest, float(gap.min()))
        if floor == "terrain" and sim.time > 0.1:
            fn.append((sim.scene.obstacles[0].fn, sim.dt))
    s = float(((st.p_x - x_start) @ down).mean())
    mean_fn = sum(f * dt for f, dt in fn) / sum(dt for _, dt in fn) if fn else None
    return s, sim, lowest, mean_fn
