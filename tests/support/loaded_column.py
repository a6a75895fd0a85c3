"""A laterally confined elastic column under a surface load (boundaries/surface_load.py), weightless, brought
to rest by Cundall's local damping: the case and its closed form (tests/verification/test_surface_load.py,
benchmarks/surface_load/column.py)."""

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

E, NU, RHO = 10e6, 0.3, 2000.0  # [Pa], [-], [kg/m3]
Q, H, W = 10e3, 1.0, 0.2  # pressure [Pa], column height and width [m]
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))  # oedometric (constrained) modulus [Pa]
END = 0.3  # [s]: about 25 P-wave transits of the column (c = sqrt(M / rho) = 82 m/s)


def column_case(h: float, ramp: float = 0.05, alpha: float = 0.3) -> dict:
    return {"name": "loaded_column", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [W, H + 2 * h], "cell_size": h},
            "time": {"end": END, "cfl": 0.4}, "gravity": [0.0, 0.0],
            "materials": {"soil": {"model": "linear_elastic", "density": RHO, "youngs_modulus": E,
                                   "poisson_ratio": NU}},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [W, H]},
                        "particles_per_cell": 2}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"},
                           {"type": "wall", "side": "x-", "condition": "slip"},
                           {"type": "wall", "side": "x+", "condition": "slip"},
                           {"type": "surface_load", "name": "footing",
                            "region": {"min": [0.0, H - h / 2], "max": [W, H]}, "normal": [0.0, 1.0],
                            "pressure": Q, "ramp_time": ramp}],
            "damping": [{"model": "local", "alpha": alpha}],
            "outputs": []}


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
