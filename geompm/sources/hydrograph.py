"""A hydrograph: the discharge Q(t) through a cross-section and the flow's speed or depth there, from a table.

The table's rows are times t_i [s] (non-decreasing), discharges Q_i [m3/s; m2/s per metre in 2D] (>= 0) and
either speeds v_i [m/s] or depths h_i [m] (> 0 where Q > 0).  Between two rows every column is linear in time;
before the first row and after the last the discharge is zero (the flow starts and stops with the table).
The volume that has passed by t is the exact integral of that piecewise-linear Q,

    V(t) = sum of the whole intervals' trapezoids + Q_i tau + (Q_{i+1} - Q_i) tau^2 / (2 dt_i),

tau = t - t_i in interval i, and its inverse (the time a volume has passed) solves that quadratic.  A CSV file
has a header naming its columns: ``time``, ``discharge`` and ``velocity`` or ``depth`` (a unit after the name,
"time [s]" or "time_s", is allowed); commas, semicolons or tabs separate the values.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

#: the third column's names
THIRD = ("velocity", "depth")
#: the rows a table may have (it is read whole)
MAX_ROWS = 100_000


class Hydrograph:
    """The piecewise-linear hydrograph of ``times``, ``discharge`` and ``third`` (speeds or depths, named by
    ``kind``)."""

    def __init__(self, times, discharge, third, kind: str):
        self.t = np.asarray(times, float)
        self.q = np.asarray(discharge, float)
        self.third = np.asarray(third, float)
        self.kind = kind
        dt = np.diff(self.t)
        self.cum = np.r_[0.0, np.cumsum(0.5 * (self.q[1:] + self.q[:-1]) * dt)]  # V at each row [m3]

    @property
    def total(self) -> float:
        """The volume of the whole hydrograph [m3; m2 per metre in 2D]."""
        return float(self.cum[-1])

    @property
    def end(self) -> float:
        return float(self.t[-1])

    def discharge(self, time: float) -> float:
        if time < self.t[0] or time > self.t[-1]:
            return 0.0
        return float(np.interp(time, self.t, self.q))

    def column(self, time: float) -> float:
        """The speed [m/s] or depth [m] at ``time`` (the nearest row's outside the table)."""
        return float(np.interp(time, self.t, self.third))

    def volume(self, time: float) -> float:
        """V(t) = int_0^t Q dt [m3; m2 per metre in 2D]."""
        if time <= self.t[0]:
            return 0.0
        if time >= self.t[-1]:
            return self.total
        i = int(np.searchsorted(self.t, time, side="right")) - 1
        tau, span = time - self.t[i], self.t[i + 1] - self.t[i]
        slope = (self.q[i + 1] - self.q[i]) / span if span > 0 else 0.0
        return float(self.cum[i] + self.q[i] * tau + 0.5 * slope * tau * tau)

    def time_of(self, vol: float) -> float:
        """The first time at which V(t) >= ``vol``; inf if the hydrograph never carries it."""
        if vol <= 0.0:
            return float(self.t[0])
        if vol > self.total:
            return math.inf
        i = min(int(np.searchsorted(self.cum, vol, side="left")), len(self.t) - 1) - 1
        i = max(i, 0)
        rest, q0 = vol - self.cum[i], self.q[i]
        span = self.t[i + 1] - self.t[i]
        a = 0.5 * (self.q[i + 1] - q0) / span if span > 0 else 0.0
        if abs(a) * span < 1e-12 * max(q0, 1e-300):  # constant discharge in the interval
            tau = rest / q0 if q0 > 0 else 0.0
        else:  # a tau^2 + q0 tau - rest = 0, the root in [0, span]
            tau = 2.0 * rest / (q0 + math.sqrt(max(q0 * q0 + 4.0 * a * rest, 0.0)))
        return float(self.t[i] + min(max(tau, 0.0), span))


def table_problems(times, discharge, third, kind: str) -> list[str]:
    """What is wrong with a hydrograph's columns, as sentences (empty: none)."""
    t, q, c = (np.asarray(a, float) for a in (times, discharge, third))
    out = []
    if len(t) < 2:
        out.append("needs at least two rows (the discharge is linear between rows)")
    if not (np.isfinite(t).all() and np.isfinite(q).all() and np.isfinite(c).all()):
        out.append("every value must be a finite number")
        return out
    if len(t) and t[0] < 0.0:
        out.append(f"times start at {t[0]:g} s: they must be >= 0 (the run starts at t = 0)")
    bad = np.flatnonzero(np.diff(t) < 0)
    if bad.size:
        out.append(f"times must not decrease (row {bad[0] + 2}: {t[bad[0] + 1]:g} s after {t[bad[0]]:g} s)")
    if (q < 0).any():
        k = int(np.argmax(q < 0))
        out.append(f"discharge must be >= 0 (row {k + 1}: {q[k]:g})")
    wet = q > 0
    if (c[wet] <= 0).any():
        k = int(np.flatnonzero(wet & (c <= 0))[0])
        out.append(f"the {kind} must be > 0 where the discharge is (row {k + 1}: {c[k]:g} with Q = {q[k]:g})")
    if len(q) and not wet.any():
        out.append("the discharge is zero throughout: nothing would flow in")
    return out


def _name(cell: str) -> str:
    """A header cell's column name: its first word, lower case ('Time [s]' and 'time_s' -> 'time')."""
    return re.split(r"[\s\[\(_]", cell.strip().lower(), maxsplit=1)[0]


def read_hydrograph(path) -> tuple[Hydrograph | None, list[str]]:
    """(the hydrograph of a CSV file, []) or (None, sentences naming the file, the line and the fix)."""
    path = Path(path)
    try:
        with open(path, encoding="utf-8-sig") as fh:
            lines = [ln for ln in (raw.strip() for raw in fh) if ln and not ln.startswith("#")]
    except OSError as exc:
        return None, [f"cannot read the hydrograph '{path}': {exc.strerror or exc}"]
    except UnicodeDecodeError:
        return None, [f"the hydrograph '{path}' is not a text (CSV) file"]
    if len(lines) > MAX_ROWS + 1:
        return None, [f"the hydrograph '{path}' has {len(lines) - 1} rows, more than {MAX_ROWS}: thin it out"]
    if not lines:
        return None, [f"the hydrograph '{path}' is empty: give a header (time,discharge,velocity) and rows"]
    sep = "\t" if "\t" in lines[0] else (";" if ";" in lines[0] and "," not in lines[0] else ",")
    names = [_name(c) for c in lines[0].split(sep)]
    third = [n for n in names if n in THIRD]
    missing = [n for n in ("time", "discharge") if n not in names]
    if missing or len(third) != 1:
        return None, [f"the hydrograph '{path}' header '{lines[0]}' must name the columns 'time' [s], "
                      f"'discharge' [m3/s, m2/s per metre in 2D] and one of 'velocity' [m/s] or 'depth' [m]"]
    cols = [names.index("time"), names.index("discharge"), names.index(third[0])]
    rows = []
    for k, line in enumerate(lines[1:], start=2):
        cells = line.split(sep)
        try:
            rows.append([float(cells[c]) for c in cols])
        except (ValueError, IndexError):
            return None, [f"the hydrograph '{path}', data row {k - 1} ('{line}'): expected numbers in the "
                          f"columns {', '.join(names[c] for c in cols)}"]
    arr = np.asarray(rows, float).reshape(-1, 3)
    bad = table_problems(arr[:, 0], arr[:, 1], arr[:, 2], third[0])
    if bad:
        return None, [f"the hydrograph '{path}': {b}" for b in bad]
    return Hydrograph(arr[:, 0], arr[:, 1], arr[:, 2], third[0]), []
