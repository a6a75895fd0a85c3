"""The bottom row of a saturated flow on a bed aligned with the grid (docs/pore-water.md, Walls and the bottom
row; schemes/saturated/mirror.py; tests/verification/test_wall_mirror.py, benchmarks/pore_water/bottom_row.py).

The 2D twin of the main job (cases/saturated_debris_obstacle.json's debris: Drucker-Prager phi = 30, psi = 0,
n = 0.4, k = 1e-5 m/s, K_w = 2e7 Pa; APIC, quadratic B-splines): a 0.6 x 0.25 m block on a 35 degree slope
written as a horizontal bed (wall y-, friction 0.4) under gravity turned by 35 degrees, so the wall lies on
grid nodes and no oblique cut is involved.
"""

from __future__ import annotations

import json
import math

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.schema.load import apply_overrides
from geompm.testing.verification.cases import CASES, shipped_case

SLOPE = math.radians(35.0)
#: the basal Coulomb coefficient and the block [m]: x from 0.2 to 0.8, y from 0 to 0.25
MU, X0, X1, HEIGHT = 0.4, 0.2, 0.8, 0.25


def case(h: float = 0.05, sets=(), bed: str = "wall") -> dict:
    """The case; ``bed``: "wall" (the grid's face y-) or "box" (an analytic box obstacle whose top is the same
    plane, y = 0, the grid reaching 0.2 m below it: a rigid solid's fill and mirror instead of a wall's)."""
    c = json.loads(shipped_case("saturated_debris_obstacle.json").read_text())
    c["dimension"] = 2
    below = 0.2 if bed == "box" else 0.0
    c["grid"] = {"origin": [0, -below], "extent": [4.0, 0.8 + below], "cell_size": h, "shape_function": "quadratic"}
    c["gravity"] = [9.81 * math.sin(SLOPE), -9.81 * math.cos(SLOPE)]
    c["boundaries"] = [{"type": "wall", "side": "x-", "condition": "slip"},
                       {"type": "wall", "side": "x+", "condition": "slip"}]
    if bed == "box":
        c["obstacles"] = [{"type": "box", "name": "bed", "min": [-0.1, -0.3], "max": [4.1, 0.0],
                           "condition": "friction", "friction": MU}]
    else:
        c["boundaries"].insert(0, {"type": "wall", "side": "y-", "condition": "friction", "friction": MU})
        c.pop("obstacles")
    c["outputs"] = []
    c["time"]["cfl"] = 0.4
    body = c["bodies"][0]
    body["geometry"] = {"type": "polygon", "vertices": [[X0, 0.0], [X1, 0.0], [X1, HEIGHT], [X0, HEIGHT]]}
    return apply_overrides(c, list(sets))


def simulation(h: float = 0.05, sets=(), bed: str = "wall") -> Simulation:
    return Simulation(scene_from_dict(case(h, sets, bed), base_dir=CASES))


def rows(st, h: float, x_lo: float = 0.5, x_hi: float = 1.1) -> tuple[float, float]:
    """The particles' mean pore pressure [Pa] in the bottom row (y < h) and the row above (h <= y < 2 h),
    over x_lo <= x < x_hi."""
    x, p = st.p_x, st.p_pore
    band = (x[:, 0] >= x_lo) & (x[:, 0] < x_hi)
    bottom = band & (x[:, 1] < h)
    above = band & (x[:, 1] >= h) & (x[:, 1] < 2 * h)
    return float(p[bottom].mean()), float(p[above].mean())


def weight_normal(c: dict | None = None) -> float:
    """The block's weight normal to the bed per metre of width [N/m], from the case's grain density, porosity
    and water density: the total-stress friction bound / MU."""
    debris = (c or case())["materials"]["debris"]
    pw = debris["pore_water"]
    n, rho_w = pw["porosity"], pw.get("fluid", {}).get("density", 1000.0)
    rho_sat = (1.0 - n) * debris["density"] + n * rho_w
    return rho_sat * (X1 - X0) * HEIGHT * 9.81 * math.cos(SLOPE)


def friction_meter(sim: Simulation) -> list:
    """Wraps the simulation's grid stages so that the x-momentum they remove is summed into the returned
    one-element list [N s/m]: the bed's friction impulse (the end walls take none before the front reaches them)."""
    acc = [0.0]
    run = sim.grid_stages_run

    def measured(view, dt, remap=False, phases=None):
        before = float(np.dot(view.g_mass, view.g_vel[:, 0]))
        run(view, dt, remap=remap, phases=phases)
        acc[0] -= float(np.dot(view.g_mass, view.g_vel[:, 0])) - before

    sim.grid_stages_run = measured
    return acc
