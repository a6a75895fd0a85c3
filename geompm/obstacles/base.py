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

from ..boundaries.contact import CONDITIONS
from ..errors import CaseError
from ..plugin import Params, vector_length_problems
from ..stages import OBSTACLE, GridStage, ParticleStage
from .contact_force import contact_and_record
from .guard import guard_particles, guard_spacing, lattice_points
from .sdf_field import interp_field, sdf_lattice


class ObstacleParams(Params):
    condition: Literal["slip", "fixed", "friction"] = Field("friction", description="Contact condition")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (condition 'friction')")
    velocity: list[float] | None = Field(None, description="Prescribed translational velocity [m/s]")
    contact_layer: float = Field(
        0.0, ge=0.0, description="Nodes with signed distance <= this [m] are in contact (0: on or inside)")
    moment_point: list[float] | None = Field(None, description="Reference point of the moment [m]; default the "
                                                               "centre of the obstacle's bounding box")


@njit(cache=True)
def obstacle_apply(g_vel, g_mass, origin, h, lo, nloc, field, lat_origin, lat_shape, shift, vel, layer,
                   condition, mu, inv_dt, moment_point, out):
    """Contact on window nodes; out[0:d] force on the obstacle, out[d] f_n, out[d+1:2d+1] sum f_n n,
    out[2d+1:2d+4] moment (3 components)."""
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
        interp_field(field, lat_origin, inv_h, lat_shape, x, base, frac, val)
        if val[0] > layer:
            continue
        for a in range(d):
            normal[a] = val[1 + a]
        contact_and_record(g_vel, idx, normal, vel, condition, mu, m, inv_dt, x, shift, moment_point, before, f, out)


GUARD_POINTS_MAX = 2e7  # lattice points of one obstacle's guard field (4 doubles each in 3D: 640 MB)


