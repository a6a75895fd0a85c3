"""Terrain from a DEM (GeoTIFF or ESRI ASCII grid): rigid ground with Coulomb friction and a force history, 3D.

The ground is the solid below the height field z = H(x, y), H bilinear
between the DEM's pixel centres (dem.py), in the case's frame: the DEM's map
coordinates [m].  Contact is the rule every rigid surface uses
(contact/rules.py: ``friction`` by default, ``slip``, ``fixed``) on the
nodes whose signed distance phi <= ``contact_layer``, and after G2P a
particle below the surface is put back on it (phi exact to the method below,
so none is deeper than its error); the momentum both remove is the terrain's
force history, as for an obstacle (recorded.py).

Signed distance from the height field (``terrain_phi``): start from the
point's vertical foot q = (x, y); take the tangent plane of the surface at
(q, H(q)), with unit normal n = (-H_x, -H_y, 1) / sqrt(1 + H_x^2 + H_y^2); the
point's distance to that plane is phi = (p - (q, H(q))) . n, and the plane's
closest point gives the next foot, q <- (p - phi n)_xy.  Three such steps.
On a plane the first is exact; on a curved surface the foot converges to
the closest point (the normal of the closest point passes through p).
tests/verification/test_terrain.py measures it against the exact distance to a
paraboloid.  A point above the surface (z > H(x, y)) is outside, one below
inside, exactly.  The vertical gap g = z - H(x, y) bounds the distance,
phi >= g cos(theta_max) (theta_max the steepest DEM slope), which lets most
nodes leave after one height lookup.

Outside the DEM (or its ``clip``) the edge heights continue; the DEM must
cover the grid's horizontal extent (or the clip).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numba import njit
from pydantic import Field

from geompm.errors import CaseError
from geompm.files.atomic import case_relative, unreadable_file
from geompm.contract.layout import param_layout
from geompm.contact.impact_params import ImpactParams
from geompm.contact.voellmy_params import VoellmyParams
from geompm.contract.stages import FAR_NODE
from geompm.contact.force import COUNT, DEPTH, FACES_GRID, FACES_GUARD, OBSTACLE, contact_and_record
from geompm.files.dem import bilinear, read_dem
from geompm.contact.recorded import ContactForceStage

#: the obstacle slots (contact/force.OBSTACLE) and the DEM's lattice: first pixel centre [m], pixel size [m],
#: pixels per axis, the cosine of its steepest slope
TERRAIN = param_layout(OBSTACLE, "dem_x0", "dem_y0", "dem_dx", "dem_dy", "dem_nx", "dem_ny", "cos_steepest",
                       "faces")  # faces: 1 when the force is spread on the DEM's triangles (surfaces writer)
T = TERRAIN
O_LAYER = OBSTACLE.layer
PROJECTIONS = 3  # tangent-plane steps of the signed distance


class TerrainParams(ImpactParams, VoellmyParams):
    dem: str = Field(description="DEM file relative to the case file (GeoTIFF, ESRI ASCII grid), heights [m]")
    clip: list[list[float]] | None = Field(
        None, description="[[xmin, ymin], [xmax, ymax]] in map coordinates [m]: use only this part of the DEM")
    condition: Literal["slip", "fixed", "friction", "voellmy"] = Field(
        "friction", description="Contact condition; 'voellmy': Coulomb 'friction' plus rho g u^2 / xi "
                                "(contact/voellmy.py)")
    friction: float = Field(0.0, ge=0.0, description="Coulomb coefficient mu [-] (conditions 'friction', 'voellmy')")
    contact_layer: float = Field(
        0.0, ge=0.0, description="Nodes with signed distance <= this [m] are in contact (0: on or below)")
    moment_point: list[float] | None = Field(None, description="Reference point of the moment [m]; default the "
                                                               "centre of the DEM region at its mean height")


@njit(cache=True, inline="always")
def _height(z, prm, x, y):
    return bilinear(z, prm[T.dem_x0], prm[T.dem_y0], prm[T.dem_dx], prm[T.dem_dy], x, y)


@njit(cache=True)  # a call: used by both rules, kept out of their loops' inlined bodies
def terrain_phi(z, prm, px, py, pz, w, n0):
    """Signed distance [m] of (px, py, pz) to the surface (positive above); its unit normal goes to
    w[n0:n0 + 3]."""
    nx, ny = int(prm[T.dem_nx]), int(prm[T.dem_ny])
    dx, dy = prm[T.dem_dx], prm[T.dem_dy]
    qx, qy = px, py
    phi = 0.0
    for _ in range(PROJECTIONS):
        fx = (qx - prm[T.dem_x0]) / dx
        fy = (qy - prm[T.dem_y0]) / dy
        i = min(max(int(math.floor(fx)), 0), nx - 2)
        j = min(max(int(math.floor(fy)), 0), ny - 2)
        tx = min(max(fx - i, 0.0), 1.0)
        ty = min(max(fy - j, 0.0), 1.0)
        z00, z10, z01, z11 = z[i, j], z[i + 1, j], z[i, j + 1], z[i + 1, j + 1]
        hq = (1 - tx) * (1 - ty) * z00 + tx * (1 - ty) * z10 + (1 - tx) * ty * z01 + tx * ty * z11
        hx = ((1 - ty) * (z10 - z00) + ty * (z11 - z01)) / dx
        hy = ((1 - tx) * (z01 - z00) + tx * (z11 - z10)) / dy
        s = math.sqrt(1.0 + hx * hx + hy * hy)
        n_x, n_y, n_z = -hx / s, -hy / s, 1.0 / s
        phi = (px - qx) * n_x + (py - qy) * n_y + (pz - hq) * n_z
        w[n0], w[n0 + 1], w[n0 + 2] = n_x, n_y, n_z
        qx, qy = px - phi * n_x, py - phi * n_y
    return phi


@njit(cache=True, inline="always")
def record_on_dem_faces(prm, px, py, w, f0, slot0, out):
    """Share the force w[f0:f0 + 3] among the DEM triangles under four samples of the point's patch, at
    +-h/4 in x and y (as sdf_field.face_lattice_ids for obstacles): the triangles of
    tessellate.heightfield_surface, cell c = ix (ny - 1) + iy split along its diagonal, c below it
    (fx >= fy), (nx - 1)(ny - 1) + c above."""
    nx, ny = int(prm[T.dem_nx]), int(prm[T.dem_ny])
    q = 0.25 * prm[OBSTACLE.spacing]
    cells = (nx - 1) * (ny - 1)
    for s in range(4):
        sx = px + (q if s & 1 else -q)
        sy = py + (q if s & 2 else -q)
        fx = (sx - prm[T.dem_x0]) / prm[T.dem_dx]
        fy = (sy - prm[T.dem_y0]) / prm[T.dem_dy]
        ix = min(max(int(math.floor(fx)), 0), nx - 2)
        iy = min(max(int(math.floor(fy)), 0), ny - 2)
        c = ix * (ny - 1) + iy
        face = c if fx - ix >= fy - iy else cells + c
        for a in range(3):
            out[slot0 + face * 3 + a] += 0.25 * w[f0 + a]


@njit(cache=True, inline="always")
def terrain_node_rule(prm, z, dt, x, m, v, v_old, f, pw, work, out):
    """Contact on one node; work: the node (0:3), the normal (3:6), two force scratch vectors (6:12)."""
    gap = x[2] - _height(z, prm, x[0], x[1])
    if gap * prm[T.cos_steepest] > prm[O_LAYER]:
        return  # phi >= gap cos(theta_max): not in contact
    phi = terrain_phi(z, prm, x[0], x[1], x[2], work, 3)
    if phi > prm[O_LAYER]:
        return
    for a in range(3):
        work[a] = x[a]
    if contact_and_record(v, work, 3, 0, 6, 9, prm, m, 1.0 / dt, pw, True, out, phi) and prm[T.faces] > 0.0:
        record_on_dem_faces(prm, x[0], x[1], work, 9, FACES_GRID, out)


@njit(cache=True, inline="always")
def terrain_guard_rule(prm, z, dt, k, x, x0, v, C, m, s, work, out):
    """A particle below the surface is put back on it (two projections along the normal) and gets the
    contact rule; its correction goes to the force (out[COUNT], out[DEPTH] as for obstacles)."""
    if x[2] >= _height(z, prm, x[0], x[1]):
        return  # above the height field: outside the ground, exactly
    phi = terrain_phi(z, prm, x[0], x[1], x[2], work, 3)
    out[DEPTH] = max(out[DEPTH], -phi)
    for _ in range(2):
        for a in range(3):
            x[a] -= phi * work[3 + a]
        phi = terrain_phi(z, prm, x[0], x[1], x[2], work, 3)
        if phi >= 0.0:
            break
    for a in range(3):
        work[a] = x[a]
    if contact_and_record(v, work, 3, 0, 6, 9, prm, m, 1.0 / dt, work, False, out, -math.inf):
        out[COUNT] += 1.0
        if prm[T.faces] > 0.0:
            record_on_dem_faces(prm, x[0], x[1], work, 9, FACES_GUARD, out)



class Terrain(ContactForceStage):
    holds_step = True  # its parameters follow the step and the time alone (engine/held_step.py)
    name = "terrain"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Rigid terrain from a DEM (GeoTIFF / ESRI ASCII grid): Coulomb friction, force history (3D)"
    Params = TerrainParams
    node_rule = terrain_node_rule
    node_scratch = 12
    particle_rule = terrain_guard_rule
    particle_scratch = 12
    kind = "terrain"
    provides_ground = True

    def ground_dem(self):
        return self.dem_path, f"{self.json_path}.dem"

    @classmethod
    def check(cls, params, case):
        if case.dimension != 3:
            return [("type", "a terrain needs a 3D case (a DEM is a surface z = H(x, y))")]
        if params.clip is not None and (len(params.clip) != 2 or any(len(c) != 2 for c in params.clip)
                                        or any(a >= b for a, b in zip(*params.clip))):
            return [("clip", "must be [[xmin, ymin], [xmax, ymax]] with xmin < xmax and ymin < ymax")]
        if params.moment_point is not None and len(params.moment_point) != 3:
            return [("moment_point", "must have 3 entries")]
        return []

    def setup(self, scene):
        self.start_recording(scene)
        g = scene.grid
        where = f"{self.json_path}.dem"
        path = case_relative(scene.base_dir, self.params.dem)
        self.dem_path = path
        problem = unreadable_file(path, self.params.dem)
        if problem:
            raise CaseError([(where, f"DEM {problem}")])
        lo, hi = g.origin[:2], g.upper[:2]
        if self.params.clip is not None:
            lo, hi = np.maximum(lo, self.params.clip[0]), np.minimum(hi, self.params.clip[1])
        dem = read_dem(path, where, (lo, hi))
        # the pixels' areas must cover the region (half a pixel beyond the outer centres)
        hx, hy = 0.5 * dem.dx * (1 + 1e-9), 0.5 * dem.dy * (1 + 1e-9)
        if dem.x0 - hx > lo[0] or dem.y0 - hy > lo[1] or dem.upper[0] + hx < hi[0] or dem.upper[1] + hy < hi[1]:
            raise CaseError([(where, f"the DEM's pixels cover x {dem.x0 - dem.dx / 2:.3f}..{dem.upper[0] + dem.dx / 2:.3f}, "
                                     f"y {dem.y0 - dem.dy / 2:.3f}..{dem.upper[1] + dem.dy / 2:.3f} m but the grid (or "
                                     f"clip) needs x {lo[0]:.3f}..{hi[0]:.3f}, y {lo[1]:.3f}..{hi[1]:.3f} m: enlarge "
                                     "the DEM or set 'clip'")])
        same = _same_crs(scene.crs, dem.crs)
        if same is not None:
            raise CaseError([(where, same)])
        self.dem = dem
        zx = np.diff(dem.z, axis=0) / dem.dx
        zy = np.diff(dem.z, axis=1) / dem.dy
        steepest = float(max(np.abs(zx).max(initial=0.0), np.abs(zy).max(initial=0.0)))
        cos_steepest = 1.0 / math.sqrt(1.0 + 2.0 * steepest ** 2)  # |grad H| <= sqrt(2) max(|H_x|, |H_y|)
        centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, float(dem.z.mean())])
        self.set_moment_point(centre)
        faces = self.faces_wanted(scene)
        extra = {"dem_x0": dem.x0, "dem_y0": dem.y0, "dem_dx": dem.dx, "dem_dy": dem.dy,
                 "dem_nx": dem.z.shape[0], "dem_ny": dem.z.shape[1], "cos_steepest": cos_steepest,
                 "faces": 1.0 if faces else 0.0}
        if faces:
            surf = self.surface()
            self.start_faces(surf, surf.normals())  # heightfield_surface's triangles face up, out of the ground
        self.prm = self.pack_obstacle({"lat": np.zeros(3), "shape": np.zeros(3), "shift": np.zeros(3),
                                       "vel": np.zeros(3)}, g.h, extra, TERRAIN)
        top = float(dem.z.max()) + self.params.contact_layer
        self.box = (np.full(3, -FAR_NODE, np.int64), np.full(3, FAR_NODE, np.int64))
        self.box[1][2] = int(math.floor((top - g.origin[2]) / g.h)) + 1  # no node above the highest ground

    def surface(self):
        """Two triangles per DEM cell, vertices at the pixel centres (the heights the contact interpolates)."""
        from geompm.contact.tessellate import heightfield_surface

        d = self.dem
        nx, ny = d.z.shape
        return heightfield_surface(d.x0 + d.dx * np.arange(nx), d.y0 + d.dy * np.arange(ny), d.z)

    def solid_depth(self, pts):
        """Depth below the ground, H(x, y) - z (the bilinear DEM the contact uses)."""
        return self.dem.height(pts[:, 0], pts[:, 1]) - pts[:, 2]

    def grid_args(self, dt, time, remap):
        return self.prm, self.dem.z

    def node_box(self, time):
        return self.box

    def particle_args(self, dt, time):
        return self.prm, self.dem.z


def _same_crs(case_crs, dem_crs):
    """Why the DEM's CRS does not match the case's, or None (also None when the case states none)."""
    if case_crs is None:
        return None
    from rasterio.crs import CRS
    from rasterio.errors import CRSError

    try:
        want = CRS.from_user_input(case_crs)
    except CRSError as exc:
        return f"the case's crs '{case_crs}' is not a coordinate reference system GDAL knows ({exc})"
    if dem_crs is None:
        return f"the DEM has no CRS but the case is in {case_crs}: assign it (gdal_edit.py -a_srs {case_crs})"
    if CRS.from_user_input(dem_crs) != want:
        return (f"the DEM is in {dem_crs} but the case is in {case_crs}: reproject the DEM "
                f"(gdalwarp -t_srs {case_crs}) or change 'crs'")
    return None
