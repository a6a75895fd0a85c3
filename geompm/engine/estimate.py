"""What the time step will be, which limit sets it, and how long the run will take.

The wave limit cfl h / c and the viscous limit rho h^2 / (2 d mu_max)
(timestep.py) are compared at the start.  When the viscous one governs (the
source's Cross mapping mu_0 = 1e4 mu_inf does this), the report names the
material, the step, the number of steps, a run time measured on this machine
from a few steps of the scene itself, and the remedies.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from ..errors import SimulationError


@dataclass
class StepReport:
    dt_wave: float
    dt_viscous: float
    material: str | None  # the most viscous material
    mu: float  # its largest viscosity [Pa s]
    steps: float
    seconds_per_step: float | None = None

    @property
    def viscous_governs(self) -> bool:
        return self.dt_viscous < self.dt_wave

    def message(self, end_time: float) -> str:
        dt = min(self.dt_wave, self.dt_viscous)
        text = (f"the time step is set by viscosity: mu = {self.mu:.4g} Pa s of material '{self.material}' gives "
                f"rho h^2 / (2 d mu) = {self.dt_viscous:.3g} s, {self.dt_wave / self.dt_viscous:.0f}x below the "
                f"wave limit {self.dt_wave:.3g} s: {end_time / dt:,.0f} steps to t = {end_time:g} s")
        if self.seconds_per_step:
            text += f", about {_duration(self.steps * self.seconds_per_step)} on this machine"
        return text + (". Remedies: (1) a smaller low-shear viscosity (cross: give viscosity_zero, "
                       "viscosity_infinity and time_constant instead of from_bingham, e.g. mu_0 = 100 mu_inf: the "
                       "step grows in proportion, and the fluid creeps that much faster below its yield stress, "
                       "so check the deposit); (2) a coarser grid (the step grows with h^2); (3) accept the run time "
                       "(docs/stability.md)")


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def step_report(scene) -> StepReport:
    from .timestep import viscous_limit, wave_speed

    c = wave_speed(scene, scene.state)
    dt_wave = scene.cfl * scene.grid.h / c if c > 0 else float("inf")
    dt_visc = viscous_limit(scene)
    mat, name = max(zip(scene.materials, scene.material_names), key=lambda m: m[0].kinematic_viscosity())
    mu = mat.kinematic_viscosity() * mat.density
    dt = scene.dt_fixed or min(dt_wave, dt_visc)
    return StepReport(dt_wave, dt_visc, name, mu, scene.end_time / dt if dt > 0.0 else float("inf"))


def measure_step_seconds(scene_factory, steps: int = 20) -> float:
    """Wall seconds per step of a fresh copy of the scene (after two warm-up steps that load the kernels)."""
    from .scheduler import Simulation

    sim = Simulation(scene_factory())
    for _ in range(2):
        sim.step(sim.stable_dt())
    t0 = time.perf_counter()
    for _ in range(steps):
        sim.step(sim.stable_dt())
    return (time.perf_counter() - t0) / steps


def viscous_report(scene, factory=None) -> StepReport | None:
    """The step report when viscosity governs the time step (with a measured run time if ``factory``)."""
    if scene.dt_fixed is not None:
        return None
    rep = step_report(scene)
    if not rep.viscous_governs:
        return None
    if factory is not None:
        try:
            rep.seconds_per_step = measure_step_seconds(factory)
        except SimulationError:
            pass  # the scene cannot take 22 steps: the run itself reports why, with exit 3
    return rep
