"""Terzaghi's column loaded undrained, pushed and pulled: does the saturated column hold suction as it holds
compression?  Measured: it does not, and the cause is the boundary, not the two-phase step.  The side walls
are ``slip`` walls, one-sided contacts: pulled, the column's total lateral stress turns to tension and it
leaves them (in the column started in its undrained state at -9.6 kPa, by 2.9 um a side within 1 ms, 13x the
undrained volumetric strain), which relieves the water.  Pushed, it presses on them and holds.

    python benchmarks/pore_water/undrained_pull.py > benchmarks/results/<date>-undrained-pull.txt

The column of cases/terzaghi_consolidation.json at cell size h, from rest (no initial stress, p = 0), with
k = 1e-9 m/s (no water moves in the 40 ms run), its base wall ``fixed`` (a ``slip`` wall is one-sided: a
pulled column lifts off it), its surface load ramped over 2 ms to +q (push) or -q (pull), local damping 0.3.
Undrained and oedometric, the interior's pore pressure is p = B q, B = 1 / (1 + n M / K_w), in either
direction.  One JSON line per run: the interior's mean and extreme pore pressure, the theory's, the total
stress's error against the load, the drained particles and the porosity's range.
"""

import copy
import json

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.saturated_columns import run_to, terzaghi_case, terzaghi_constants


def loaded_column(h: float, q: float) -> dict:
    """The column at h pushed by q > 0 or pulled by q < 0 [Pa] (module docstring)."""
    case = copy.deepcopy(terzaghi_case(h))
    case["bodies"][0].pop("stress_offset")
    case["bodies"][0].pop("pore_pressure")
    case["materials"]["soil"]["pore_water"]["hydraulic_conductivity"] = 1e-9
    case["boundaries"][0]["condition"] = "fixed"
    case["boundaries"][-1]["pressure"] = q
    case["boundaries"][-1]["ramp_time"] = 0.002
    case["damping"] = [{"model": "local", "alpha": 0.3}]
    c = terzaghi_constants(case)
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    run_to(sim, 0.04)
    inner = (st.p_x0[:, 1] > 2 * h) & (st.p_x0[:, 1] < c["H"] - 2 * h)
    p, s = float(st.p_pore[inner].mean()), float(st.p_stress[inner, 1].mean())
    return {"h": h, "q": q, "p_mean": p, "p_min": float(st.p_pore[inner].min()),
            "p_max": float(st.p_pore[inner].max()), "p_undrained": q / (1 + c["n"] * c["M"] / c["Kw"]),
            "total_error": (s - p) / -q - 1, "drained": int(st.p_drained.sum()), "particles": st.n,
            "porosity": [float(st.p_n.min()), float(st.p_n.max())], "largest_speed": float(np.abs(st.p_v).max()),
            "steps": sim.step_count}


def main():
    for h in (0.1, 0.05, 0.025):
        for q in (50e3, -50e3):
            print(json.dumps(loaded_column(h, q)), flush=True)
    print(json.dumps(loaded_column(0.1, -300e3)), flush=True)


if __name__ == "__main__":
    main()
