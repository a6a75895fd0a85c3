"""A linear-elastic block in free flight (no gravity, no wall) at 3 m/s for 1 s: its kinetic energy must stay
as it is.  Each shape function and transfer, dry and saturated (n = 0.4, k = 1e-8 m/s, K_w = 2.2e7 Pa); a
blow-up is recorded with the step it stopped at and its message.

    python benchmarks/envelope/free_flight.py [OUT.json]

Raw output: benchmarks/results/2026-12-05-issue52/free_flight.json.
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

COMBINATIONS = [("linear", "apic"), ("linear", "flip"), ("linear", "pic"), ("quadratic", "apic"),
                ("quadratic", "flip"), ("cubic", "apic")]


def block(shape: str, transfer: str, saturated: bool) -> dict:
    soil = {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 10e6, "poisson_ratio": 0.3}
    if saturated:
        soil["pore_water"] = {"porosity": 0.4, "hydraulic_conductivity": 1e-8, "fluid": {"bulk_modulus": 2.2e7}}
    return {"name": "free_flight", "dimension": 2,
            "grid": {"origin": [0, 0], "extent": [5, 1], "cell_size": 0.05, "shape_function": shape},
            "time": {"end": 1.0}, "gravity": [0, 0], "materials": {"soil": soil},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.2, 0.3], "max": [0.6, 0.7]},
                        "velocity": [3, 0], "particles_per_cell": 2}],
            "solver": {"transfer": transfer}}


def run(shape: str, transfer: str, saturated: bool) -> dict:
    out = {"shape": shape, "transfer": transfer, "saturated": saturated}
    t0 = time.perf_counter()
    try:
        sim = Simulation(scene_from_dict(block(shape, transfer, saturated)))
    except Exception as exc:  # refused before any work
        out["refused"] = str(exc)[:300]
        return out
    st = sim.state
    ke0 = 0.5 * float((st.p_mass * (st.p_v ** 2).sum(1)).sum())
    try:
        while sim.time < 1.0 - 1e-12:
            sim.step(min(sim.stable_dt(), 1.0 - sim.time))
        out["ke_ratio"] = 0.5 * float((st.p_mass * (st.p_v ** 2).sum(1)).sum()) / ke0
    except Exception as exc:
        out["blew_up_at_step"] = sim.step_count
        out["time"] = sim.time
        out["error"] = f"{type(exc).__name__}: {exc}"[:300]
    out["steps"] = sim.step_count
    out["max_abs_C"] = float(np.abs(st.p_C).max()) if np.isfinite(st.p_C).all() else float("inf")
    out["seconds"] = round(time.perf_counter() - t0, 1)
    return out


def main() -> None:
    rows = []
    for saturated in (False, True):
        for shape, transfer in COMBINATIONS:
            r = run(shape, transfer, saturated)
            print(json.dumps(r), flush=True)
            rows.append(r)
    with open(sys.argv[1] if len(sys.argv) > 1 else "free_flight.json", "w") as f:
        json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
