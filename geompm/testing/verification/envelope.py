"""Run a small scene step by step and record what stability means here.

A run is stable when, at every step: no position, velocity or stress is NaN
or Inf; the kinetic energy stays below what the run can supply,
E_k(t) <= E_k(0) + U_0 + max(W_g(t), 0) (engine/health.py: U_0 the strain
energy of the initial stress, W_g the work done by gravity) within a 5%
allowance for the O(dt) energy error of an explicit stable scheme; and every
particle stays inside the grid (to 5% of a cell: contact lets a particle
sink microns behind a wall).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np

from geompm.api import scene_from_dict
from geompm.schema.load import apply_overrides
from geompm.engine.health import HealthCheck, health_sums, outside_grid
from geompm.engine.scheduler import Simulation

ALLOWANCE = 1.05


@dataclass
class Outcome:
    steps: int
    dt_first: float
    dt_min: float
    energy_ratio: float  # max over steps of E_k / (E_k0 + U_0 + max(W_g, 0))
    finite: bool
    inside: bool
    kinetic_energy: float
    front_x: float
    time: float
    rho_max: float = 0.0  # largest particle density over the run [kg/m3]

    @property
    def stable(self) -> bool:
        return self.finite and self.inside and self.energy_ratio <= ALLOWANCE


def column(**over) -> dict:
    """A 0.2 m x 0.1 m soil column (DP, source sec. 3.2 soil) on a rough floor, h = 0.02 m, 2x2 per cell."""
    case = {
        "name": "stability_column", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [0.6, 0.2], "cell_size": 0.02},
        "time": {"end": 0.3, "cfl": 0.4},
        "gravity": [0.0, -9.81],
        "materials": {"soil": {"model": "drucker_prager", "density": 2650.0, "youngs_modulus": 0.84e6,
                               "poisson_ratio": 0.3, "friction_angle": 31.0, "cohesion": 0.0}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [0.2, 0.1]},
                    "particles_per_cell": 2, "initial_stress": "geostatic"}],
        "boundaries": [{"type": "wall", "side": "x-", "condition": "slip"},
                       {"type": "wall", "side": "x+", "condition": "slip"},
                       {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.6}],
        "outputs": [],
    }
    return merge(case, over)


def merge(case: dict, over: dict) -> dict:
    """A copy of ``case`` with the dotted keys of ``over`` replaced (as ``--set`` does)."""
    return apply_overrides(case, [f"{k}={json.dumps(v)}" for k, v in over.items()])


def run(case: dict, max_steps: int = 20000, cfl: float | None = None) -> Outcome:
    """Step the case to its end time (or ``max_steps``) and check stability after every step.

    ``cfl`` replaces the case's Courant number after validation (to show what the limit prevents)."""
    scene = scene_from_dict(case)
    if cfl is not None:
        scene.cfl = cfl
    sim = Simulation(scene)
    check = HealthCheck(scene)
    st = sim.state
    budget = check.budget0
    slack = 0.05 * scene.grid.h
    lo, hi = scene.grid.origin - slack, scene.grid.upper + slack
    ratio, finite, inside, rho_max = 0.0, True, True, 0.0
    dt_first = dt_min = sim.stable_dt()
    while sim.time < scene.end_time * (1 - 1e-12) and sim.step_count < max_steps:
        dt = min(sim.stable_dt(), scene.end_time - sim.time)
        if not math.isfinite(dt):  # a NaN step would end the loop as if the run had finished
            finite = False
            break
        dt_min = min(dt_min, dt)
        sim.step(dt)
        bad, ek, wg = health_sums(st.p_x, st.p_x0, st.p_v, st.p_stress, st.p_mass, scene.gravity)
        if bad:
            finite = False
            break
        ratio = max(ratio, ek / (budget + max(wg, 0.0) + 1e-30))
        rho_max = max(rho_max, float(st.p_rho.max()))
        if outside_grid(st.p_x, lo, hi).any():
            inside = False
            break
    return Outcome(sim.step_count, dt_first, dt_min, ratio, finite, inside, float(ek) if finite else np.nan,
                   float(st.p_x[:, 0].max()), sim.time, rho_max)


