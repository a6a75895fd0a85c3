"""The thinnest part of a closed triangle mesh [m]: the shortest inward chord from a face's centre.

From the centre of every face a ray is cast into the solid, along the inward
normal -n, starting a small offset delta inside the face (1e-6 of the mesh's
bounding-box diagonal).  The first face it leaves the solid through (a hit
whose outward normal points along the ray, n_hit . d > 0; the face of origin
excluded) ends the chord; the thinnest part is the shortest chord over all
faces, t + delta.  That is exact for the faceted mesh of a box, a prism or a
plate (parallel faces), gives the diameter of a cylinder (2 r cos(pi / k) for
k sections: the distance between opposite flats) and of a sphere, the tube's
diameter of a torus and the wall of a thin shell.

Rays are tested against the triangles (Moller & Trumbore 1997, J. Graphics
Tools 2(1):21) held in a uniform grid of bins over the mesh's bounding box
and walked bin by bin (Amanatides & Woo 1987, Eurographics '87: 3-10), so
the cost is about one bin row per ray and the memory a few integers per
(triangle, bin) pair, bounded before anything is allocated.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

#: (triangle, bin) pairs the bin grid may hold (8 bytes each): bins are coarsened until it fits
MAX_BIN_ENTRIES = 20_000_000
#: the ray's start, inside the face, as a fraction of the mesh's bounding-box diagonal
OFFSET = 1e-6
#: a face whose area is below this fraction of the diagonal squared is degenerate: neither origin nor target
DEGENERATE_AREA = 1e-14


@njit(cache=True)
def _bin_range(tri_lo, tri_hi, lo, inv_b, nb, out):
    for a in range(3):
        i0 = int(math.floor((tri_lo[a] - lo[a]) * inv_b[a]))
        i1 = int(math.floor((tri_hi[a] - lo[a]) * inv_b[a]))
        out[a] = min(max(i0, 0), nb[a] - 1)
        out[3 + a] = min(max(i1, 0), nb[a] - 1)


@njit(cache=True)
def _bin_entries(tri, lo, inv_b, nb, counts, fill, ids):
    """Walk every (triangle, bin) pair of the triangles' bounding boxes; tri (f, 3, 3).  With ``ids`` of
    length 0: count the triangles of each bin into counts (flat bins); else write each triangle's id at
    fill[bin] (the CSR start of the bin, advanced as it fills).  Returns the number of pairs."""
    r = np.empty(6, np.int64)
    total = 0
    counting = ids.shape[0] == 0
    for f in range(tri.shape[0]):
        tlo = np.minimum(np.minimum(tri[f, 0], tri[f, 1]), tri[f, 2])
        thi = np.maximum(np.maximum(tri[f, 0], tri[f, 1]), tri[f, 2])
        _bin_range(tlo, thi, lo, inv_b, nb, r)
        for i in range(r[0], r[3] + 1):
            for j in range(r[1], r[4] + 1):
                for k in range(r[2], r[5] + 1):
                    b = (i * nb[1] + j) * nb[2] + k
                    if counting:
                        counts[b] += 1
                    else:
                        ids[fill[b]] = f
                        fill[b] += 1
                    total += 1
    return total


@njit(cache=True, inline="always")
def _hit(tri, f, o, d):
    """Distance along the ray o + t d to triangle f (Moller-Trumbore), or inf."""
    e1x, e1y, e1z = tri[f, 1, 0] - tri[f, 0, 0], tri[f, 1, 1] - tri[f, 0, 1], tri[f, 1, 2] - tri[f, 0, 2]
    e2x, e2y, e2z = tri[f, 2, 0] - tri[f, 0, 0], tri[f, 2, 1] - tri[f, 0, 1], tri[f, 2, 2] - tri[f, 0, 2]
    px, py, pz = d[1] * e2z - d[2] * e2y, d[2] * e2x - d[0] * e2z, d[0] * e2y - d[1] * e2x
    det = e1x * px + e1y * py + e1z * pz
    if det == 0.0:
        return np.inf
    inv = 1.0 / det
    sx, sy, sz = o[0] - tri[f, 0, 0], o[1] - tri[f, 0, 1], o[2] - tri[f, 0, 2]
    u = (sx * px + sy * py + sz * pz) * inv
    if u < 0.0 or u > 1.0:
        return np.inf
    qx, qy, qz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
    v = (d[0] * qx + d[1] * qy + d[2] * qz) * inv
    if v < 0.0 or u + v > 1.0:
        return np.inf
    t = (e2x * qx + e2y * qy + e2z * qz) * inv
    return t if t > 0.0 else np.inf


@njit(cache=True)
def _chord(tri, normals, valid, f0, o, d, lo, bsize, nb, start, ids):
    """Distance from o along d to the first face the ray leaves the solid through (inf if none): a walk
    through the bins the ray crosses, stopping once the nearest hit lies within the bins walked."""
    cell = np.empty(3, np.int64)
    step = np.empty(3, np.int64)
    t_next = np.empty(3)
    t_delta = np.empty(3)
    for a in range(3):
        c = int(math.floor((o[a] - lo[a]) / bsize[a]))
        cell[a] = min(max(c, 0), nb[a] - 1)
        if d[a] > 0.0:
            step[a] = 1
            t_next[a] = (lo[a] + (cell[a] + 1) * bsize[a] - o[a]) / d[a]
            t_delta[a] = bsize[a] / d[a]
        elif d[a] < 0.0:
            step[a] = -1
            t_next[a] = (lo[a] + cell[a] * bsize[a] - o[a]) / d[a]
            t_delta[a] = -bsize[a] / d[a]
        else:
            step[a] = 0
            t_next[a] = np.inf
            t_delta[a] = np.inf
    best = np.inf
    while True:
        b = (cell[0] * nb[1] + cell[1]) * nb[2] + cell[2]
        for e in range(start[b], start[b + 1]):
            f = ids[e]
            if f == f0 or not valid[f]:
                continue
            if normals[f, 0] * d[0] + normals[f, 1] * d[1] + normals[f, 2] * d[2] <= 0.0:
                continue  # an entry into the solid, or a face along the ray: not where the chord ends
            t = _hit(tri, f, o, d)
            if t < best:
                best = t
        a = 0
        if t_next[1] < t_next[a]:
            a = 1
        if t_next[2] < t_next[a]:
            a = 2
        if best <= t_next[a]:
            return best
        cell[a] += step[a]
        if cell[a] < 0 or cell[a] >= nb[a]:
            return best
        t_next[a] += t_delta[a]


@njit(cache=True, parallel=True)
def _all_chords(tri, normals, valid, origins, lo, bsize, nb, start, ids):
    out = np.full(tri.shape[0], np.inf)
    for f in prange(tri.shape[0]):
        if valid[f]:
            d = -normals[f]
            out[f] = _chord(tri, normals, valid, f, origins[f], d, lo, bsize, nb, start, ids)
    return out


def bin_grid(tri: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """(bin size (3,), bins per axis (3,), CSR start, triangle ids): about one triangle per bin, coarsened
    (counted first, nothing allocated) until the (triangle, bin) pairs fit MAX_BIN_ENTRIES."""
    span = np.maximum(hi - lo, 1e-12 * max(float(np.max(hi - lo)), 1e-300))
    per_axis = max(1.0, len(tri) ** (1.0 / 3.0))
    while True:
        bsize = span.max() / per_axis * np.ones(3)
        nb = np.maximum(np.ceil(span / bsize), 1).astype(np.int64)
        counts = np.zeros(int(nb.prod()) + 1, np.int64)
        total = _bin_entries(tri, lo, 1.0 / bsize, nb, counts[1:], counts[:0], np.zeros(0, np.int64))
        if total <= MAX_BIN_ENTRIES or per_axis <= 1.0:
            break
        per_axis = max(1.0, per_axis / 2.0)
    start = np.cumsum(counts)
    ids = np.empty(int(start[-1]), np.int64)
    _bin_entries(tri, lo, 1.0 / bsize, nb, counts[:0], start[:-1].copy(), ids)
    return bsize, nb, start, ids


def face_chords(vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray | None = None) -> np.ndarray:
    """The inward chord [m] of every face (inf where the ray leaves through no face, or the face is
    degenerate); normals (f, 3) outward, from the winding if not given."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    tri = np.ascontiguousarray(v[np.asarray(faces, np.int64)])
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area2 = np.linalg.norm(cross, axis=1)
    lo, hi = v.min(axis=0), v.max(axis=0)
    diag = float(np.linalg.norm(hi - lo))
    valid = area2 > 2.0 * DEGENERATE_AREA * diag * diag
    if normals is None:
        normals = cross / np.maximum(area2, 1e-300)[:, None]
    normals = np.ascontiguousarray(normals, dtype=np.float64)
    delta = OFFSET * diag
    origins = np.ascontiguousarray(tri.mean(axis=1) - delta * normals)
    bsize, nb, start, ids = bin_grid(tri, lo, hi)
    return _all_chords(tri, normals, valid, origins, lo, bsize, nb, start, ids) + delta


def thinnest_part(vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray | None = None) -> float | None:
    """The shortest inward chord of a closed mesh [m]; None where no ray found an exit (not a closed
    surface)."""
    if len(faces) == 0:
        return None
    chords = face_chords(vertices, faces, normals)
    finite = chords[np.isfinite(chords)]
    return float(finite.min()) if len(finite) else None
