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
from pathlib import Path

import numpy as np

from geompm.api import scene_from_dict
from geompm.schema.load import apply_overrides
from geompm.engine.health import HealthCheck, health_sums, outside_grid
from geompm.engine.scheduler import Simulation

ALLOWANCE = 1.05
ROOT = Path(__file__).resolve().parents[2]


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