#: the envelope's scenes: (label, overrides of ``column()``), each run by tests/envelope/test_envelope.py
ELASTIC_DROP = {  # an elastic block dropped 4 cm onto the floor: it bounces, and nothing dissipates energy
    "materials.soil": {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": 1e6, "poisson_ratio": 0.3},
    "bodies.0.initial_stress": "none", "bodies.0.geometry": {"type": "box", "min": [0.2, 0.04], "max": [0.4, 0.14]},
    "time.end": 1.0}
WATER = {"materials.soil": {"model": "newtonian", "density": 1000.0, "viscosity": 1e-6, "sound_speed": 20.0},
         "bodies.0.initial_stress": "none"}
IMPACT = {"bodies.0.velocity": [50.0, 0.0], "bodies.0.initial_stress": "none",
          "bodies.0.geometry": {"type": "box", "min": [0.2, 0.0], "max": [0.3, 0.1]},
          "time.end": 0.03, "grid.extent": [0.6, 1.0]}  # the elastic rebound splashes up to ~0.7 m by 0.03 s

SOIL = [  # (label, overrides): end times keep each run to a few thousand steps
    ("E = 1e3 Pa", {"materials.soil.youngs_modulus": 1e3}),
    ("E = 1e5 Pa", {"materials.soil.youngs_modulus": 1e5}),
    ("E = 1e8 Pa", {"materials.soil.youngs_modulus": 1e8, "time.end": 0.05}),
    ("E = 1e10 Pa", {"materials.soil.youngs_modulus": 1e10, "time.end": 0.005}),
    ("nu = 0", {"materials.soil.poisson_ratio": 0.0}),
    ("nu = 0.45", {"materials.soil.poisson_ratio": 0.45}),
    ("nu = 0.499", {"materials.soil.poisson_ratio": 0.499, "time.end": 0.1}),
    ("phi = 0", {"materials.soil.friction_angle": 0.0}),
    ("phi = 15", {"materials.soil.friction_angle": 15.0}),
    ("phi = 45", {"materials.soil.friction_angle": 45.0}),
    ("phi = 60", {"materials.soil.friction_angle": 60.0}),
    ("c = 1 MPa", {"materials.soil.cohesion": 1e6}),
    ("1 particle per cell", {"bodies.0.particles_per_cell": 1}),
    ("4x4 particles per cell", {"bodies.0.particles_per_cell": 4}),
    ("cfl = 0.1", {"time.cfl": 0.1, "time.end": 0.1}),
    ("cfl = 0.8", {"time.cfl": 0.8}),
    ("water, mu = 1e-6 Pa s", WATER),
    ("water, mu = 1e-6 Pa s, cfl = 0.6", {**WATER, "time.cfl": 0.6}),
    ("elastic drop, cfl = 0.8, 1 s", {**ELASTIC_DROP, "time.cfl": 0.8}),
    ("elastic drop, nu = 0.499", {**ELASTIC_DROP, "materials.soil.poisson_ratio": 0.499, "time.end": 0.2}),
    ("impact at 50 m/s", IMPACT),
    ("impact at 50 m/s, cfl = 0.8", {**IMPACT, "time.cfl": 0.8}),
    ("Cross, mu_0 = 1e4 mu_inf", {"materials.soil": {"model": "cross", "density": 2650.0, "sound_speed": 20.0,
                                                    "from_bingham": {"viscosity": 1.2, "yield_stress": 200.0}},
                                  "bodies.0.initial_stress": "none", "time.end": 0.01}),
]


def evp(model: str, **law) -> dict:
    """The column as a yield-stress fluid (rho0 2650 kg/m3, c 20 m/s) under the elasto-viscoplastic
    integration, G = rho0 c^2 / 4 = 265 kPa, over the whole collapse (0.3 s)."""
    mat = {"model": model, "density": 2650.0, "sound_speed": 20.0, "integration": "elastoviscoplastic", **law}
    return {"materials.soil": mat, "bodies.0.initial_stress": "none"}


def cross_ratio(ratio: float) -> dict:
    """Cross with mu_inf = 1.2 Pa s, mu_0 = ratio mu_inf, A = mu_0 / tau_B (tau_B = 200 Pa), m = 1."""
    return evp("cross", viscosity_infinity=1.2, viscosity_zero=1.2 * ratio, time_constant=1.2 * ratio / 200.0)


SOIL += [(f"Cross EVP, mu_0 = 1e{k} mu_inf", cross_ratio(10.0 ** k)) for k in range(2, 7)]
SOIL += [
    ("Bingham EVP, tau_B = 200 Pa", evp("bingham", viscosity=1.2, yield_stress=200.0)),
    ("Bingham EVP, tau_B = 1e5 Pa (stands)", evp("bingham", viscosity=1.2, yield_stress=1e5)),
    ("Herschel-Bulkley EVP, n = 0.5", evp("herschel_bulkley", consistency=5.0, flow_index=0.5, yield_stress=200.0,
                                          max_viscosity=1e4)),
    ("Herschel-Bulkley EVP, n = 1.5", evp("herschel_bulkley", consistency=5.0, flow_index=1.5, yield_stress=200.0,
                                          max_viscosity=1e4)),
]
