"""Whether a strength-reduction trial failed: the slope is still moving steadily at the end of the trial.

A trial runs for T seconds under viscous damping (trial.py), which brings a slope that can stand to
rest: the increments of its largest displacement u(t) shrink geometrically, by exp(-zeta T / 8) or
faster from one quarter to the next for the modes it damps.  A slope that cannot stand moves on at its
terminal speed (the damping force -zeta m v balances the unbalanced part of gravity) or faster.  The trial
failed when, over its last two quarters,

    r = (u(T) - u(3T/4)) / (u(3T/4) - u(T/2)) >= ratio     and     u(T) - u(3T/4) >= floor,

with ``ratio`` 0.5 by default and ``floor`` a thousandth of the cell size (increments below it are the
round-off of a slope at rest, whose ratio means nothing).  The criterion has no displacement scale: a
failing slope just past its limit moves slowly but steadily (r near 1), a stable one just below it slowly
and ever more slowly.  docs/slope-stability.md shows how the factor of safety moves with ``ratio`` and
why a threshold on the displacement itself (the first version) and Cundall's local damping were dropped.
The kinetic energy at the end against its peak is reported beside it (Dawson, Roth & Drescher 1999,
Geotechnique 49(6):835, use its non-convergence).
"""

from __future__ import annotations

import numpy as np

DEFAULT_RATIO = 0.5
FLOOR_CELLS = 1e-3


def at(series: dict, column: str, t: float) -> float:
    return float(np.interp(t, series["time"], series[column]))


def judge(series: dict, ratio: float, floor: float) -> dict:
    """{'failed', 'ratio', 'last_increment', 'max_displacement', 'kinetic_energy_ratio'} of one trial's
    series (its time, max_displacement and kinetic_energy columns)."""
    t_end = float(series["time"][-1])
    u2, u3, u4 = (at(series, "max_displacement", f * t_end) for f in (0.5, 0.75, 1.0))
    d_prev, d_last = u3 - u2, u4 - u3
    r = d_last / d_prev if d_prev > 0.0 else (np.inf if d_last > 0.0 else 0.0)
    ek = np.asarray(series["kinetic_energy"], float)
    peak = float(ek.max()) if ek.size else 0.0
    return {"failed": bool(r >= ratio and d_last >= floor), "ratio": float(r), "last_increment": float(d_last),
            "max_displacement": float(u4), "kinetic_energy_ratio": float(ek[-1] / peak) if peak > 0 else 0.0}
