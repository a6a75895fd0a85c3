"""A law in a saturated element: every registered law that is not a fluid runs with pore water, unchanged
(docs/pore-water.md).

``check_saturated(name)`` loads a small sealed column of the law (``example_params()``, porosity 0.3,
k = 1e-9 m/s so that no water leaves in the run, water of K_w = 2.2e9 Pa) by q on its top over 2 ms
through the engine, with local damping, for 30 ms, and checks:

- the run stays finite and the law's state keeps its shape;
- the mixture carries the load: the interior's total vertical stress sigma'_yy - p = -q within 2 %;
- the water carries its undrained share: p / q within 2 % of 1 / (1 + n M / K_w), the oedometric Skempton
  ratio, with M = c^2 rho_d the law's own constrained modulus (its wave speed at the dry density); a law
  that yields under the effective-stress increment carries less in its skeleton, so p / q then lies
  between that ratio and 1.
"""

from __future__ import annotations

import numpy as np

from geompm.api import scene_from_dict
from geompm.backend.cpu_loops import law_wave_speed
from geompm.contract import registry
from geompm.engine.scheduler import Simulation

H, W, CELL, N0, K_W = 0.2, 0.1, 0.05, 0.3, 2.2e9


def saturated_element(name: str) -> dict:
    """The sealed column of law ``name`` (a geompm.materials entry point) after 30 ms: interior p / q, total
    stress / q, the closed-form ratio and the run's state."""
    law = registry.get("materials", name)
    params = law.example_params().model_dump()
    params.update(model=name, pore_water={"porosity": N0, "hydraulic_conductivity": 1e-9,
                                          "fluid": {"bulk_modulus": K_W}})
    probe = law(law.example_params())
    rho_d = (1 - N0) * probe.density
    probe_dry = law(law.example_params().model_copy(update={"density": rho_d}))
    modulus = law_wave_speed(probe_dry, np.array([rho_d])) ** 2 * rho_d
    q = 1e-3 * modulus
    case = {"name": "saturated_element", "dimension": 2,
            "grid": {"origin": [0, 0], "extent": [W, H + 2 * CELL], "cell_size": CELL, "shape_function": "linear"},
            "time": {"end": 0.03}, "gravity": [0.0, 0.0], "solver": {"transfer": "flip"},
            "materials": {"soil": params},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0], "max": [W, H]},
                        "particles_per_cell": 2}],
            "boundaries": [{"type": "wall", "side": s, "condition": "slip"} for s in ("y-", "x-", "x+")]
            + [{"type": "surface_load", "region": {"min": [0, H / 2], "max": [W, H]}, "normal": [0, 1],
                "pressure": q, "ramp_time": 0.002}],
            "damping": [{"model": "local", "alpha": 0.3}]}
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    while sim.time < 0.03 - 1e-12:
        sim.step(min(sim.stable_dt(), 0.03 - sim.time))
    inner = (st.p_x0[:, 1] > CELL) & (st.p_x0[:, 1] < H - CELL)
    p = float(st.p_pore[inner].mean())
    total = float((st.p_stress[inner, 1] - st.p_pore[inner]).mean())
    return {"law": name, "p_over_q": p / q, "total_over_q": -total / q,
            "skempton": 1.0 / (1.0 + N0 * modulus / K_W), "finite": bool(np.isfinite(st.p_stress).all()
                                                                        and np.isfinite(st.p_pore).all()),
            "state_shapes": [sv.shape for sv in st.p_state], "state_vars": len(law.state_vars)}


def check_saturated(name: str) -> None:
    r = saturated_element(name)
    assert r["finite"], f"{name}: non-finite stress or pore pressure in a saturated element: {r}"
    assert all(s[1] == r["state_vars"] for s in r["state_shapes"]), f"{name}: state shape changed: {r}"
    assert abs(r["total_over_q"] - 1.0) < 0.02, f"{name}: the saturated element does not carry its load: {r}"
    assert r["skempton"] * 0.98 < r["p_over_q"] < 1.02, f"{name}: the water's share is off: {r}"
