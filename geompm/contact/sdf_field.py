"""A signed-distance field sampled on a lattice, and its (bi/tri)linear interpolation.

``sdf_lattice`` samples phi (positive outside, metres) and its gradient on a
regular lattice covering a box plus two spacings; ``interp_field`` interpolates
the flat (points, 1 + d) field at a point.  Shared by the grid contact
(base.py, lattice spacing h) and the particle guard (guard.py, finer).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def interp_field(field, prm, lat0, shape0, inv_h, w, x0, base0, frac0, val0, d):
    """Trilinear (bilinear in 2D) interpolation of the first k = d + 1 columns (phi, grad phi) of a flat
    lattice field (points, >= d + 1) at a point in d dimensions.

    Every vector is read at an offset, never sliced (a slice in a per-item
    function costs a reference count per call, contact.apply_condition): the
    lattice's first point [m] is prm[lat0:lat0 + d], its points per axis
    prm[shape0:shape0 + d]; the point is w[x0:x0 + d]; w[base0:base0 + d] and
    w[frac0:frac0 + d] are scratch; the k interpolated values go to
    w[val0:val0 + k].  A further column (the face ids of face_lattice_ids) is not interpolated."""
    k = d + 1
    for c in range(k):
        w[val0 + c] = 0.0
    for a in range(d):
        xi = (w[x0 + a] - prm[lat0 + a]) * inv_h
        i = int(math.floor(xi))
        i = min(max(i, 0), int(prm[shape0 + a]) - 2)
        w[base0 + a] = i
        w[frac0 + a] = min(max(xi - i, 0.0), 1.0)
    for corner in range(1 << d):
        wt = 1.0
        flat = 0
        for a in range(d):
            bit = (corner >> a) & 1
            wt *= w[frac0 + a] if bit else 1.0 - w[frac0 + a]
            flat = flat * int(prm[shape0 + a]) + int(w[base0 + a]) + bit
        if wt == 0.0:
            continue
        for c in range(k):
            w[val0 + c] += wt * field[flat, c]


@njit(cache=True, inline="always")
def nearest_point(prm, shape0, w, base0, frac0, d):
    """Flat index of the lattice point nearest to the point interp_field was last called at (from its
    base and fraction in w)."""
    flat = 0
    for a in range(d):
        flat = flat * int(prm[shape0 + a]) + int(w[base0 + a]) + (1 if w[frac0 + a] >= 0.5 else 0)
    return flat


def lattice_coords(lo, shape, h: float) -> np.ndarray:
    """The (points, d) coordinates [m] of a lattice with first point lo, points per axis shape, spacing h,
    in the flat order of the fields (the last axis fastest)."""
    axes = [lo[a] + h * np.arange(shape[a]) for a in range(len(lo))]
    return np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=1)


def nearest_faces(surface, pts: np.ndarray) -> np.ndarray:
    """Index of the face of ``surface`` (tessellate.Surface) nearest to each point (n, d): the 16 (2D: 4)
    faces with the nearest centres are candidates (cKDTree), and the exact point-triangle (point-segment)
    distance picks among them, so that a long thin face is not passed over for a neighbour whose centre
    is nearer."""
    from scipy.spatial import cKDTree

    d = pts.shape[1]
    verts = surface.vertices[surface.cells][:, :, :d]  # (faces, corners, d)
    k = min(16 if d == 3 else 4, len(verts))
    cand = cKDTree(verts.mean(axis=1)).query(pts, k=k)[1].reshape(len(pts), k)
    p = np.repeat(pts, k, axis=0)
    if d == 3:
        from trimesh.triangles import closest_point

        q = closest_point(verts[cand.ravel()], p)
    else:
        a, b = verts[cand.ravel(), 0], verts[cand.ravel(), 1]
        t = np.clip(((p - a) * (b - a)).sum(axis=1) / np.maximum(((b - a) ** 2).sum(axis=1), 1e-300), 0.0, 1.0)
        q = a + t[:, None] * (b - a)
    dist = ((q - p) ** 2).sum(axis=1).reshape(len(pts), k)
    return cand[np.arange(len(pts)), dist.argmin(axis=1)]


def face_lattice_ids(field: np.ndarray, lo, shape, h: float, surface, reach: float,
                     patch: float, inner: float = np.inf) -> np.ndarray:
    """The field with 2 (2D) or 4 (3D) more columns: the faces that share the force recorded at each lattice
    point with -inner <= phi <= reach [m] (-1 elsewhere: no contact force is recorded there).

    The point is projected on the surface, x - phi grad phi / |grad phi|^2, and its patch of width
    ``patch`` [m] (the cell size: a node's share of the surface) is sampled at +-patch/4 along each tangent;
    each sample takes its nearest face (nearest_faces), and the force is shared equally
    (contact/force.record_on_face).  A node on the edge between two faces thus gives half to each, where a
    single nearest face would give all to one (a hydrostatic plate's raw pressure alternated between 0
    and twice its value that way)."""
    d = len(lo)
    pts = lattice_coords(lo, shape, h)
    phi, grad = field[:, 0], field[:, 1:d + 1]
    signs = [(-1,), (1,)] if d == 2 else [(-1, -1), (-1, 1), (1, -1), (1, 1)]  # the samples, along the tangents
    ids = np.full((len(pts), len(signs)), -1.0)
    near = (phi <= reach) & (phi >= -inner)
    g = grad[near]
    g2 = np.maximum((g ** 2).sum(axis=1), 1e-300)
    proj = pts[near] - (phi[near] / g2)[:, None] * g
    n = g / np.sqrt(g2)[:, None]
    if d == 2:
        tangents = [np.stack([-n[:, 1], n[:, 0]], axis=1)]
    else:
        helper = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        t1 = np.cross(n, helper)
        t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
        tangents = [t1, np.cross(n, t1)]
    q = 0.25 * patch
    for c, sg in enumerate(signs):
        sample = proj + sum(s * q * t for s, t in zip(sg, tangents))
        ids[near, c] = nearest_faces(surface, sample)
    return np.ascontiguousarray(np.column_stack([field[:, :d + 1], ids]))


#: points whose signed distance is computed at once: bounds the sampling's transient memory
SAMPLE_CHUNK = 500_000


def lattice_bytes_per_point(d: int) -> int:
    """Peak bytes per lattice point while a field is built: coordinates and gradients (d each), phi, the
    stacked field (1 + d) and its copy with face ids (1 + d + 2^(d-1)), in float64."""
    return 8 * (d + d + 1 + 2 * (1 + d) + 2 ** (d - 1))


def lattice_extent(lo, hi, h):
    """(first point, points per axis) of the lattice sdf_lattice samples over [lo, hi] + 2 spacings."""
    lo = np.asarray(lo, float) - 2 * h
    hi = np.asarray(hi, float) + 2 * h
    return lo, np.ceil((hi - lo) / h).astype(np.int64) + 1


def lattice_size(lo, hi, h) -> float:
    """Points of that lattice, as a float (no overflow for absurd sizes): checked before it is built."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return float(np.prod(np.ceil((hi - lo + 4 * h) / h) + 1))


def sdf_lattice(sdf_fn, lo, hi, h):
    """Signed distance (positive outside) and its gradient on a lattice covering [lo, hi] + 2 cells,
    sampled SAMPLE_CHUNK points at a time."""
    lo, shape = lattice_extent(lo, hi, h)
    pts = lattice_coords(lo, shape, h)
    phi = np.empty(len(pts))
    for a in range(0, len(pts), SAMPLE_CHUNK):
        phi[a:a + SAMPLE_CHUNK] = np.asarray(sdf_fn(pts[a:a + SAMPLE_CHUNK]), dtype=float).ravel()
    del pts
    phi = phi.reshape(tuple(shape))
    grads = np.gradient(phi, h)
    grads = grads if isinstance(grads, (list, tuple)) else [grads]
    field = np.stack([phi] + list(grads), axis=-1).reshape(-1, len(lo) + 1)
    return np.ascontiguousarray(field), lo, shape
