"""One strength-reduction trial: the case with its strength divided by F, run quasi-statically.

A trial is an ordinary run of the case with ``--set`` overrides (so its folder is a run folder that
``geompm info`` reads), over ``duration`` T:

- the strength trigger (schema: triggers.strength_reduction) holds F0 for the first quarter (the case
  comes to equilibrium from its initial state), ramps to F over the second quarter and holds F for the
  second half: F0 = 1, the soil as it is, for F >= 1; for F < 1, where the soil as it is cannot stand,
  F0 = F / 2 (at least 0.05, the trigger's lowest factor), twice the trial's strength (starting at F itself let the dynamic response to the initial
  imbalance fail a slope that stands: on the infinite slope with phi = 15 deg on beta = 20 deg, h = 0.2 m,
  F came out 0.654 against tan(phi) / tan(beta) = 0.736); criterion.py reads the last quarter.  Every material
  whose law declares ``strength_reduction`` is reduced; others (a fluid, an elastic base) keep theirs.
  Any trigger of the case is replaced: the factor of safety is that of the slope before its trigger; a
  water table stays, held at its height at t = 0 (``--set triggers.water_table.heights=[...]`` for another);
- the damping becomes mass-proportional viscous damping f = -zeta m v at one rate zeta [1/s] for every
  material (the ``artificial`` stage, its rate fixed through reference_cell_size), default 40 / T so that
  the transient of the first quarter decays by e^-5 in its amplitude before the ramp; Cundall's local
  damping only if asked for (``alpha`` > 0): its force alpha |f| sign(v) rectifies the noise of the nodal
  forces into a friction that adds strength, +3.6 % to the infinite slope's F at alpha = 0.1 and growing
  with refinement where failure localises (docs/slope-stability.md);
- a saturated material (``pore_water``) is drained: its pore pressure is held at its initial, steady state
  (``pore_water.drainage: "drained"``), so that the trial reads the strength of the soil under that pressure
  and not the creep of its consolidation (a long-term, drained factor of safety; an undrained one is the
  law's undrained strength, c_u with phi = 0, not a reduction of the coupled run);
- the outputs become series.csv with ``max_displacement`` (40 rows) and one VTU at the end (the mechanism).

Starting every trial at once from the reduced strength instead (the first version) let the dynamic
response to the initial imbalance yield the slope: on the infinite slope its factor of safety came out
1.6 % low and the stable trials near it moved 0.17 m (docs/slope-stability.md).
"""

from __future__ import annotations

import json
import math

from geompm.errors import CaseError

SERIES_ROWS = 40
XI = 1e-3
#: the trials' default viscoplastic time is the trial's duration over this (0.0025 s for a trial of 2 s)
VISCOPLASTIC_SHARE = 800.0
#: the least factor a trial starts from (the strength trigger's lowest)
LOWEST_START = 0.05


def reducible_materials(loaded) -> list[str]:
    """The names of the case's materials, used by a body, whose law has a strength to reduce."""
    used = {b.material for b in loaded.case.bodies}
    return [name for name, r in loaded.materials.items() if name in used and r.cls.strength_reduction]


def check_case(loaded) -> None:
    if not reducible_materials(loaded):
        laws = ", ".join(sorted({r.cls.name for r in loaded.materials.values()})) or "none"
        raise CaseError([("materials", "geompm stability divides the shear strength of the case's soils, but no "
                                       f"body is made of a law with a strength to reduce (laws: {laws}); give a "
                                       "body a soil law such as mohr_coulomb or drucker_prager")])


def trial_damping(loaded, rate: float, alpha: float) -> list[dict]:
    """The trials' damping stages: viscous at ``rate`` [1/s] for every material, Cundall's if ``alpha`` > 0.
    The artificial stage's rate is (xi / h_ref) sqrt(E / rho) (damping/artificial.py): xi = 1e-3 and
    h_ref = xi sqrt(E / rho) / rate give each material the same rate."""
    out = []
    for name, r in loaded.materials.items():
        mat = r.cls(r.params)
        speed = math.sqrt(mat.stiffness() / mat.density)
        out.append({"model": "artificial", "xi": XI, "reference_cell_size": XI * speed / rate, "materials": [name]})
    if alpha > 0.0:
        out.append({"model": "local", "alpha": alpha})
    return out


def drained_materials(loaded) -> list[str]:
    """The saturated materials (``pore_water``) whose pore pressure the trials hold at its initial state."""
    return sorted(name for name, m in loaded.case.materials.items() if m.pore_water is not None)


def viscoplastic_time(loaded, duration: float, given: float | None) -> float | None:
    """The trials' Duvaut-Lions relaxation time [s] (kernels/viscoplastic.py): ``given`` (0: none), else the
    case's own solver.viscoplastic_time, else duration / VISCOPLASTIC_SHARE."""
    if given is not None:
        return float(given) if given > 0.0 else None
    own = loaded.case.solver.viscoplastic_time
    return float(own) if own is not None else duration / VISCOPLASTIC_SHARE


def strength_schedule(factor: float, duration: float) -> tuple[list[float], list[float]]:
    """(times [s], factors) of the trial at ``factor``: F0 for the first quarter, a ramp to F over the second,
    F held for the second half (module docstring)."""
    f0 = 1.0 if factor >= 1.0 else max(0.5 * factor, LOWEST_START)
    return [0.0, 0.25 * duration, 0.5 * duration], [f0, f0, float(factor)]


def trial_sets(loaded, factor: float, duration: float, damping: list[dict], relaxation: float | None = None) -> list[str]:
    """The --set overrides of the trial at ``factor``; ``relaxation``: the laws' viscoplastic time [s] or None."""
    times, factors = strength_schedule(factor, duration)
    trigger = {"strength_reduction": {"times": times, "factors": factors, "materials": reducible_materials(loaded)}}
    water = loaded.case.triggers.water_table if loaded.case.triggers is not None else None
    if water is not None:
        held = water.model_dump(exclude_none=True)
        held["times"] = [0.0]
        if water.heights is not None:
            held["heights"] = [water.heights[0]]
        if water.pond is not None:
            held["pond"] = {"times": [0.0], "levels": [water.pond.levels[0]]}
        if water.seepage is not None:
            held["seepage"]["times"] = [0.0]
            for row, spec in zip(held["seepage"]["heads"], water.seepage.heads):
                row["head"] = spec.at(water.seepage.times, 0.0)
        trigger["water_table"] = held
    outputs = [{"writer": "series", "interval": duration / SERIES_ROWS, "displacement": True},
               {"writer": "vtu", "interval": duration / 4}]  # 3T/4 and T give the slip surface (slip.py)
    drained = [f"materials.{name}.pore_water.drainage=\"drained\"" for name in drained_materials(loaded)]
    return [f"triggers={json.dumps(trigger)}", f"time.end={json.dumps(duration)}",
            f"damping={json.dumps(damping)}", f"outputs={json.dumps(outputs)}",
            f"solver.viscoplastic_time={json.dumps(relaxation)}", *drained]
