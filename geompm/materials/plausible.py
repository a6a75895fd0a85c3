"""Plausibility ranges a law declares for its parameters: values that are valid but look like a wrong unit.

A law lists ``Plausible`` entries in its class attribute ``plausible``; `geompm
validate` and `geompm run` warn (never refuse) for each parameter outside its
range, naming the JSON path, the value and the likely meaning ("looks like
radians", "t/m3?").  Zero is never suspicious where ``zero_ok`` (a cohesionless
soil).  Third-party laws declare theirs the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Plausible:
    """``field`` is suspicious below ``low`` or above ``high`` (SI units); ``hint(value)`` says why."""

    field: str
    hint: Callable[[float], str]
    low: float | None = None
    high: float | None = None
    zero_ok: bool = True

    def check(self, value) -> str | None:
        if value is None or (self.zero_ok and value == 0.0):
            return None
        if (self.low is not None and value < self.low) or (self.high is not None and value > self.high):
            return f"{self.field} = {value:g}: {self.hint(float(value))}"
        return None


def warnings_for(plausible, params) -> list[tuple[str, str]]:
    """(field, sentence) for every declared parameter of ``params`` outside its range."""
    return [(p.field, text) for p in plausible if (text := p.check(getattr(params, p.field, None))) is not None]


DENSITY = Plausible(
    "density", low=100.0,
    hint=lambda v: (f"below 100 kg/m3, lighter than any soil, debris or water: was it given in t/m3 or "
                    f"g/cm3? ({v:g} t/m3 is {v * 1000:g} kg/m3)"))

YOUNGS_MODULUS = Plausible(
    "youngs_modulus", low=1.0e3,
    hint=lambda v: (f"below 1 kPa: was it given in MPa or kPa? ({v:g} MPa is {v * 1e6:.3g} Pa; soils are "
                    "1-1000 MPa, and a stiffness this low makes a soft jelly with a long, slow time step)"))


def angle(field: str) -> Plausible:
    """An angle in degrees that is below 1.6 (pi / 2 rad): it looks like radians."""
    return Plausible(field, low=1.6, hint=lambda v: (f"below 1.6 deg, which looks like radians ({v:g} rad is "
                                                     f"{math.degrees(v):.4g} deg); angles are in degrees"))


COHESION = Plausible(
    "cohesion", low=100.0,
    hint=lambda v: (f"below 100 Pa, negligible beside any soil's weight (1 m of soil weighs ~20 kPa): was it "
                    f"given in kPa? ({v:g} kPa is {v * 1e3:g} Pa); give 0 for a cohesionless soil"))
