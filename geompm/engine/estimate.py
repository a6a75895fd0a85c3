"""What the time step will be, which limit sets it, and how long the run will take.

The wave limit cfl h / c and the viscous limit rho h^2 / (2 d mu_max)
(timestep.py) are compared at the start.  When the viscous one governs (the
source's Cross mapping mu_0 = 1e4 mu_inf does this), the report names the
material, the step, the number of steps, a run time measured on this machine
from a few steps of the scene itself, and the remedies.  A law that offers
another integration (Material.alternatives: the yield-stress fluids' explicit
and elasto-viscoplastic) is swapped in block by block and the step it would
give is reported beside the current one, so that the user sees what the
other choice costs or saves before running.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from geompm.errors import SimulationError


@dataclass
class Alternative:
    """The step a material's other integration would give the scene (Material.alternatives)."""
    material: str  # its name in the case
    setting: str  # the JSON that selects it, e.g. '"integration": "elastoviscoplastic"'
    dt_wave: float
    dt_viscous: float

    @property
    def dt(self) -> float:
        return min(self.dt_wave, self.dt_viscous)

    def sentence(self, dt_now: float, end_time: float) -> str:
        limit = "the viscous limit" if self.dt_viscous < self.dt_wave else "the wave limit"
        ratio = self.dt / dt_now
        change = f"{ratio:.3g}x longer" if ratio >= 1.0 else f"{1.0 / ratio:.3g}x shorter"
        return (f"materials.{self.material}: with {self.setting} the step would be {self.dt:.3g} s, set by {limit} "
                f"({change}: {end_time / self.dt:,.0f} steps to t = {end_time:g} s)")


@dataclass
class StepReport:
    dt_wave: float
    dt_viscous: float
    material: str | None  # the most viscous material
    mu: float  # its largest viscosity [Pa s]
    steps: float
    seconds_per_step: float | None = None
    alternatives: list[Alternative] = field(default_factory=list)

    @property
    def dt(self) -> float:
        return min(self.dt_wave, self.dt_viscous)

    @property
    def viscous_governs(self) -> bool:
        return self.dt_viscous < self.dt_wave

    def governing(self) -> str:
        """Which limit sets the first step, with both limits' values."""
        visc = f"{self.dt_viscous:.3g} s" if math.isfinite(self.dt_viscous) else "none"
        if self.viscous_governs:
            return (f"the time step is set by the viscous limit rho h^2 / (2 d mu) = {self.dt_viscous:.3g} s "
                    f"(mu = {self.mu:.4g} Pa s of material '{self.material}'; the wave limit is {self.dt_wave:.3g} s)")
        return f"the time step is set by the wave limit cfl h / (c + |v|) = {self.dt_wave:.3g} s (viscous limit: {visc})"

    def message(self, end_time: float) -> str:
        """The warning when viscosity governs: the step, the steps, the run time, the remedies."""
        text = (f"the time step is set by viscosity: mu = {self.mu:.4g} Pa s of material '{self.material}' gives "
                f"rho h^2 / (2 d mu) = {self.dt_viscous:.3g} s, {self.dt_wave / self.dt_viscous:.0f}x below the "
                f"wave limit {self.dt_wave:.3g} s: {end_time / self.dt:,.0f} steps to t = {end_time:g} s")
        if self.seconds_per_step:
            text += f", about {_duration(self.steps * self.seconds_per_step)} on this machine"
        remedies = [f"{a.sentence(self.dt, end_time)}; docs/materials.md" for a in self.alternatives
                    if a.dt > self.dt]
        remedies += ["a smaller low-shear viscosity (cross: give viscosity_zero, viscosity_infinity and "
                     "time_constant instead of from_bingham, e.g. mu_0 = 100 mu_inf: the step grows in proportion, "
                     "and the fluid creeps that much faster below its yield stress, so check the deposit)",
                     "a coarser grid (the step grows with h^2)", "accept the run time (docs/numerical-envelope.md)"]
        return text + ". Remedies: " + "; ".join(f"({i}) {r}" for i, r in enumerate(remedies, 1))


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def step_report(scene) -> StepReport:
    """The first step's limits, and what each material's other integration would make of them."""
    from geompm.backend.timestep import viscous_limit, wave_limit

    st = scene.state
    dt_wave, dt_visc = wave_limit(scene, st), viscous_limit(scene)
    mat, name = max(zip(scene.materials, scene.material_names), key=lambda m: m[0].kinematic_viscosity())
    mu = mat.kinematic_viscosity() * mat.density
    dt = scene.dt_fixed or min(dt_wave, dt_visc)
    alts = []
    for i, (m, mname) in enumerate(zip(scene.materials, scene.material_names)):
        for setting, other in m.alternatives():
            swapped = [other if j == i else x for j, x in enumerate(scene.materials)]
            alts.append(Alternative(mname, setting, wave_limit(scene, st, swapped), viscous_limit(scene, swapped)))
    return StepReport(dt_wave, dt_visc, name, mu, scene.end_time / dt if dt > 0.0 else float("inf"),
                      alternatives=alts)


def measure_step_seconds(scene_factory, steps: int = 20) -> float:
    """Wall seconds per step of a fresh copy of the scene (after two warm-up steps that load the kernels)."""
    from geompm.engine.scheduler import Simulation

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
