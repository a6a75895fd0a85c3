"""series.csv: one row per output time of global scalar quantities.

Columns: time [s], step, dt [s], kinetic_energy [J; J/m in 2D plane strain],
front_x [m] (largest particle x), then the columns that stages add (obstacle
forces, ...).  Each row is written with one call and flushed, so a crash
loses at most the row being written.
"""

from __future__ import annotations

import os

from ..plugin import Params
from .base import Writer


class SeriesWriter(Writer):
    name = "series"
    description = "series.csv: time, step, dt, kinetic energy, front position and stage quantities"
    Params = Params

    def open(self, run_dir, sim):
        self.columns = list(sim.series_row())
        self.path = run_dir / "series.csv"
        self.fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_APPEND, 0o644)
        os.write(self.fd, (",".join(self.columns) + "\n").encode())

    def write(self, sim):
        row = sim.series_row()
        line = ",".join(repr(int(row[c])) if c == "step" else f"{row[c]:.10g}" for c in self.columns)
        os.write(self.fd, (line + "\n").encode())

    def close(self, sim):
        os.fsync(self.fd)
        os.close(self.fd)
