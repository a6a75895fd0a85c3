"""Whether a strength-reduction trial failed: the slope is still moving at the end of the trial.

A trial runs for T seconds under local damping, which brings a slope that can stand to rest: its
largest displacement u(t) converges.  A slope that cannot stand keeps moving.  The trial failed when
the largest displacement still grew over the last quarter of the trial by at least ``creep``:

    u(T) - u(3T/4) >= creep,      creep = ``creep_cells`` x the cell size (default 0.1 h).

Why this and not the alternatives, measured on the infinite slope (docs/slope-stability.md): the
kinetic energy at the end against its peak (Dawson, Roth & Drescher 1999, Geotechnique 49(6):835)
has no scale when the trial starts from equilibrium (its peak is then round-off); the ratio of the
last two quarters' increments calls a failing slope that slows down under large shear strain stable.
Both are reported beside the criterion.  docs/slope-stability.md shows how the factor of safety moves
with ``creep_cells``.
"""

from __future__ import annotations

import numpy as np

CREEP_CELLS = 0.1


def at(series: dict, column: str, t: float) -> float:
    return float(np.interp(t, series["time"], series[column]))


def judge(series: dict, creep: float) -> dict:
    """{'failed', 'ratio', 'last_increment', 'max_displacement', 'kinetic_energy_ratio'} of one trial's
    series (its time, max_displacement and kinetic_energy columns)."""
    t_end = float(series["time"][-1])
    u2, u3, u4 = (at(series, "max_displacement", f * t_end) for f in (0.5, 0.75, 1.0))
    d_prev, d_last = u3 - u2, u4 - u3
    r = d_last / d_prev if d_prev > 0.0 else (np.inf if d_last > 0.0 else 0.0)
    ek = np.asarray(series["kinetic_energy"], float)
    peak = float(ek.max()) if ek.size else 0.0
    return {"failed": bool(d_last >= creep), "ratio": float(r), "last_increment": float(d_last),
            "max_displacement": float(u4), "kinetic_energy_ratio": float(ek[-1] / peak) if peak > 0 else 0.0}
