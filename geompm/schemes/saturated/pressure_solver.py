"""The semi-implicit step's linear solve: conjugate gradients (scipy.sparse.linalg.cg) preconditioned by one
V-cycle of pyamg's smoothed aggregation (Vanek, Mandel & Brezina 1996, Computing 56:179) on the symmetric
positive definite pressure system (pressure_system.py), scaled to a unit diagonal first (D^-1/2 A D^-1/2: the
system's coefficients are of order dt^2 V / (rho h^2), 1e-12 and less, beside its identity rows; unscaled, a
small system's one-level hierarchy inverted it with a pseudo-inverse that cut the physical rows off as
round-off, and CG returned NaN).

The system has a row per node of the step's grid window (pressure_system.py), so its size lasts while the
window does.  The multigrid hierarchy costs several solves to build, and any symmetric positive definite
preconditioner keeps CG exact, so one hierarchy serves while the window and the step (within 20 %: the
matrix is the storage plus dt^2 times the Laplacian) stay the same, for at most ``rebuild_interval`` steps, and
until the iterations reach twice those of its first solve (the water has moved enough to matter).  A solve that
does not converge on a reused hierarchy is tried once more on a fresh one.  The last increment starts the next
solve.
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import cg

from geompm.errors import SimulationError


class PressureSolver:
    def __init__(self, tolerance: float, max_iterations: int, rebuild_interval: int):
        self.tolerance = float(tolerance)
        self.max_iterations = int(max_iterations)
        self.rebuild_interval = int(rebuild_interval)
        self._size = -1  # the system's size and the window (lo) of the hierarchy
        self._lo = None
        self._dt = 0.0  # the step of the hierarchy's matrix
        self._M = None
        self._age = 0
        self._first = 0
        self._x = None
        #: the last solve's iterations, its relative residual, seconds in the solve (hierarchy included),
        #: unknowns; and the run's totals
        self.iterations = 0
        self.residual = 0.0
        self.seconds = 0.0
        self.unknowns = 0
        self.total_iterations = 0
        self.total_seconds = 0.0
        self.solves = 0
        self.builds = 0

    def _build(self, A, size, lo, dt) -> None:
        import pyamg

        ml = pyamg.smoothed_aggregation_solver(A, symmetry="symmetric", max_coarse=500)
        self._M = ml.aspreconditioner(cycle="V")
        self._size, self._lo, self._dt = size, np.array(lo), dt
        self._age, self._first = 0, 0
        self.builds += 1

    def solve(self, A: sp.csr_matrix, b: np.ndarray, unknowns: int, lo, dt: float, where: str) -> np.ndarray:
        """x with A x = b to the relative residual ``tolerance`` (``unknowns``: the rows that are not the
        identity, reported; ``dt`` the step the matrix is for); SimulationError (exit 3) naming ``where`` (the
        step) and the residual if CG does not reach it within ``max_iterations``."""
        t0 = time.perf_counter()
        self.unknowns = unknowns
        norm = float(np.linalg.norm(b))
        if b.size == 0 or norm == 0.0:
            self.iterations, self.residual = 0, 0.0
            self._x = np.zeros(b.size)
            self.seconds = time.perf_counter() - t0
            return self._x
        scale = 1.0 / np.sqrt(A.diagonal())
        rows = np.repeat(np.arange(b.size), np.diff(A.indptr))
        A = sp.csr_matrix((A.data * scale[rows] * scale[A.indices], A.indices, A.indptr), shape=A.shape)
        b = b * scale
        norm = float(np.linalg.norm(b))
        same = b.size == self._size and np.array_equal(self._lo, lo)
        fresh = (not same or self._M is None or self._age >= self.rebuild_interval or abs(dt / self._dt - 1.0) > 0.2
                 or (self._first > 0 and self.iterations > 2 * self._first))
        if fresh:
            self._build(A, b.size, lo, dt)
        x0 = self._x / scale if same and self._x is not None and self._x.size == b.size else None
        count = [0]

        def tick(_):
            count[0] += 1

        x, info = cg(A, b, x0=x0, rtol=self.tolerance, atol=0.0, maxiter=self.max_iterations, M=self._M,
                     callback=tick)
        if info != 0 and not fresh:
            self._build(A, b.size, lo, dt)
            x, info = cg(A, b, x0=x0, rtol=self.tolerance, atol=0.0, maxiter=self.max_iterations, M=self._M,
                         callback=tick)
        self.residual = float(np.linalg.norm(b - A @ x)) / norm
        self.iterations = count[0]
        if self._first == 0:
            self._first = max(count[0], 1)
        self._age += 1
        self.seconds = time.perf_counter() - t0
        self.total_iterations += count[0]
        self.total_seconds += self.seconds
        self.solves += 1
        if info != 0 or not np.isfinite(self.residual):
            raise SimulationError(
                f"the pore pressure's solve did not converge at {where}: relative residual {self.residual:.3g} "
                f"after {count[0]} iterations (solver.pressure_solver.tolerance {self.tolerance:g}, max_iterations "
                f"{self.max_iterations}). Likely causes: a step too long for the skeleton (lower time.cfl), a "
                "blow-up, or a body sealed from every drained surface with incompressible water; raise "
                "solver.pressure_solver.max_iterations if the residual was still falling")
        self._x = x * scale
        return self._x
