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
from ..layout import pack_in_layout
from ..plugin import Params, vector_length_problems
from ..stages import OBSTACLE as OBSTACLE_PHASE
from ..stages import GridStage, ParticleStage
from .contact_force import COUNT, DEPTH, FORCE_SLOTS, OBSTACLE, contact_and_record
from .guard import guard_rule, guard_spacing, lattice_points
from .sdf_field import interp_field, sdf_lattice

O = OBSTACLE


class ObstacleParams(Params):
    condition: Literal["slip", "fixed", "friction"] = Field("friction", description="Contact condition")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (condition 'friction')")
    velocity: list[float] | None = Field(None, description="Prescribed translational velocity [m/s]")
    contact_layer: float = Field(
        0.0, ge=0.0, description="Nodes with signed distance <= this [m] are in contact (0: on or inside)")
    moment_point: list[float] | None = Field(None, description="Reference point of the moment [m]; default the "
                                                               "centre of the obstacle's bounding box")


@njit(cache=True, inline="always")
def obstacle_node_rule(prm, field, dt, x, m, v, v_old, f, work, out):
    """Contact on one node; ``field`` the contact lattice (points, 1 + d); out[0:d] force on the
    obstacle, out[d] f_n, out[d+1:2d+1] sum f_n n, out[2d+1:2d+4] moment (3 components).  ``work``
    holds, at offsets of d: the node in the obstacle's frame, the normal, two force scratch vectors,
    the interpolation's base and fraction, and its d + 1 values (phi, grad phi)."""
    d = x.shape[0]
    hl = prm[O.spacing]
    for a in range(d):
        xa = x[a] - prm[O.shift_x + a]
        lo = prm[O.lat_x + a]
        if xa < lo or xa > lo + (prm[O.shape_x + a] - 1.0) * hl:
            return
        work[a] = xa
    xf, nrm, bef, fo, base, frac, val = 0, d, 2 * d, 3 * d, 4 * d, 5 * d, 6 * d
    interp_field(field, prm, O.lat_x, O.shape_x, 1.0 / hl, work, xf, base, frac, val)
    if work[val] > prm[O.layer]:
        return
    for a in range(d):
        work[nrm + a] = work[val + 1 + a]
    contact_and_record(v, work, nrm, xf, bef, fo, prm, m, 1.0 / dt, out)


GUARD_POINTS_MAX = 2e7  # lattice points of one obstacle's guard field (4 doubles each in 3D: 640 MB)


class RigidObstacle(GridStage, ParticleStage):
    """Base of every rigid obstacle: subclasses give ``bounds()``, ``signed_distance(points)`` and, where
    they can, ``thinnest()``.

    A grid stage (contact on nodes) and a particle stage (the penetration
    guard of guard.py, after G2P); the force history is the sum of both."""

    Params = ObstacleParams
    phase = OBSTACLE_PHASE
    node_rule = obstacle_node_rule
    node_scratch = 7 * 3 + 1
    node_reduction = FORCE_SLOTS
    particle_rule = guard_rule
    particle_scratch = 8 * 3 + 1
    particle_reduction = DEPTH + 1

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
        self.grid_prm = self._pack(self.lat_origin, self.lat_shape, h)
        self.guard_prm = self._pack(self.guard_origin, self.guard_shape, self.guard_h)
        self.grid_out = np.zeros(FORCE_SLOTS)  # the grid pass of this step (MUSL's second pass is not counted)
        self.force = np.zeros(scene.dim)
        self.peak = (0.0, 0.0)  # (|F|, time)
        self.fn = self.ft = 0.0  # normal and tangential force magnitudes [N, N/m in 2D]
        self.moment = np.zeros(3)
        self.particles_put_back = 0  # by the guard, over the run
        self.max_depth = 0.0  # deepest penetration the guard corrected [m]

    def _pack(self, lat_origin, lat_shape, spacing):
        d = self.dim
        vec = {}
        for name, value in (("lat", lat_origin), ("shape", lat_shape), ("shift", np.zeros(d)), ("vel", self.vel),
                            ("moment", self.moment_point)):
            full = np.zeros(3)
            full[:d] = value
            vec.update({f"{name}_{c}": full[k] for k, c in enumerate("xyz")})
        vec.update(spacing=spacing, layer=self.params.contact_layer, condition=CONDITIONS[self.params.condition],
                   mu=self.params.friction)
        return pack_in_layout(OBSTACLE, vec, f"stage '{self.label}'")

    def _shifted(self, prm, time):
        prm[O.shift_x:O.shift_x + self.dim] = self.vel * time
        return prm

    def grid_args(self, dt, time, remap):
        return self._shifted(self.grid_prm, time), self.field

    def node_box(self, time):
        """The contact lattice's nodes, moved with the obstacle."""
        h, origin = self.grid.h, self.grid.origin
        lo = self.lat_origin + self.vel * time
        first = np.floor((lo - origin) / h).astype(np.int64)
        last = np.ceil((lo + (self.lat_shape - 1) * h - origin) / h).astype(np.int64)
        return first, last

    def grid_reduced(self, out, dt, time, remap):
        if not remap:  # forces are those of the first application in the step; the guard's are added
            self.grid_out[:] = out.sum(axis=0)

    def particle_args(self, dt, time):
        return self._shifted(self.guard_prm, time + dt), self.guard_field

    def particle_reduced(self, out, dt, time):
        d = self.dim
        self.max_depth = max(self.max_depth, float(out[:, DEPTH].max()))
        self.particles_put_back += int(round(out[:, COUNT].sum()))
        total = self.grid_out + out[:, :FORCE_SLOTS].sum(axis=0)
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
