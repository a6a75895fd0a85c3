"""A laterally confined elastic column under a surface load (boundaries/surface_load.py), weightless, brought
to rest by Cundall's local damping: cases/loaded_column.json at any cell size, and its closed form
(tests/verification/test_surface_load.py, benchmarks/surface_load/column.py)."""

import copy
import json

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

from geompm.testing.verification.cases import shipped_case

CASE = shipped_case("loaded_column.json")
_RAW = json.loads(CASE.read_text())
_SOIL = _RAW["materials"]["soil"]
E, NU, RHO = _SOIL["youngs_modulus"], _SOIL["poisson_ratio"], _SOIL["density"]  # [Pa], [-], [kg/m3]
Q = _RAW["boundaries"][3]["pressure"]  # [Pa]
H, W = _RAW["bodies"][0]["geometry"]["max"][1], _RAW["bodies"][0]["geometry"]["max"][0]  # column height, width [m]
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))  # oedometric (constrained) modulus [Pa]
END = _RAW["time"]["end"]  # [s]: about 25 P-wave transits of the column (c = sqrt(M / rho) = 82 m/s)


def column_case(h: float, ramp: float | None = None) -> dict:
    """cases/loaded_column.json at cell size h, without output writers (``ramp``: another ramp time)."""
    case = copy.deepcopy(_RAW)
    case["grid"]["cell_size"] = h
    case["outputs"] = []
    if ramp is not None:
        case["boundaries"][3]["ramp_time"] = ramp
    return case


def run_column(h: float) -> dict:
    """Errors of the loaded column at rest, relative to the closed form: settlement of the top row
    (q H / M, at its initial height H - h/4: q (H - h/4) / M), the largest error of the displacement
    profile u_y(y0) = -q y0 / M over all particles (relative to q H / M), and the vertical stress of the
    middle rows (-q)."""
    scene = scene_from_dict(column_case(h))
    sim = Simulation(scene)
    st = scene.state
    while sim.time < END - 1e-12:
        sim.step(min(sim.stable_dt(), END - sim.time))
    uy = st.p_x[:, 1] - st.p_x0[:, 1]
    top = st.p_x0[:, 1] > H - h / 4 - 1e-9
    y_top = H - h / 4
    mid = np.abs(st.p_x0[:, 1] - H / 2) < h / 2
    return {"h": h, "steps": sim.step_count,
            "settlement": float(-uy[top].mean()), "settlement_exact": Q * y_top / M,
            "settlement_error": float(-uy[top].mean() / (Q * y_top / M) - 1),
            "profile_error": float(np.abs(uy + Q * st.p_x0[:, 1] / M).max() / (Q * H / M)),
            "stress_error": float(-st.p_stress[mid, 1].mean() / Q - 1),
            "largest_speed": float(np.abs(st.p_v).max())}
