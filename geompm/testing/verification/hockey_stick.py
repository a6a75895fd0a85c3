"""The hockey stick (tests/verification/test_hockey_stick.py, benchmarks/terrain_hockey_stick.py): a block slides
s0 = 2 m down a 30 deg DEM slope onto flat DEM ground (Coulomb mu = 0.3) and stops where the point-mass
energy balance with the kink's momentum loss puts it (``closed_form``; the derivation is in the test's
docstring and docs/terrain.md)."""

import math
import tempfile
from pathlib import Path

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

G, THETA, MU, S0, KINK = 9.81, math.radians(30.0), 0.3, 2.0, 2.2
#: the block's law: von Mises (DP, phi = 0) that yields under the kink's impact, not under its weight
PLASTIC = {"model": "drucker_prager", "friction_angle": 0.0, "dilation_angle": 0.0, "cohesion": 5000.0}
ELASTIC = {"model": "linear_elastic"}


def closed_form() -> tuple[float, float]:
    """(stopping distance past the kink with the kink's impulsive friction, without it) [m]."""
    v1 = math.sqrt(2 * G * S0 * (math.sin(THETA) - MU * math.cos(THETA)))
    with_impulse = (v1 * (math.cos(THETA) - MU * math.sin(THETA))) ** 2 / (2 * MU * G)
    without = (v1 * math.cos(THETA)) ** 2 / (2 * MU * G)
    return with_impulse, without


def ground(x, y):
    return np.where(x < KINK, math.tan(THETA) * (KINK - x), 0.0) + 0.2


def hockey_stick_case(folder: Path, h: float, size=(0.16, 0.16, 0.08), law=PLASTIC, pixel_ratio=1.0) -> dict:
    """The case in ``folder`` (DEM and block STL written there): a block size[0] along the slope,
    size[1] across and size[2] thick (E = 1 MPa, nu = 0.2, 1000 kg/m3) resting 1 mm above the slope,
    its centre s0 = 2 m up from the kink; DEM pixel h / pixel_ratio."""
    import trimesh

    from geompm.testing.verification.dem import write_dem

    px = h / pixel_ratio
    write_dem(folder / "stick.tif", ground, -0.2, -0.2, int(round(4.4 / px)), int(round(0.8 / px)), px)
    down = np.array([math.cos(THETA), 0.0, -math.sin(THETA)])
    normal = np.array([math.sin(THETA), 0.0, math.cos(THETA)])
    start = np.array([KINK, 0.2, 0.2]) - S0 * down + (size[2] / 2 + 0.001) * normal
    rot = np.eye(4)
    rot[:3, :3] = np.stack([down, np.cross(normal, down), normal], axis=1)
    block = trimesh.creation.box(extents=size)
    block.apply_transform(rot)
    block.apply_translation(start)
    block.export(folder / "block.stl")
    return {
        "name": "hockey_stick", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [4.0, 0.4, 1.6], "cell_size": h},
        "time": {"end": 4.0, "cfl": 0.4}, "gravity": [0.0, 0.0, -G],
        "materials": {"block": dict({"density": 1000.0, "youngs_modulus": 1.0e6, "poisson_ratio": 0.2}, **law)},
        "bodies": [{"material": "block", "geometry": {"type": "stl", "file": "block.stl"}, "particles_per_cell": 2}],
        "obstacles": [{"type": "terrain", "name": "ground", "dem": "stick.tif", "friction": MU}],
    }


def stopping_distance(h: float, **kw) -> tuple[float, int, int, float]:
    """(block centre's final distance past the kink [m], particles, steps, end time [s]); the run ends at
    rest (every particle below 1 mm/s after t = 1 s) or at t = 4 s."""
    folder = Path(tempfile.mkdtemp())
    sim = Simulation(scene_from_dict(hockey_stick_case(folder, h, **kw), base_dir=folder))
    st = sim.state
    while sim.time < 4.0:
        sim.step(min(sim.stable_dt(), 4.0 - sim.time))
        if sim.time > 1.0 and float(np.abs(st.p_v).max()) < 1e-3:
            break
    return float(np.average(st.p_x[:, 0], weights=st.p_mass)) - KINK, st.n, sim.step_count, sim.time
