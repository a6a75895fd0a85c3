"""Surface meshes of the rigid boundaries, for output (writers/surfaces.py) and face pressures.

Every function returns a ``Surface``: vertices (n, 3) [m] in the case's frame
(z = 0 in 2D) and cells (m, k) of one VTK kind, "triangle" in 3D and "line"
in 2D (a 2D obstacle is its outline in the x-y plane, per unit depth).  Faces
are refined so that no edge is longer than ``h``, the cell size: a face's
pressure is then an average over about one cell, the resolution of the grid
contact that produces it (docs/obstacles.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class Surface:
    vertices: np.ndarray  # (n, 3) [m]
    cells: np.ndarray  # (m, 3) triangles or (m, 2) lines, vertex indices
    kind: str  # "triangle" or "line"

    def centres(self) -> np.ndarray:
        return self.vertices[self.cells].mean(axis=1)

    def normals(self) -> np.ndarray:
        """Unit normal (m, 3) of each cell: the right-hand normal of a triangle (outward for the closed
        obstacles, whose faces are ordered counter-clockwise seen from outside), (dy, -dx) of a 2D segment
        (outward for outlines traversed counter-clockwise)."""
        p = self.vertices[self.cells]
        if self.kind == "line":
            t = p[:, 1] - p[:, 0]
            n = np.stack([t[:, 1], -t[:, 0], np.zeros(len(t))], axis=1)
        else:
            n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)

    def sizes(self) -> np.ndarray:
        """Face areas [m2] (triangles) or lengths [m] (lines: the area per metre of depth)."""
        p = self.vertices[self.cells]
        if self.kind == "line":
            return np.linalg.norm(p[:, 1] - p[:, 0], axis=1)
        return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


def _pad3(v: np.ndarray) -> np.ndarray:
    out = np.zeros((len(v), 3))
    out[:, : v.shape[1]] = v
    return out


def refine_triangles(vertices: np.ndarray, faces: np.ndarray, h: float) -> Surface:
    """Split triangles until no edge exceeds h (trimesh.remesh.subdivide_to_size)."""
    import trimesh

    v, f = trimesh.remesh.subdivide_to_size(np.asarray(vertices, float), np.asarray(faces, np.int64), max_edge=h,
                                            max_iter=30)
    return Surface(np.asarray(v, float), np.asarray(f, np.int64), "triangle")


def polyline(points: np.ndarray, h: float, closed: bool) -> Surface:
    """A 2D outline through ``points`` (k, 2), each segment split into pieces no longer than h."""
    pts = np.asarray(points, float)
    ends = np.vstack([pts[1:], pts[:1]]) if closed else pts[1:]
    out = []
    for a, b in zip(pts, ends):
        n = max(1, math.ceil(np.linalg.norm(b - a) / h - 1e-9))
        out.append(a + (b - a) * (np.arange(n) / n)[:, None])
    if not closed:
        out.append(pts[-1:])
    v = np.vstack(out)
    m = len(v)
    idx = np.arange(m if closed else m - 1)
    return Surface(_pad3(v), np.stack([idx, (idx + 1) % m], axis=1), "line")


def box_surface(lo, hi, h: float) -> Surface:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    if len(lo) == 2:
        return polyline(np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]]), h, closed=True)
    import trimesh

    box = trimesh.creation.box(extents=hi - lo)
    box.apply_translation(0.5 * (lo + hi))
    return refine_triangles(box.vertices, box.faces, h)


def sphere_surface(center, radius: float, h: float) -> Surface:
    c = np.asarray(center, float)
    if len(c) == 2:
        n = max(32, math.ceil(4.0 * math.pi * radius / h))  # perimeter within 0.2 %
        a = 2.0 * math.pi * np.arange(n) / n
        return polyline(c + radius * np.stack([np.cos(a), np.sin(a)], axis=1), h, closed=True)
    import trimesh

    # an icosphere's edge is about 1.1 r / 2^k: the smallest k that reaches h, then split to h
    k = min(7, max(1, math.ceil(math.log2(max(1.0, 1.1 * radius / h)))))
    s = trimesh.creation.icosphere(subdivisions=k, radius=radius)
    return refine_triangles(s.vertices + c, s.faces, h)


def cylinder_surface(center, radius: float, axis: str, length: float, h: float) -> Surface:
    import trimesh

    sections = max(32, math.ceil(4.0 * math.pi * radius / h))  # circumference within 0.2 %
    cyl = trimesh.creation.cylinder(radius=radius, height=length, sections=sections)  # along z
    rot = {"x": trimesh.transformations.rotation_matrix(math.pi / 2, [0, 1, 0]),
           "y": trimesh.transformations.rotation_matrix(-math.pi / 2, [1, 0, 0]), "z": np.eye(4)}[axis]
    cyl.apply_transform(rot)
    return refine_triangles(cyl.vertices + np.asarray(center, float), cyl.faces, h)


def plane_surface(point, normal, lo, hi, h: float) -> Surface | None:
    """The plane n.(x - p) = 0 clipped to the box [lo, hi]: a segment in 2D, a convex polygon (fanned into
    triangles) in 3D; None where the plane misses the box."""
    p, n = np.asarray(point, float), np.asarray(normal, float)
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    d = len(p)
    corners = np.array(np.meshgrid(*[[lo[a], hi[a]] for a in range(d)], indexing="ij")).reshape(d, -1).T
    s = (corners - p) @ n
    pts = []
    for i in range(len(corners)):
        for j in range(i + 1, len(corners)):
            if np.count_nonzero(corners[i] != corners[j]) != 1:
                continue  # box edges join corners differing in one coordinate
            si, sj = s[i], s[j]
            if si * sj < 0.0:
                pts.append(corners[i] + si / (si - sj) * (corners[j] - corners[i]))
        if s[i] == 0.0:
            pts.append(corners[i])
    if len(pts) < d:
        return None
    pts = np.unique(np.round(np.array(pts), 12), axis=0)
    if d == 2:
        t = np.array([-n[1], n[0]])
        order = np.argsort(pts @ t)
        return polyline(pts[[order[0], order[-1]]], h, closed=False)
    c = pts.mean(axis=0)
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    ang = np.arctan2((pts - c) @ w, (pts - c) @ u)
    ring = pts[np.argsort(ang)]
    verts = np.vstack([c, ring])
    k = len(ring)
    faces = np.stack([np.zeros(k, np.int64), 1 + np.arange(k), 1 + (np.arange(k) + 1) % k], axis=1)
    return refine_triangles(verts, faces, h)


def heightfield_surface(xs: np.ndarray, ys: np.ndarray, z: np.ndarray) -> Surface:
    """Two triangles per cell of a height field: z (nx, ny) at xs (nx,), ys (ny,) [m] (dem.Dem's layout)."""
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    verts = np.stack([X.ravel(), Y.ravel(), np.asarray(z, float).ravel()], axis=1)
    nx, ny = z.shape
    i = (np.arange(nx - 1)[:, None] * ny + np.arange(ny - 1)[None, :]).ravel()
    tri = np.concatenate([np.stack([i, i + ny, i + ny + 1], axis=1), np.stack([i, i + ny + 1, i + 1], axis=1)])
    return Surface(verts, tri.astype(np.int64), "triangle")
