"""The strength trigger at run time: the soils' packed parameters follow F(t) (schema: triggers).

F(t) is piecewise linear through the case's (times, factors).  Before each stress update the
Simulation asks for F at the step's time; where it changed, each named law's parameters are packed
again from ``strength_reduced(params, F)`` into the same array (so the backend's loops see them) and
the backend is told (a device keeps a copy).  The original parameters are never changed: F is a
function of time alone, so a run resumed from a checkpoint takes the same strength at the same time.
"""

from __future__ import annotations

import numpy as np


class StrengthSchedule:
    """F(t) through ``times`` [s] and ``factors`` [-] for the materials ``material_ids`` (scene order);
    made from ``scene.strength_trigger`` (setup/assemble.py)."""

    def __init__(self, times, factors, material_ids):
        self.times = np.asarray(times, float)
        self.factors = np.asarray(factors, float)
        self.material_ids = list(material_ids)
        self.current = 1.0

    def factor(self, time: float) -> float:
        return float(np.interp(time, self.times, self.factors))

    def apply(self, scene, backend, time: float) -> None:
        f = self.factor(time)
        if f == self.current:
            return
        for k in self.material_ids:
            mat = scene.materials[k]
            law = type(mat)
            reduced = mat.params.model_copy(update=law.strength_reduced(mat.params, f))
            mat.prm[:] = law(reduced).prm
        backend.material_parameters_changed()
        self.current = f

    def series(self, time: float) -> dict[str, float]:
        return {"strength_factor": self.factor(time)}


class NoStrengthSchedule:
    """A scene without a strength trigger: nothing changes, no series column."""

    current = 1.0

    def apply(self, scene, backend, time: float) -> None:
        pass

    def series(self, time: float) -> dict[str, float]:
        return {}


def strength_schedule(trigger):
    """The schedule of ``scene.strength_trigger`` (times, factors, material ids), or a NoStrengthSchedule."""
    return NoStrengthSchedule() if trigger is None else StrengthSchedule(*trigger)
