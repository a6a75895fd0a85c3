"""The semi-implicit step's pressure system on the CPU: assembled from the particles into a band per node,
compressed to the unknown nodes' CSR rows, and the increment's forces scattered back (projection.py for the
equations).

The scatters are race-free without private grids: the particles are grouped by the cell of their stencil's
first node and the cells coloured by that node's index modulo the stencil's width S per axis (S^d colours).
Two cells of one colour are at least S nodes apart along some axis, so their particles' stencils share no
node: each colour's cells run in parallel, the colours one after the other.  A node's band holds its
(2S - 1)^d neighbours' coefficients (the pairs two stencils can couple): 9 / 25 / 49 entries per node in 2D,
27 / 125 / 343 in 3D for linear / quadratic / cubic shape functions.  The system has a row per window node,
the nodes without an unknown increment (dp = 0) as identity rows.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from geompm.schemes.saturated.kernels import node_index, particle_stencil


@njit(parallel=True, cache=True)
def stencil_keys(p_x, origin, h, kind, lo, nloc, S, keys):
    """keys[p] = colour * nn + the window index of particle p's stencil's first node (module docstring)."""
    d = p_x.shape[1]
    nn = 1
    for a in range(d):
        nn *= nloc[a]
    inv_h = 1.0 / h
    for p in prange(p_x.shape[0]):
        b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
        colour = (b[0] % S) * S + (b[1] % S)
        if d == 3:
            colour = colour * S + (b[2] % S)
        keys[p] = colour * nn + node_index(b, lo, nloc, 0, 0, 0, d)


def colour_groups(keys: np.ndarray, nn: int, colours: int):
    """(order, cell starts, colour starts): the particles ordered by key, where each cell's particles begin
    in ``order`` (one more entry, the end), and where each colour's cells begin (colours + 1 entries)."""
    order = np.argsort(keys, kind="stable")
    ordered = keys[order]
    if ordered.size == 0:
        return order, np.zeros(1, np.int64), np.zeros(colours + 1, np.int64)
    starts = np.concatenate(([0], np.flatnonzero(np.diff(ordered)) + 1, [ordered.size])).astype(np.int64)
    colour_of_cell = ordered[starts[:-1]] // nn
    colour_starts = np.searchsorted(colour_of_cell, np.arange(colours + 1)).astype(np.int64)
    return order, starts, colour_starts


@njit(cache=True, inline="always")
def band_offset(di, dj, dk, S, d):
    W = 2 * S - 1
    o = (di + S - 1) * W + (dj + S - 1)
    if d == 3:
        o = o * W + (dk + S - 1)
    return o


@njit(parallel=True, cache=True)
def assemble_band(tag, order, starts, colour_starts, p_x, p_vol, p_coef, p_store, p_div, dt, origin, h, kind, lo,
                  nloc, band, rhs):
    """band[I, o] += sum_p V (dt^2 c grad N_I . grad N_J + n/K_w N_I [I = J]) and rhs[I] += -dt sum_p V N_I
    div u* over the particles (projection.py), band and rhs zeroed by the caller; o the offset of J from I
    (band_offset).  Each particle's stencil is tabulated once (weights, gradients, nodes, offsets) and each
    pair I <= J computed once, added to both rows."""
    S = len(tag)
    d = p_x.shape[1]
    Sz = S if d == 3 else 1
    K = S * S * Sz
    W = 2 * S - 1
    centre = band_offset(0, 0, 0, S, d)
    inv_h = 1.0 / h
    for col in range(colour_starts.shape[0] - 1):
        for cell in prange(colour_starts[col], colour_starts[col + 1]):
            na = np.empty(K)
            g0 = np.empty(K)
            g1 = np.empty(K)
            g2 = np.zeros(K)
            node = np.empty(K, np.int64)
            pos = np.empty(K, np.int64)  # the node's place in the stencil as a band offset from its first node
            for q in range(starts[cell], starts[cell + 1]):
                p = order[q]
                if p_coef[p] == 0.0 and p_store[p] == 0.0:
                    continue
                b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
                m = 0
                for i in range(S):
                    for j in range(S):
                        for k in range(Sz):
                            na[m] = wx[i] * wy[j] * wz[k]
                            g0[m] = dx[i] * wy[j] * wz[k]
                            g1[m] = wx[i] * dy[j] * wz[k]
                            if d == 3:
                                g2[m] = wx[i] * wy[j] * dz[k]
                            node[m] = node_index(b, lo, nloc, i, j, k, d)
                            pos[m] = (i * W + j) * W + k if d == 3 else i * W + j
                            m += 1
                v = p_vol[p]
                cc = dt * dt * p_coef[p] * v
                st = p_store[p] * v
                rd = -dt * v * p_div[p]
                for a in range(K):
                    ia = node[a]
                    rhs[ia] += rd * na[a]
                    band[ia, centre] += st * na[a] + cc * (g0[a] * g0[a] + g1[a] * g1[a] + g2[a] * g2[a])
                    for c in range(a + 1, K):
                        val = cc * (g0[a] * g0[c] + g1[a] * g1[c] + g2[a] * g2[c])
                        off = pos[c] - pos[a]
                        band[ia, centre + off] += val
                        band[node[c], centre - off] += val


