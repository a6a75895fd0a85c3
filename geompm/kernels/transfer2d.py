"""P2G and G2P specialised for 2D (plane strain): the transfers of the reference tests/support/reference_transfer.py
with the stencil as two nested loops, weights and APIC terms built up axis by
axis (see transfer3d.py for the scheme, the stencil tag, the interleaved
private grids, the folded force and MLS).  Same results to rounding as
tests/support/reference_transfer.py with split force.
"""

import numpy as np
from numba import njit, prange

from geompm.kernels.chunks import CHUNK_BODY, FAR, g2p_chunks, sum_interleaved, zero_rows
from geompm.kernels.stencil import APIC, FLIP, MLS, axis_stencil, mls_derivatives
from geompm.kernels.volume import update_volume


@njit(parallel=True, fastmath=True, cache=True)
def p2g_2d(tag, scheme, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
           c_grid, split, f_scale, mls_dinv, g_mass, g_mom, g_force):
    """2D P2G: m_i, APIC momentum and f_i = -sum V_p sigma_p grad w (see tests/reference_transfer.p2g).

    ``c_grid`` rows are [m, (mv)_x, (mv)_y, f_x, f_y]; ``split`` and ``f_scale`` as in
    transfer3d.p2g_3d (folded: (mv)_i += f_scale f_i, g_force not written); MLS (``scheme``):
    the MLS-MPM force through the pseudo-derivatives of stencil.mls_derivatives.
    """
    nchunks = c_grid.shape[0]
    for c in prange(nchunks):
        _p2g_chunk_2d(np.uint64(c), nchunks, tag, scheme, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind,
                      lo, nloc, c_grid[c], g_mass.shape[0], split, f_scale, mls_dinv)
    sum_interleaved(c_grid, split, g_mass, g_mom, g_force)


