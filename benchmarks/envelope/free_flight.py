"""A linear-elastic block in free flight (no gravity, no wall) at 3 m/s for 1 s: its kinetic energy must stay
as it is.  Each shape function and transfer, dry and saturated (n = 0.4, k = 1e-8 m/s, K_w = 2.2e7 Pa); a
blow-up is recorded with the step it stopped at and its message.

    python benchmarks/envelope/free_flight.py [OUT.json]

Raw output: benchmarks/results/2026-12-05-issue52/free_flight.json (before saturated linear APIC was refused)
and free_flight_refused.json (after).
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.free_flight import block_case

COMBINATIONS = [("linear", "apic"), ("linear", "flip"), ("linear", "pic"), ("quadratic", "apic"),
                ("quadratic", "flip"), ("quadratic", "mls"), ("cubic", "apic")]


def run(shape: str, transfer: str, saturated: bool) -> dict:
    out = {"shape": shape, "transfer": transfer, "saturated": saturated}
    t0 = time.perf_counter()
    try:
        sim = Simulation(scene_from_dict(block_case(shape, transfer, saturated)))
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