@njit(cache=True, inline="always")
def neighbour(i, di, dj, dk, nloc, d):
    """The window index of node i's neighbour at offset (di, dj, dk), or -1 outside the window."""
    if d == 2:
        x, y = i // nloc[1] + di, i % nloc[1] + dj
        if x < 0 or y < 0 or x >= nloc[0] or y >= nloc[1]:
            return -1
        return x * nloc[1] + y
    x = i // (nloc[1] * nloc[2]) + di
    y = (i // nloc[2]) % nloc[1] + dj
    z = i % nloc[2] + dk
    if x < 0 or y < 0 or z < 0 or x >= nloc[0] or y >= nloc[1] or z >= nloc[2]:
        return -1
    return (x * nloc[1] + y) * nloc[2] + z


@njit(parallel=True, cache=True)
def band_row_counts(band, unknown, nloc, S, counts):
    """counts[I]: the entries of node I's row in the window's system: its nonzero couplings to unknown nodes
    where it is unknown itself (unknown[I] = 1), 1 (the identity: dp = 0) where it is not."""
    d = nloc.shape[0]
    Sz = S if d == 3 else 1
    for i in prange(unknown.shape[0]):
        if unknown[i] == 0:
            counts[i] = 1
            continue
        c = 0
        for di in range(1 - S, S):
            for dj in range(1 - S, S):
                for dk in range(1 - Sz, Sz):
                    j = neighbour(i, di, dj, dk, nloc, d)
                    if j >= 0 and unknown[j] != 0 and band[i, band_offset(di, dj, dk, S, d)] != 0.0:
                        c += 1
        counts[i] = c


@njit(parallel=True, cache=True)
def band_csr_fill(band, unknown, nloc, S, indptr, indices, data):
    """The CSR rows of the window's system (after band_row_counts and its cumulative sum ``indptr``), columns
    in ascending order: one row per window node, so that its size (and a preconditioner built for it) lasts
    while the window does, whichever nodes the water reaches."""
    d = nloc.shape[0]
    Sz = S if d == 3 else 1
    for i in prange(unknown.shape[0]):
        at = indptr[i]
        if unknown[i] == 0:
            indices[at] = i
            data[at] = 1.0
            continue
        for di in range(1 - S, S):
            for dj in range(1 - S, S):
                for dk in range(1 - Sz, Sz):
                    j = neighbour(i, di, dj, dk, nloc, d)
                    if j >= 0 and unknown[j] != 0:
                        v = band[i, band_offset(di, dj, dk, S, d)]
                        if v != 0.0:
                            indices[at] = j
                            data[at] = v
                            at += 1


@njit(parallel=True, cache=True)
def increment_forces(tag, order, starts, colour_starts, p_x, p_vol, p_n, p_wmass, g_dp, origin, h, kind, lo, nloc,
                     g_f):
    """g_f[I] = (-sum_p V N_I grad dp, -sum_p V n N_I grad dp over the particles holding water), grad dp the
    nodal increment's gradient at each particle: the increment's forces on the mixture and on the water
    (projection.node_correct_one), zeroed by the caller.  This form (not integrated by parts) has no
    boundary term: a node that a particle's stencil barely reaches takes the mean of its particles' gradients
    over its mass, not a boundary traction over a vanishing mass."""
    S = len(tag)
    d = p_x.shape[1]
    Sz = S if d == 3 else 1
    inv_h = 1.0 / h
    for col in range(colour_starts.shape[0] - 1):
        for cell in prange(colour_starts[col], colour_starts[col + 1]):
            for q in range(starts[cell], starts[cell + 1]):
                p = order[q]
                b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
                g0 = g1 = g2 = 0.0
                for i in range(S):
                    for j in range(S):
                        for k in range(Sz):
                            v = g_dp[node_index(b, lo, nloc, i, j, k, d)]
                            g0 += dx[i] * wy[j] * wz[k] * v
                            g1 += wx[i] * dy[j] * wz[k] * v
                            if d == 3:
                                g2 += wx[i] * wy[j] * dz[k] * v
                if g0 == 0.0 and g1 == 0.0 and g2 == 0.0:
                    continue
                f = -p_vol[p]
                fw = f * p_n[p] if p_wmass[p] > 0.0 else 0.0
                for i in range(S):
                    for j in range(S):
                        for k in range(Sz):
                            ia = node_index(b, lo, nloc, i, j, k, d)
                            na = wx[i] * wy[j] * wz[k]
                            g_f[ia, 0] += f * na * g0
                            g_f[ia, 1] += f * na * g1
                            g_f[ia, d] += fw * na * g0
                            g_f[ia, d + 1] += fw * na * g1
                            if d == 3:
                                g_f[ia, 2] += f * na * g2
                                g_f[ia, 5] += fw * na * g2
