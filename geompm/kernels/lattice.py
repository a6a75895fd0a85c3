"""Heights on a regular lattice, bilinear between its points (a DEM's pixel centres: files/dem.py; a
phreatic surface's lattice: mpm/phreatic_surface.py)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def bilinear(z, x0, y0, dx, dy, x, y):
    """Height [m] at (x, y) between the pixel centres of z (nx, ny), the edge heights continued beyond."""
    nx, ny = z.shape
    fx = (x - x0) / dx
    fy = (y - y0) / dy
    i = min(max(int(math.floor(fx)), 0), nx - 2)
    j = min(max(int(math.floor(fy)), 0), ny - 2)
    tx = min(max(fx - i, 0.0), 1.0)
    ty = min(max(fy - j, 0.0), 1.0)
    return ((1 - tx) * (1 - ty) * z[i, j] + tx * (1 - ty) * z[i + 1, j] + (1 - tx) * ty * z[i, j + 1]
            + tx * ty * z[i + 1, j + 1])


@njit(cache=True)
def heights(z, x0, y0, dx, dy, xs, ys):
    out = np.empty(xs.shape[0])
    for p in range(xs.shape[0]):
        out[p] = bilinear(z, x0, y0, dx, dy, xs[p], ys[p])
    return out


@njit(cache=True, inline="always")
def trilinear(v, x0, y0, z0, h, x, y, z):
    """v (nx, ny, nz) at x0 + i h, y0 + j h, z0 + k h, trilinear at (x, y, z), the edge values continued beyond."""
    nx, ny, nz = v.shape
    fx, fy, fz = (x - x0) / h, (y - y0) / h, (z - z0) / h
    i = min(max(int(math.floor(fx)), 0), nx - 2)
    j = min(max(int(math.floor(fy)), 0), ny - 2)
    k = min(max(int(math.floor(fz)), 0), nz - 2)
    tx, ty, tz = min(max(fx - i, 0.0), 1.0), min(max(fy - j, 0.0), 1.0), min(max(fz - k, 0.0), 1.0)
    out = 0.0
    for a in range(2):
        wa = tx if a else 1.0 - tx
        for b in range(2):
            wb = ty if b else 1.0 - ty
            for c in range(2):
                wc = tz if c else 1.0 - tz
                out += wa * wb * wc * v[i + a, j + b, k + c]
    return out
