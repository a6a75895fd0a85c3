"""series.csv: one row per output time of global scalar quantities.

Columns: time [s], step, dt [s], kinetic_energy [J; J/m in 2D plane strain],
front_x [m] (largest particle x), then the columns that stages add (obstacle
forces, ...).  With ``displacement`` it adds ``max_displacement`` and
``mean_displacement`` [m], the largest and the mean |x_p - x0_p| over the particles.  With ``normalise`` it adds the dimensionless quantities of
granular-flow studies (e.g. the source study, section 3.1):

    T_star = t sqrt(g / h0),   X_star = (x_front - l0) / l0,   K_star = E_k / (m g h0)

with x_front the largest (x_p - origin) . direction (the front measured along
the slope from the column's back), m the total mass and g = |gravity|.  Each
row is written with one call and flushed, so a crash loses at most the row
being written.  With ``deposit_threshold`` (2D) it adds ``deposit_front`` [m],
the largest x where the deposit is at least that thick (geompm.writers.deposit:
a front that one particle rolling ahead cannot move), and ``deposit_height``
[m], the deposit's largest thickness averaged over a window as wide as the
threshold.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np
from pydantic import Field

from geompm.kernels.reduce import max_projection
from geompm.contract.plugin import Params
from geompm.writers.deposit import front_of, height_of, thickness_profile
from geompm.writers.base import Writer


class Normalise(Params):
    length: float = Field(gt=0, description="l0: initial length of the mass along the slope [m]")
    height: float = Field(gt=0, description="h0: initial height of the mass [m]")
    origin: list[float] = Field(description="Back of the initial mass, where the front is measured from [m]")
    direction: list[float] = Field(description="Direction along the slope in which the front is measured")


class SeriesParams(Params):
    normalise: Normalise | None = Field(None, description="Add T_star, X_star, K_star columns")
    displacement: bool = Field(
        False, description="Add the columns max_displacement and mean_displacement [m], the largest and the mean "
        "particle displacement |x - x0| (geompm stability judges each trial by them)")
    deposit_threshold: float | None = Field(
        None, gt=0, description="2D: add the column deposit_front [m], the largest x where the deposit is at "
        "least this thick [m] (geompm.writers.deposit; e.g. 0.05 H0), and deposit_height [m]; geompm study then takes "
        "them as the runout and the height")


class SeriesWriter(Writer):
    name = "series"
    files = ("series.csv",)
    description = "series.csv: time, step, dt, kinetic energy, front position and stage quantities"
    Params = SeriesParams
    ranks = "own"  # every column is reduced over the ranks (sim.domain.comm); rank 0 writes the file

    @classmethod
    def check(cls, params, case):
        out = []
        if params.deposit_threshold is not None and case.dimension != 2:
            out.append(("deposit_threshold", "the deposit front is defined for 2D (plane-strain) cases only"))
        nm = params.normalise
        if nm is None:
            return out
        return out + [(f"normalise.{k}", f"must have {case.dimension} entries (one per dimension)")
                      for k in ("origin", "direction") if len(getattr(nm, k)) != case.dimension]

    def _row(self, sim):
        row = sim.series_row()
        nm = self.params.normalise
        comm = sim.domain.comm
        if nm is not None:
            st = sim.state
            g = float(np.linalg.norm(sim.scene.gravity))
            front = float(comm.max([max_projection(st.p_x, self.origin, self.direction) if st.n else -np.inf])[0])
            row["T_star"] = sim.time * np.sqrt(g / nm.height)
            row["X_star"] = (front - nm.length) / nm.length
            row["K_star"] = row["kinetic_energy"] / (self.mass * g * nm.height)
        if self.params.displacement:
            st = sim.state
            u = np.sqrt(((st.p_x - st.p_x0) ** 2).sum(axis=1))
            top, total, n = comm.max([u.max() if st.n else 0.0])[0], *comm.sum([u.sum(), st.n])
            row["max_displacement"] = float(top)
            row["mean_displacement"] = float(total / n) if n else 0.0
        if self.params.deposit_threshold is not None:
            t = self.params.deposit_threshold
            parts = comm.gather((sim.state.p_x[:, :1], self._solid_areas(sim)))
            xs, thickness = thickness_profile(np.concatenate([p[0] for p in parts]),
                                              np.concatenate([p[1] for p in parts]), 0.2 * t)
            row["deposit_front"] = front_of(xs, thickness, t, 0.2 * t)
            row["deposit_height"] = height_of(thickness, 0.2 * t, t)
        return row

    @staticmethod
    def _solid_areas(sim):
        """m_p / rho0 of each particle: a particle whose volume grew as it left the flow counts as solid."""
        st = sim.state
        rho0 = np.empty(st.n)
        for mat, (s, e) in zip(sim.scene.materials, st.blocks):
            rho0[s:e] = mat.density
        return st.p_mass / rho0

    def _setup(self, run_dir, sim):
        nm = self.params.normalise
        self.mass = None  # total mass [kg], for the normalised columns only
        if nm is not None:
            self.origin = np.asarray(nm.origin, float)
            self.direction = np.asarray(nm.direction, float) / np.linalg.norm(nm.direction)
            self.mass = float(sim.domain.comm.sum([sim.state.p_mass.sum()])[0])
        self.path = run_dir / "series.csv"
        self.fd = None  # series.csv, open on rank 0 only

    def open(self, run_dir, sim):
        self._setup(run_dir, sim)
        self.columns = list(self._row(sim))
        if sim.domain.comm.is_root:
            self.fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_APPEND, 0o666)  # less the umask
            os.write(self.fd, (",".join(self.columns) + "\n").encode())

    def state(self):
        return {"columns": self.columns, "bytes": os.fstat(self.fd).st_size, "mass": self.mass}

    def resume(self, run_dir, sim, state):
        """Reopen series.csv and cut the rows written after the checkpoint."""
        self._setup(run_dir, sim)
        if state.get("mass") is not None:
            self.mass = state["mass"]  # the initial mass, even if particles were deleted since
        self.columns = state["columns"]
        if sim.domain.comm.is_root:
            self.fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
            os.ftruncate(self.fd, state["bytes"])

    def write(self, sim):
        row = self._row(sim)
        if self.fd is None:
            return
        line = ",".join(repr(int(row[c])) if c == "step" else f"{row[c]:.10g}" for c in self.columns)
        os.write(self.fd, (line + "\n").encode())

    def close(self, sim):
        if self.fd is not None:
            os.fsync(self.fd)
            os.close(self.fd)
            self.fd = None


def read_series(path: str | Path) -> dict[str, np.ndarray]:
    """Columns of a CSV with a header row, as float arrays (``time`` first)."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows or "time" not in rows[0]:
        raise ValueError(f"{path}: a CSV with a 'time' column is needed")
    head, body = rows[0], [r for r in rows[1:] if len(r) == len(rows[0])]
    return {c: np.array([float(r[i]) for r in body]) for i, c in enumerate(head)}
