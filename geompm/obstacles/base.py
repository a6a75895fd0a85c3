"""Rigid obstacles: grid contact through a signed-distance field, and the force history.

At set-up each obstacle samples its signed distance phi (positive outside,
metres) on a lattice of spacing h in its own frame, covering its bounding box
plus two cells.  Each step every window node within the obstacle's reach is
looked up (trilinear interpolation; exact on static obstacles whose lattice
coincides with the grid), and nodes with phi <= ``contact_layer`` get the
contact rule of contact/rules.py with the outward normal grad(phi)/|grad(phi)|,
applied to the velocity relative to the obstacle's prescribed velocity
(velocity-based grid contact of rigid-boundary MPM; Bardenhagen et al. 2000).

The force history, its normal and tangential parts and the moment are kept by
recorded.ContactForceStage (shared with the terrain).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numba import njit
from pydantic import Field

from geompm.errors import CaseError
from geompm.contact.impact_params import ImpactParams
from geompm.contact.voellmy_params import VoellmyParams
from geompm.contract.plugin import Params, vector_length_problems
from geompm.mpm.memory import require_memory
from geompm.contact.force import FACES_GRID, OBSTACLE, contact_and_record, record_on_face
from geompm.contact.guard import guard_rule, guard_spacing
from geompm.contact.recorded import ContactForceStage
from geompm.contact.sdf_field import face_lattice_ids, interp_field, lattice_bytes_per_point, lattice_size, sdf_lattice

O = OBSTACLE


class ObstacleParams(ImpactParams, VoellmyParams):
    condition: Literal["slip", "fixed", "friction", "voellmy"] = Field(
        "friction", description="Contact condition; 'voellmy': Coulomb 'friction' plus rho g u^2 / xi on the nodes "
                                "within one cell behind the contact layer (contact/voellmy.py)")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (conditions 'friction', 'voellmy')")
    velocity: list[float] | None = Field(None, description="Prescribed translational velocity [m/s]")
    contact_layer: float = Field(
        0.0, ge=0.0, description="Nodes with signed distance <= this [m] are in contact (0: on or inside)")
    moment_point: list[float] | None = Field(None, description="Reference point of the moment [m]; default the "
                                                               "centre of the obstacle's bounding box")
    drainage: Literal["impermeable", "drained"] = Field(
        "impermeable", description="For saturated soil: 'impermeable' keeps the pore pressure against the obstacle "
                                   "(it counts as filled for the free surface); 'drained' (a permeable or slit dam) "
                                   "lets the water leave through it, p = 0 at its face (docs/pore-water.md)")


@njit(cache=True, inline="always")
def obstacle_node_rule(prm, field, dt, x, m, v, v_old, f, pw, work, out):
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
    interp_field(field, prm, O.lat_x, O.shape_x, 1.0 / hl, work, xf, base, frac, val, d)
    if work[val] > prm[O.layer]:
        return
    for a in range(d):
        work[nrm + a] = work[val + 1 + a]
    if contact_and_record(v, work, nrm, xf, bef, fo, prm, m, 1.0 / dt, pw, True, out, work[val]):
        record_on_face(field, prm, work, base, frac, fo, d, FACES_GRID, out)


#: lattice points of one obstacle's guard field (8 doubles each in 3D with the face ids: 1.3 GB); the spacing
#: coarsens towards half the thinnest part to fit, and an obstacle that needs more is refused
GUARD_POINTS_MAX = 2e7


class RigidObstacle(ContactForceStage):
    """Base of every rigid obstacle: subclasses give ``bounds()``, ``signed_distance(points)`` and, where
    they can, ``thinnest()``.

    A grid stage (contact on nodes) and a particle stage (the penetration
    guard of guard.py, after G2P); the force history is the sum of both."""
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)

    Params = ObstacleParams
    #: the rules are this base's (a subclass gives host-side geometry only): checked against the CPU under
    #: numba-cuda's simulator (tests/cuda/cuda_parity.py)
    backends = ("cpu", "cuda")
    node_rule = obstacle_node_rule
    node_scratch = 7 * 3 + 1
    particle_rule = guard_rule
    particle_scratch = 8 * 3 + 1

    @classmethod
    def check(cls, params, case):
        problems = vector_length_problems(params, case, ("velocity", "moment_point"))
        if params.drainage == "drained" and not any(m.pore_water is not None for m in case.materials.values()):
            problems.append(("drainage", "a drained obstacle lets pore water through, but no material of the case "
                                         "has pore_water: remove 'drainage' (or give a material pore_water)"))
        return problems

    def drained_layer(self):
        return self.params.contact_layer if self.params.drainage == "drained" else None

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def signed_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance [m] of points (m, d), positive outside the obstacle."""
        raise NotImplementedError

    def thinnest(self) -> float | None:
        """Thickness of the obstacle's thinnest part [m], or None if unknown."""
        return None

    def solid_depth(self, pts):
        return -self.signed_distance(pts)

    def setup(self, scene):
        self.start_recording(scene)
        lo, hi = self.bounds()
        if np.any(hi < scene.grid.origin) or np.any(lo > scene.grid.upper):
            raise CaseError([(self.json_path, f"obstacle '{self.label}' lies outside the grid "
                                              f"({lo} .. {hi} m against {scene.grid.origin} .. {scene.grid.upper} m)")])
        h = scene.grid.h
        self.thickness = self.thinnest()
        self.guard_h = self._guard_spacing(lo, hi, h)
        self.field, self.lat_origin, self.lat_shape = sdf_lattice(self.signed_distance, lo, hi, h)
        self.guard_field, self.guard_origin, self.guard_shape = sdf_lattice(
            self.signed_distance, lo - h, hi + h, self.guard_h)
        if self.params.velocity is not None:
            self.vel = np.asarray(self.params.velocity, float)
        self.set_moment_point(0.5 * (lo + hi))
        if self.faces_wanted(scene):
            self._spread_on_faces(h)
        self.grid_prm = self._pack(self.lat_origin, self.lat_shape, h)
        self.guard_prm = self._pack(self.guard_origin, self.guard_shape, self.guard_h)

    def _guard_spacing(self, lo, hi, h) -> float:
        """The guard lattice's spacing (guard.guard_spacing), coarsened by 1.25 at a time while the lattice
        exceeds GUARD_POINTS_MAX points and the spacing stays below half the thinnest part; both lattices'
        memory checked against resources.memory_cap() before either is built (CaseError, exit 2)."""
        d = self.dim
        size = float(np.max(hi - lo))
        per_point = lattice_bytes_per_point(d)
        contact = lattice_size(lo, hi, h)
        require_memory(contact * per_point, self.json_path,
                       f"obstacle '{self.label}' ({size:.3g} m across) sampled every cell (h = {h:g} m): its "
                       f"contact lattice of {contact:.3g} points",
                       "check the obstacle's unit (scale) and size, or use a coarser grid.cell_size")
        hs = guard_spacing(h, self.thickness)
        coarsest = np.inf if self.thickness is None else 0.5 * self.thickness
        while lattice_size(lo - h, hi + h, hs) > GUARD_POINTS_MAX and hs * 1.25 <= coarsest:
            hs *= 1.25
        points = lattice_size(lo - h, hi + h, hs)
        thin = "" if self.thickness is None else f", {self.thickness:.3g} m thick at its thinnest"
        remedy = ("thicken the obstacle's thinnest part (or check its unit: scale), or use a coarser "
                  "grid.cell_size; the guard samples an obstacle at h / 4 and at a third of its thinnest part")
        if points > GUARD_POINTS_MAX:
            raise CaseError([(self.json_path, f"obstacle '{self.label}' ({size:.3g} m across{thin}) needs a "
                                              f"penetration-guard lattice of {points:.3g} points at spacing "
                                              f"{hs:.3g} m, more than {GUARD_POINTS_MAX:.3g} "
                                              f"({points * per_point / 2**30:.3g} GiB); {remedy}")])
        kept = contact * 8 * (1 + d + 2 ** (d - 1))
        require_memory(kept + points * per_point, self.json_path,
                       f"obstacle '{self.label}' ({size:.3g} m across{thin}): its penetration-guard lattice of "
                       f"{points:.3g} points at spacing {hs:.3g} m", remedy)
        return hs

    def _spread_on_faces(self, h):
        """Face ids on both lattices (sdf_field.face_lattice_ids): every contact node (phi <= contact_layer;
        its nearest lattice point within h sqrt(d) / 2 more) and every guard correction (on the surface:
        |phi| <= 2 hs at its nearest lattice point) finds its face.  Normals are turned out of the solid
        where the mesh's winding says otherwise (phi > 0 just outside)."""
        surf = self.surface()
        n = surf.normals()
        c = surf.centres()[:, :self.dim]
        out = self.signed_distance(c + 1e-3 * h * n[:, :self.dim]) > self.signed_distance(c - 1e-3 * h * n[:, :self.dim])
        n[~out] *= -1.0
        reach = self.params.contact_layer + h * np.sqrt(self.dim)
        self.field = face_lattice_ids(self.field, self.lat_origin, self.lat_shape, h, surf, reach, h)
        self.guard_field = face_lattice_ids(self.guard_field, self.guard_origin, self.guard_shape, self.guard_h,
                                            surf, 2.0 * self.guard_h, h, inner=2.0 * self.guard_h)
        self.start_faces(surf, n)

    def _pack(self, lat_origin, lat_shape, spacing):
        return self.pack_obstacle({"lat": lat_origin, "shape": lat_shape, "shift": np.zeros(self.dim),
                                   "vel": self.vel}, spacing)

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

    def particle_args(self, dt, time):
        return self._shifted(self.guard_prm, time + dt), self.guard_field

    def particle_reach(self, prm, lo, hi):
        """Skip the guard when the particles' box lies beside its lattice (moved with the obstacle) along an
        axis: the rule's first test, computed here in its own arithmetic (monotone in the position), then
        sends every particle away.  When the guard runs, a particle it puts back may move anywhere near
        the surface: the box is then unknown."""
        hs = prm[O.spacing]
        for a in range(len(lo)):
            first = prm[O.lat_x + a]
            last = first + (prm[O.shape_x + a] - 1.0) * hs
            if hi[a] - prm[O.shift_x + a] < first or lo[a] - prm[O.shift_x + a] > last:
                return None
        return super().particle_reach(prm, lo, hi)

    def warnings(self) -> list[str]:
        h = self.grid.h
        t = self.thickness
        if t is None or t >= 2.0 * h:
            return []
        return [f"obstacle '{self.label}' ({self.json_path}) is {t:.3g} m thick at its thinnest, {t / h:.2f} "
                f"cells: grid contact alone would miss it; the particle guard keeps debris out, but the "
                f"contact force is resolved only with grid.cell_size <= {t / 2:.3g} m (two cells across)"]
