"""A saturated linear-elastic block (1.2 x 0.25 m, rho_s = 2700 kg/m3, E = 5 MPa, n = 0.4, k = 1e-5 m/s,
K_w = 2e7 Pa: the wet-bed case's debris made elastic) on a fixed base, geostatic with the table at its top and
parallel to the base, in a frame turned by BETA degrees (gravity tilted), with free ends ('free'), or filling
the grid between slip end walls ('walls'), PIC, quadratic B-splines, h = 0.04 m: the mean pore pressure of
all particles, of the bottom row and of its middle 0.4 m, the middle's effective and total normal stress,
every few steps to 0.3 s (docs/validation/wet-bed-entrainment.md, Why the debris stalls).

    python benchmarks/pore_water/finite_block.py BETA free|walls [K_W]

Raw output: benchmarks/results/2026-12-05-issue52/finite_block.txt.
"""
import json
import math
import sys

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

H_CELL, LENGTH, HEIGHT = 0.04, 1.2, 0.25


def block_case(beta: float, ends: str, kw: float = 2e7) -> dict:
    b = math.radians(beta)
    soil = {"model": "linear_elastic", "density": 2700.0, "youngs_modulus": 5e6, "poisson_ratio": 0.3,
            "pore_water": {"porosity": 0.4, "hydraulic_conductivity": 1e-5, "fluid": {"bulk_modulus": kw}}}
    lo, hi = (0.4, 0.4 + LENGTH) if ends == "free" else (0.0, 2.0)
    case = {"name": "finite_block", "dimension": 2,
            "grid": {"origin": [0, 0], "extent": [2.0, 0.5], "cell_size": H_CELL, "shape_function": "quadratic"},
            "time": {"end": 1.0, "cfl": 0.2}, "gravity": [9.81 * math.sin(b), -9.81 * math.cos(b)],
            "solver": {"transfer": "pic"}, "materials": {"soil": soil},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [lo, 0.0], "max": [hi, HEIGHT]},
                        "particles_per_cell": 2, "pore_pressure": {"table_normal": [0.0, 1.0]},
                        "initial_stress": "geostatic", "surface_normal": [0.0, 1.0]}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"}]}
    if ends == "walls":
        case["boundaries"] += [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "x+")]
    return case


def row(sim) -> dict:
    st = sim.state
    bottom = st.p_x0[:, 1] < H_CELL / 2
    middle = bottom & (np.abs(st.p_x0[:, 0] - st.p_x0[:, 0].mean()) < 0.2)
    total = st.p_stress[:, 1] - st.p_pore
    return {"t": round(sim.time, 3), "p_all": float(st.p_pore.mean()), "p_bottom": float(st.p_pore[bottom].mean()),
            "p_middle": float(st.p_pore[middle].mean()), "effective_middle": float(st.p_stress[middle, 1].mean()),
            "total_middle": float(total[middle].mean())}


def main() -> None:
    beta, ends = float(sys.argv[1]), sys.argv[2]
    sim = Simulation(scene_from_dict(block_case(beta, ends, float(sys.argv[3]) if len(sys.argv) > 3 else 2e7)))
    for t in (0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3):
        while sim.time < t - 1e-12:
            sim.step(min(sim.stable_dt(), t - sim.time))
        print(json.dumps({"beta": beta, "ends": ends, **row(sim)}), flush=True)


if __name__ == "__main__":
    main()
