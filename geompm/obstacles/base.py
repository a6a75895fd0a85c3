"""Rigid obstacles: grid contact through a signed-distance field, and the force history.

At set-up each obstacle samples its signed distance phi (positive outside,
metres) on a lattice of spacing h in its own frame, covering its bounding box
plus two cells.  Each step every window node within the obstacle's reach is
looked up (trilinear interpolation; exact on static obstacles whose lattice
coincides with the grid), and nodes with phi <= ``contact_layer`` get the
contact rule of boundaries/contact.py with the outward normal grad(phi)/|grad(phi)|,
applied to the velocity relative to the obstacle's prescribed velocity
(velocity-based grid contact of rigid-boundary MPM; Bardenhagen et al. 2000).

Force on the obstacle = - sum over its nodes of m_i (v_i,after - v_i,before) / dt
(the momentum the contact removed from the material), with its normal part
f_n = sum of the per-node components along each node's normal (pushing into the
obstacle is positive), the tangential magnitude f_t = |F - sum (F_i . n_i) n_i|,
and the moment about ``moment_point``.  Series columns <name>_fx, _fy(, _fz),
_fn, _ft, _mz (2D) or _mx, _my, _mz (3D), in N (N/m in 2D plane strain).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numba import njit
from pydantic import Field

from ..boundaries.contact import CONDITIONS, apply_condition
from ..errors import CaseError
from ..plugin import Params, vector_length_problems
from ..stages import GridStage


class ObstacleParams(Params):
    condition: Literal["slip", "fixed", "friction"] = Field("friction", description="Contact condition")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (condition 'friction')")
    velocity: list[float] | None = Field(None, description="Prescribed translational velocity [m/s]")
    contact_layer: float = Field(
        0.0, ge=0.0, description="Nodes with signed distance <= this [m] are in contact (0: on or inside)")
    moment_point: list[float] | None = Field(None, description="Reference point of the moment [m]; default the "
                                                               "centre of the obstacle's bounding box")


@njit(cache=True, inline="always")
def _interp(field, lat_origin, inv_h, shape, x, base, frac, out):
    """Trilinear (bilinear in 2D) interpolation of a flat lattice field (points, k) at x (d,) into out (k,)."""
    d = x.shape[0]
    k = field.shape[1]
    for c in range(k):
        out[c] = 0.0
    for a in range(d):
        xi = (x[a] - lat_origin[a]) * inv_h
        i = int(np.floor(xi))
        i = min(max(i, 0), shape[a] - 2)
        base[a] = i
        frac[a] = min(max(xi - i, 0.0), 1.0)
    for corner in range(1 << d):
        w = 1.0
        flat = 0
        for a in range(d):
            bit = (corner >> a) & 1
            w *= frac[a] if bit else 1.0 - frac[a]
            flat = flat * shape[a] + base[a] + bit
        if w == 0.0:
            continue
        for c in range(k):
            out[c] += w * field[flat, c]


@njit(cache=True)
def obstacle_apply(g_vel, g_mass, origin, h, lo, nloc, field, lat_origin, lat_shape, shift, vel, layer,
                   condition, mu, inv_dt, moment_point, out):
    """Contact on window nodes; out[0:d] force on the obstacle, out[d] f_n, out[d+1:2d+1] sum f_n n,
    out[2d+1:2d+4] moment (3 components).  Returns the number of nodes in contact."""
    nn, d = g_vel.shape
    inv_h = 1.0 / h
    x = np.empty(d)
    normal = np.empty(d)
    before = np.empty(d)
    f = np.empty(d)
    base = np.empty(d, np.int64)
    frac = np.empty(d)
    val = np.empty(d + 1)
    for j in range(out.shape[0]):
        out[j] = 0.0
    lat_hi = np.empty(d)
    for a in range(d):
        lat_hi[a] = lat_origin[a] + (lat_shape[a] - 1) * h
    count = 0
    for idx in range(nn):
        m = g_mass[idx]
        if m <= 0.0:
            continue
        rem = idx
        inside_box = True
        for a in range(d - 1, -1, -1):
            i = rem % nloc[a]
            rem //= nloc[a]
            x[a] = origin[a] + (lo[a] + i) * h - shift[a]
            if x[a] < lat_origin[a] or x[a] > lat_hi[a]:
                inside_box = False
        if not inside_box:
            continue
        _interp(field, lat_origin, inv_h, lat_shape, x, base, frac, val)
        if val[0] > layer:
            continue
        norm = 0.0
        for a in range(d):
            normal[a] = val[1 + a]
            norm += normal[a] * normal[a]
        if norm == 0.0:
            continue
        norm = np.sqrt(norm)
        for a in range(d):
            normal[a] /= norm
            before[a] = g_vel[idx, a]
            g_vel[idx, a] -= vel[a]
        apply_condition(g_vel, idx, normal, condition, mu)
        fn = 0.0
        for a in range(d):
            g_vel[idx, a] += vel[a]
            f[a] = -m * (g_vel[idx, a] - before[a]) * inv_dt  # force on the obstacle
            out[a] += f[a]
            fn += -f[a] * normal[a]  # normal points out of the obstacle: pushing in is positive
        out[d] += fn
        for a in range(d):
            out[d + 1 + a] += -fn * normal[a]
        r0 = x[0] + shift[0] - moment_point[0]
        r1 = x[1] + shift[1] - moment_point[1]
        if d == 3:
            r2 = x[2] + shift[2] - moment_point[2]
            out[2 * d + 1] += r1 * f[2] - r2 * f[1]
            out[2 * d + 2] += r2 * f[0] - r0 * f[2]
            out[2 * d + 3] += r0 * f[1] - r1 * f[0]
        else:
            out[2 * d + 3] += r0 * f[1] - r1 * f[0]
        count += 1
    return count


def sdf_lattice(sdf_fn, lo, hi, h):
    """Signed distance (positive outside) and its gradient on a lattice covering [lo, hi] + 2 cells."""
    lo = np.asarray(lo, float) - 2 * h
    hi = np.asarray(hi, float) + 2 * h
    shape = np.ceil((hi - lo) / h).astype(np.int64) + 1
    axes = [lo[a] + h * np.arange(shape[a]) for a in range(len(lo))]
    pts = np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=1)
    phi = np.asarray(sdf_fn(pts), dtype=float).reshape(tuple(shape))
    grads = np.gradient(phi, h)
    grads = grads if isinstance(grads, (list, tuple)) else [grads]
    field = np.stack([phi] + list(grads), axis=-1).reshape(-1, len(lo) + 1)
    return np.ascontiguousarray(field), lo, shape


class RigidObstacle(GridStage):
    """Base of every rigid obstacle: subclasses give ``bounds()`` and ``signed_distance(points)``."""

    Params = ObstacleParams

    @classmethod
    def check(cls, params, case):
        return vector_length_problems(params, case, ("velocity", "moment_point"))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def signed_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance [m] of points (m, d), positive outside the obstacle."""
        raise NotImplementedError

    def setup(self, scene):
        self.dim = scene.dim
        self.grid = scene.grid
        lo, hi = self.bounds()
        if np.any(hi < scene.grid.origin) or np.any(lo > scene.grid.upper):
            raise CaseError([(self.json_path, f"obstacle '{self.label}' lies outside the grid "
                                              f"({lo} .. {hi} m against {scene.grid.origin} .. {scene.grid.upper} m)")])
        self.field, self.lat_origin, self.lat_shape = sdf_lattice(self.signed_distance, lo, hi, scene.grid.h)
        v = self.params.velocity
        self.vel = np.zeros(scene.dim) if v is None else np.asarray(v, float)
        mp = self.params.moment_point
        self.moment_point = 0.5 * (lo + hi) if mp is None else np.asarray(mp, float)
        self.condition = CONDITIONS[self.params.condition]
        self.out = np.zeros(2 * scene.dim + 4)
        self.force = np.zeros(scene.dim)
        self.peak = (0.0, 0.0)  # (|F|, time)
        self.nodes_in_contact = 0

    def apply_grid(self, view, dt, time, remap):
        shift = self.vel * time
        self.nodes_in_contact = obstacle_apply(
            view.g_vel, view.g_mass, self.grid.origin, self.grid.h, view.lo, view.nloc, self.field,
            self.lat_origin, self.lat_shape, shift, self.vel, self.params.contact_layer, self.condition,
            self.params.friction, 1.0 / dt, self.moment_point, self.out)
        if remap:
            return  # forces are those of the first application in the step
        d = self.dim
        self.force = self.out[:d].copy()
        self.fn = self.out[d]
        self.ft = float(np.linalg.norm(self.out[:d] - self.out[d + 1:2 * d + 1]))
        self.moment = self.out[2 * d + 1:2 * d + 4].copy()
        mag = float(np.linalg.norm(self.force))
        if mag > self.peak[0]:
            self.peak = (mag, time + dt)

    def series(self):
        names = "xyz"[: self.dim]
        out = {f"{self.label}_f{c}": float(self.force[k]) for k, c in enumerate(names)}
        out[f"{self.label}_fn"] = float(getattr(self, "fn", 0.0))
        out[f"{self.label}_ft"] = float(getattr(self, "ft", 0.0))
        mom = getattr(self, "moment", np.zeros(3))
        for k, c in enumerate("xyz"):
            if self.dim == 3 or c == "z":
                out[f"{self.label}_m{c}"] = float(mom[k])
        return out

    def summary(self) -> str:
        unit = "N" if self.dim == 3 else "N/m"
        return f"obstacle '{self.label}': peak force {self.peak[0]:.4g} {unit} at t = {self.peak[1]:.4g} s"

    def state_dict(self) -> dict:
        return {"peak": list(self.peak), "force": self.force.tolist(), "fn": float(getattr(self, "fn", 0.0)),
                "ft": float(getattr(self, "ft", 0.0)), "moment": np.asarray(getattr(self, "moment", np.zeros(3))).tolist()}

    def load_state(self, state: dict) -> None:
        self.peak = tuple(state["peak"])
        self.force = np.asarray(state["force"], float)
        self.fn, self.ft = state["fn"], state["ft"]
        self.moment = np.asarray(state["moment"], float)
