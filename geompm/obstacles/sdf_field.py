"""A signed-distance field sampled on a lattice, and its (bi/tri)linear interpolation.

``sdf_lattice`` samples phi (positive outside, metres) and its gradient on a
regular lattice covering a box plus two spacings; ``interp_field`` interpolates
the flat (points, 1 + d) field at a point.  Shared by the grid contact
(base.py, lattice spacing h) and the particle guard (guard.py, finer).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def interp_field(field, lat_origin, inv_h, shape, x, base, frac, out):
    """Trilinear (bilinear in 2D) interpolation of a flat lattice field (points, k) at x (d,) into out (k,).

    ``lat_origin`` and ``shape`` (d,) the lattice's first point [m] and points per axis (any numeric
    sequences: slices of a stage's packed parameters); ``base`` and ``frac`` (d,) float scratch."""
    d = x.shape[0]
    k = field.shape[1]
    for c in range(k):
        out[c] = 0.0
    for a in range(d):
        xi = (x[a] - lat_origin[a]) * inv_h
        i = int(np.floor(xi))
        i = min(max(i, 0), int(shape[a]) - 2)
        base[a] = i
        frac[a] = min(max(xi - i, 0.0), 1.0)
    for corner in range(1 << d):
        w = 1.0
        flat = 0
        for a in range(d):
            bit = (corner >> a) & 1
            w *= frac[a] if bit else 1.0 - frac[a]
            flat = flat * int(shape[a]) + int(base[a]) + bit
        if w == 0.0:
            continue
        for c in range(k):
            out[c] += w * field[flat, c]


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
