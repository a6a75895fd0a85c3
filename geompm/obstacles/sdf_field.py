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
def interp_field(field, prm, lat0, shape0, inv_h, w, x0, base0, frac0, val0):
    """Trilinear (bilinear in 2D) interpolation of a flat lattice field (points, k) at a point.

    Every vector is read at an offset, never sliced (a slice in a per-item
    function costs a reference count per call, contact.apply_condition): the
    lattice's first point [m] is prm[lat0:lat0 + d], its points per axis
    prm[shape0:shape0 + d]; the point is w[x0:x0 + d]; w[base0:base0 + d] and
    w[frac0:frac0 + d] are scratch; the k interpolated values go to
    w[val0:val0 + k].  d is the field's column count minus one."""
    k = field.shape[1]
    d = k - 1
    for c in range(k):
        w[val0 + c] = 0.0
    for a in range(d):
        xi = (w[x0 + a] - prm[lat0 + a]) * inv_h
        i = int(np.floor(xi))
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
