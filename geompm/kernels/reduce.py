"""Reductions over particles: node-index bounding box, speeds, energies."""

import math

import numpy as np
from numba import njit, prange


@njit(parallel=True, cache=True)
def cell_bounds(p_x, origin, inv_h):
    """Per axis, min and max of floor((x - origin)/h) over particles: (2, d) int64."""
    n, d = p_x.shape
    nchunks = max(1, min(n, 256))
    part = np.empty((nchunks, 2, d), np.int64)
    for c in prange(nchunks):
        for a in range(d):
            part[c, 0, a] = 2 ** 62
            part[c, 1, a] = -(2 ** 62)
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            for a in range(d):
                xi = (p_x[p, a] - origin[a]) * inv_h
                if not math.isfinite(xi):
                    xi = 1e18
                i = math.floor(xi) if abs(xi) < 1e17 else (2 ** 61 if xi > 0 else -(2 ** 61))
                part[c, 0, a] = min(part[c, 0, a], i)
                part[c, 1, a] = max(part[c, 1, a], i)
    out = np.empty((2, d), np.int64)
    for a in range(d):
        out[0, a] = part[:, 0, a].min()
        out[1, a] = part[:, 1, a].max()
    return out


@njit(parallel=True, cache=True)
def kinetic_energy(p_mass, p_v):
    """sum 0.5 m |v|^2 [J, or J/m in plane strain]."""
    n, d = p_v.shape
    e = 0.0
    for p in prange(n):
        s = 0.0
        for a in range(d):
            s += p_v[p, a] * p_v[p, a]
        e += 0.5 * p_mass[p] * s
    return e


@njit(parallel=True, cache=True)
def max_speed(p_v):
    n, d = p_v.shape
    vmax = 0.0
    for p in prange(n):
        s = 0.0
        for a in range(d):
            s += p_v[p, a] * p_v[p, a]
        vmax = max(vmax, s)
    return math.sqrt(vmax)


@njit(parallel=True, cache=True)
def max_coordinate(p_x, axis):
    m = -np.inf
    for p in prange(p_x.shape[0]):
        m = max(m, p_x[p, axis])
    return m


@njit(cache=True)
def first_outside(p_x, lo_bound, hi_bound):
    """Index of the first particle outside [lo_bound, hi_bound] (or NaN), else -1."""
    n, d = p_x.shape
    for p in range(n):
        for a in range(d):
            x = p_x[p, a]
            if not (lo_bound[a] <= x <= hi_bound[a]):
                return p
    return -1


@njit(parallel=True, cache=True)
def max_projection(p_x, origin, direction):
    """max over particles of (x_p - origin) . direction [m]."""
    n, d = p_x.shape
    m = -np.inf
    for p in prange(n):
        s = 0.0
        for a in range(d):
            s += (p_x[p, a] - origin[a]) * direction[a]
        m = max(m, s)
    return m