@njit(**CHUNK_BODY)
def _p2g_chunk_2d(c, nchunks, tag, scheme, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
                  g, nn, split, f_scale, mls_dinv):
    """P2G of chunk c of nchunks (a contiguous range of particles) into its private grid g, its first nn rows
    zeroed first: the body of p2g_2d's parallel loop (chunks.CHUNK_BODY)."""
    n = p_x.shape[0]
    width = g.shape[1]
    S = len(tag)
    mls = len(scheme) - 1 == MLS  # compile-time (stencil.scheme_tag)
    inv_h = 1.0 / h
    sx = nloc[1]
    zero_rows(g, nn, width)
    for p in range(c * n // nchunks, (c + 1) * n // nchunks):
        bx, wx, dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
        by, wy, dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
        m = p_mass[p]
        ox = bx * h + origin[0] - p_x[p, 0]
        oy = by * h + origin[1] - p_x[p, 1]
        if mls:
            dx = mls_derivatives(wx, ox, h, mls_dinv)
            dy = mls_derivatives(wy, oy, h, mls_dinv)
        q0 = m * (p_v[p, 0] + p_C[p, 0, 0] * ox + p_C[p, 0, 1] * oy)
        q1 = m * (p_v[p, 1] + p_C[p, 1, 0] * ox + p_C[p, 1, 1] * oy)
        mh = m * h
        ax0, ax1 = mh * p_C[p, 0, 0], mh * p_C[p, 1, 0]
        ay0, ay1 = mh * p_C[p, 0, 1], mh * p_C[p, 1, 1]
        nv = -p_vol[p] * f_scale
        sxx, syy, sxy = nv * p_stress[p, 0], nv * p_stress[p, 1], nv * p_stress[p, 3]
        base = (bx - lo[0]) * sx + (by - lo[1])
        for i in range(S):
            wi = wx[i]
            dwi = dx[i]
            qi0, qi1 = q0 + i * ax0, q1 + i * ax1
            # node (i, j): force sx_i w_j + sy_i dw_j per component
            fx0, fx1 = dwi * sxx, dwi * sxy
            fy0, fy1 = wi * sxy, wi * syy
            idx = base + i * sx
            for j in range(S):
                wt = wi * wy[j]
                r = g[idx + j]
                f0 = fx0 * wy[j] + fy0 * dy[j]
                f1 = fx1 * wy[j] + fy1 * dy[j]
                r[0] += wt * m
                if split:
                    r[1] += wt * (qi0 + j * ay0)
                    r[2] += wt * (qi1 + j * ay1)
                    r[3] += f0
                    r[4] += f1
                else:
                    r[1] += wt * (qi0 + j * ay0) + f0
                    r[2] += wt * (qi1 + j * ay1) + f1


@njit(parallel=True, fastmath=True, cache=True)
def g2p_2d(tag, scheme, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
           origin, h, kind, lo, nloc, dt, flip_ratio, apic_dinv, set_velocity, move, do_gradient, p_box):
    """2D G2P (see tests/reference_transfer.g2p); L keeps its 3x3 plane-strain form (z row and column zero).
    With ``move``, ``p_box[c, :, :2]`` the box of chunk c's moved particles, as in g2p_3d."""
    nchunks = g2p_chunks(p_x.shape[0])
    for c in prange(nchunks):
        _g2p_chunk_2d(np.uint64(c), nchunks, tag, scheme, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
                      origin, h, kind, lo, nloc, dt, flip_ratio, apic_dinv, set_velocity, move, do_gradient, p_box)


@njit(**CHUNK_BODY)
def _g2p_chunk_2d(c, nchunks, tag, scheme, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
                  origin, h, kind, lo, nloc, dt, flip_ratio, apic_dinv, set_velocity, move, do_gradient, p_box):
    """G2P of chunk c of nchunks (a contiguous range of particles), and its row of ``p_box``: the body of
    g2p_2d's parallel loop (chunks.CHUNK_BODY)."""
    n = p_x.shape[0]
    S = len(tag)
    mode = len(scheme) - 1  # compile-time (stencil.scheme_tag)
    inv_h = 1.0 / h
    sx = nloc[1]
    L = np.zeros((3, 3))
    lo0 = lo1 = FAR  # finite: the kernel's fastmath assumes no infinities
    hi0 = hi1 = -FAR
    for p in range(c * n // nchunks, (c + 1) * n // nchunks):
        bx, wx, dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
        by, wy, dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
        base = (bx - lo[0]) * sx + (by - lo[1])
        v0 = v1 = d0 = d1 = 0.0
        l00 = l01 = l10 = l11 = 0.0
        b00 = b01 = b10 = b11 = 0.0  # B[:, a] = sum w v_i * (node step along axis a)
        for i in range(S):
            wi = wx[i]
            dwi = dx[i]
            idx = base + i * sx
            s0 = s1 = t0 = t1 = 0.0
            for j in range(S):
                wt = wi * wy[j]
                u0 = g_vel[idx + j, 0]
                u1 = g_vel[idx + j, 1]
                s0 += wt * u0
                s1 += wt * u1
                t0 += j * wt * u0
                t1 += j * wt * u1
                gx = dwi * wy[j]
                gy = wi * dy[j]
                l00 += u0 * gx
                l01 += u0 * gy
                l10 += u1 * gx
                l11 += u1 * gy
            v0 += s0
            v1 += s1
            b00 += i * s0
            b10 += i * s1
            b01 += t0
            b11 += t1
        if mode == FLIP and set_velocity:  # FLIP increment, a pass of its own (see transfer3d)
            for i in range(S):
                idx = base + i * sx
                for j in range(S):
                    wt = wx[i] * wy[j]
                    d0 += wt * (g_vel[idx + j, 0] - g_vel_old[idx + j, 0])
                    d1 += wt * (g_vel[idx + j, 1] - g_vel_old[idx + j, 1])
        ox = bx * h + origin[0] - p_x[p, 0]
        oy = by * h + origin[1] - p_x[p, 1]
        if mode == MLS:  # MLS: L = C = (v o^T + h B) D^-1
            l00, l01 = (v0 * ox + h * b00) * apic_dinv, (v0 * oy + h * b01) * apic_dinv
            l10, l11 = (v1 * ox + h * b10) * apic_dinv, (v1 * oy + h * b11) * apic_dinv
        if set_velocity:
            if mode == FLIP:
                p_v[p, 0] = flip_ratio * (p_v[p, 0] + d0) + (1.0 - flip_ratio) * v0
                p_v[p, 1] = flip_ratio * (p_v[p, 1] + d1) + (1.0 - flip_ratio) * v1
            else:
                p_v[p, 0] = v0
                p_v[p, 1] = v1
            if (mode == APIC or mode == MLS) and S > 2:  # APIC needs D: linear hats fall back to C = L
                p_C[p, 0, 0] = (v0 * ox + h * b00) * apic_dinv
                p_C[p, 0, 1] = (v0 * oy + h * b01) * apic_dinv
                p_C[p, 1, 0] = (v1 * ox + h * b10) * apic_dinv
                p_C[p, 1, 1] = (v1 * oy + h * b11) * apic_dinv
            elif mode == APIC:
                p_C[p, 0, 0], p_C[p, 0, 1], p_C[p, 1, 0], p_C[p, 1, 1] = l00, l01, l10, l11
            else:
                p_C[p, 0, 0] = p_C[p, 0, 1] = p_C[p, 1, 0] = p_C[p, 1, 1] = 0.0
        if move:
            p_x[p, 0] += dt * v0
            p_x[p, 1] += dt * v1
            lo0, hi0 = min(lo0, p_x[p, 0]), max(hi0, p_x[p, 0])
            lo1, hi1 = min(lo1, p_x[p, 1]), max(hi1, p_x[p, 1])
        if do_gradient:
            L[0, 0], L[0, 1], L[1, 0], L[1, 1] = l00, l01, l10, l11
            update_volume(p, p_L, p_vol, p_rho, p_mass, L, dt)
    if move:
        p_box[c, 0, 0], p_box[c, 0, 1] = lo0, lo1
        p_box[c, 1, 0], p_box[c, 1, 1] = hi0, hi1