class RigidObstacle(GridStage, ParticleStage):
    """Base of every rigid obstacle: subclasses give ``bounds()``, ``signed_distance(points)`` and, where
    they can, ``thinnest()``.

    A grid stage (contact on nodes) and a particle stage (the penetration
    guard of guard.py, after G2P); the force history is the sum of both."""

    Params = ObstacleParams
    phase = OBSTACLE

    @classmethod
    def check(cls, params, case):
        return vector_length_problems(params, case, ("velocity", "moment_point"))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def signed_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance [m] of points (m, d), positive outside the obstacle."""
        raise NotImplementedError

    def thinnest(self) -> float | None:
        """Thickness of the obstacle's thinnest part [m], or None if unknown."""
        return None

    def setup(self, scene):
        self.dim = scene.dim
        self.grid = scene.grid
        lo, hi = self.bounds()
        if np.any(hi < scene.grid.origin) or np.any(lo > scene.grid.upper):
            raise CaseError([(self.json_path, f"obstacle '{self.label}' lies outside the grid "
                                              f"({lo} .. {hi} m against {scene.grid.origin} .. {scene.grid.upper} m)")])
        h = scene.grid.h
        self.field, self.lat_origin, self.lat_shape = sdf_lattice(self.signed_distance, lo, hi, h)
        self.thickness = self.thinnest()
        self.guard_h = guard_spacing(h, self.thickness)
        # the guard lattice reaches h + 2 hs beyond the obstacle: any segment that can touch it (|v| dt < h)
        while lattice_points(lo, hi, self.guard_h, h + 2 * self.guard_h) > GUARD_POINTS_MAX:
            self.guard_h *= 1.25
        self.guard_field, self.guard_origin, self.guard_shape = sdf_lattice(
            self.signed_distance, lo - h, hi + h, self.guard_h)
        v = self.params.velocity
        self.vel = np.zeros(scene.dim) if v is None else np.asarray(v, float)
        mp = self.params.moment_point
        self.moment_point = 0.5 * (lo + hi) if mp is None else np.asarray(mp, float)
        self.condition = CONDITIONS[self.params.condition]
        self.out = np.zeros(2 * scene.dim + 4)
        self.remap_out = np.zeros_like(self.out)  # MUSL's second application: not counted
        self.guard_out = np.zeros(2 * scene.dim + 5)
        self.force = np.zeros(scene.dim)
        self.peak = (0.0, 0.0)  # (|F|, time)
        self.fn = self.ft = 0.0  # normal and tangential force magnitudes [N, N/m in 2D]
        self.moment = np.zeros(3)
        self.particles_put_back = 0  # by the guard, over the run
        self.max_depth = 0.0  # deepest penetration the guard corrected [m]

    def apply_grid(self, view, dt, time, remap):
        shift = self.vel * time
        obstacle_apply(
            view.g_vel, view.g_mass, self.grid.origin, self.grid.h, view.lo, view.nloc, self.field,
            self.lat_origin, self.lat_shape, shift, self.vel, self.params.contact_layer, self.condition,
            self.params.friction, 1.0 / dt, self.moment_point, self.remap_out if remap else self.out)
        # forces are those of the first application in the step; apply_particles adds the guard's

    def apply_particles(self, state, dt, time):
        shift = self.vel * (time + dt)
        depth = guard_particles(state.p_x, state.p_v, state.p_mass, dt, self.guard_field, self.guard_origin,
                                self.guard_h, self.guard_shape, shift, self.vel, self.condition,
                                self.params.friction, self.moment_point, self.guard_out)
        self.max_depth = max(self.max_depth, depth)
        self.particles_put_back += int(self.guard_out[-1])
        d = self.dim
        total = self.out + self.guard_out[:-1]
        self.force = total[:d].copy()
        self.fn = total[d]
        self.ft = float(np.linalg.norm(total[:d] - total[d + 1:2 * d + 1]))
        self.moment = total[2 * d + 1:2 * d + 4].copy()
        mag = float(np.linalg.norm(self.force))
        if mag > self.peak[0]:
            self.peak = (mag, time + dt)

    def supplied_speed(self) -> float:
        return float(np.linalg.norm(self.vel))

    def peak_force(self):
        return self.peak

    def warnings(self) -> list[str]:
        h = self.grid.h
        t = self.thickness
        if t is None or t >= 2.0 * h:
            return []
        return [f"obstacle '{self.label}' ({self.json_path}) is {t:.3g} m thick at its thinnest, {t / h:.2f} "
                f"cells: grid contact alone would miss it; the particle guard keeps debris out, but the "
                f"contact force is resolved only with grid.cell_size <= {t / 2:.3g} m (two cells across)"]

    def series(self):
        names = "xyz"[: self.dim]
        out = {f"{self.label}_f{c}": float(self.force[k]) for k, c in enumerate(names)}
        out[f"{self.label}_fn"] = float(self.fn)
        out[f"{self.label}_ft"] = float(self.ft)
        for k, c in enumerate("xyz"):
            if self.dim == 3 or c == "z":
                out[f"{self.label}_m{c}"] = float(self.moment[k])
        return out

    def summary(self) -> str:
        unit = "N" if self.dim == 3 else "N/m"
        guard = (f"; {self.particles_put_back} particle corrections by the guard (deepest {self.max_depth:.3g} m "
                 f"= {self.max_depth / self.grid.h:.2f} h before correction)" if self.particles_put_back else "")
        return f"obstacle '{self.label}': peak force {self.peak[0]:.4g} {unit} at t = {self.peak[1]:.4g} s{guard}"

    def state_dict(self) -> dict:
        return {"peak": list(self.peak), "force": self.force.tolist(), "fn": float(self.fn), "ft": float(self.ft),
                "moment": np.asarray(self.moment).tolist(),
                "particles_put_back": self.particles_put_back, "max_depth": self.max_depth}

    def load_state(self, state: dict) -> None:
        self.peak = tuple(state["peak"])
        self.force = np.asarray(state["force"], float)
        self.fn, self.ft = state["fn"], state["ft"]
        self.moment = np.asarray(state["moment"], float)
        self.particles_put_back = int(state.get("particles_put_back", 0))
        self.max_depth = float(state.get("max_depth", 0.0))
