"""The wet-bed entrainment case (cases/wet_bed_entrainment.json; docs/validation/wet-bed-entrainment.md):
the same saturated debris released over a saturated bed and over a dry one, and what the flow gains or
loses (benchmarks/pore_water/wet_bed.py, tests/validation/test_wet_bed_entrainment.py).

The case is in the flume's frame (x down the 31 degree slope, y normal to the bed), so momentum and
positions are along the slope.  Measured every ``every`` seconds: the momentum of everything along the
slope, sum m v_x [kg m/s per metre of width], the debris's front (its largest x), and the entrained bed
mass, the bed particles moved more than ENTRAINED m down the slope [kg/m].
"""

from __future__ import annotations

import copy
import json

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
from geompm.testing.verification.cases import shipped_case

#: a bed particle moved farther than this down the slope [m] is entrained
ENTRAINED = 0.05
CASE = json.loads(shipped_case("wet_bed_entrainment.json").read_text())


def bed_case(h: float, bed: str, end: float, cfl: float = 0.2) -> dict:
    """The shipped case at cell size h with the bed 'wet' (as shipped) or 'dry' (the same grains without
    pore water: the dry density (1 - n) rho_s), to ``end``, without writers."""
    case = copy.deepcopy(CASE)
    case["grid"]["cell_size"] = h
    case["time"].update(end=end, cfl=cfl)
    case["outputs"] = []
    if bed == "dry":
        soil = case["materials"]["bed"]
        pw = soil.pop("pore_water")
        soil["density"] = (1.0 - pw["porosity"]) * soil["density"]
        case["bodies"][1].pop("pore_pressure", None)
    return case


def run(h: float, bed: str, end: float = 1.5, every: float = 0.05, cfl: float = 0.2) -> dict:
    """The history of ``bed_case`` (module docstring) and its summary: peak momentum and its time, the
    front at the end (the runout along the slope), the front's largest speed, the entrained mass."""
    sim = Simulation(scene_from_dict(bed_case(h, bed, end, cfl), base_dir=shipped_case("wet_bed_entrainment.json").parent))
    st = sim.state
    rows = []
    nxt = 0.0
    while True:
        if sim.time >= nxt - 1e-12:
            isbed = st.p_body == 1
            moved = isbed & (st.p_x[:, 0] - st.p_x0[:, 0] > ENTRAINED)
            rows.append({"t": round(sim.time, 4), "momentum": float((st.p_mass * st.p_v[:, 0]).sum()),
                         "front": float(st.p_x[~isbed, 0].max()), "entrained": float(st.p_mass[moved].sum())})
            nxt += every
        if sim.time >= end - 1e-12:
            break
        sim.step(min(sim.stable_dt(), end - sim.time))
    mom = np.array([r["momentum"] for r in rows])
    front = np.array([r["front"] for r in rows])
    t = np.array([r["t"] for r in rows])
    k = int(mom.argmax())
    return {"h": h, "bed": bed, "steps": sim.step_count, "peak_momentum": float(mom[k]), "peak_time": float(t[k]),
            "runout": float(front[-1]), "advance": float(front[-1] - front[0]),
            "front_speed_max": float(np.max(np.diff(front) / np.diff(t))), "entrained": rows[-1]["entrained"],
            "history": rows}
