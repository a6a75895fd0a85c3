"""P2G and G2P specialised for 2D (plane strain): the transfers of transfer.py
with the stencil as two nested loops, weights and APIC terms built up axis by
axis (see transfer3d.py for the scheme).  Same arrays, arguments and results
to rounding as transfer.py.
"""

import numpy as np
from numba import njit, prange

from .chunks import sum_chunks, zero_chunk
from .shape import axis_weights, support
from .volume import update_volume


@njit(parallel=True, fastmath=True, cache=True)
def p2g_2d(p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
           c_mass, c_mom, c_force, with_force, g_mass, g_mom, g_force):
    """2D P2G: m_i, APIC momentum and f_i = -sum V_p sigma_p grad w (see transfer.p2g)."""
    n = p_x.shape[0]
    nchunks = c_mass.shape[0]
    nn = g_mass.shape[0]
    S = support(kind)
    inv_h = 1.0 / h
    sx = nloc[1]
    for c in prange(nchunks):
        cm = c_mass[c]
        cp = c_mom[c]
        cf = c_force[c]
        zero_chunk(cm, cp, cf, nn)
        w = np.empty((2, 4))
        dw = np.empty((2, 4))
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            bx = axis_weights((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h, w[0], dw[0])
            by = axis_weights((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h, w[1], dw[1])
            m = p_mass[p]
            ox = bx * h + origin[0] - p_x[p, 0]
            oy = by * h + origin[1] - p_x[p, 1]
            C = p_C[p]
            q0 = m * (p_v[p, 0] + C[0, 0] * ox + C[0, 1] * oy)
            q1 = m * (p_v[p, 1] + C[1, 0] * ox + C[1, 1] * oy)
            mh = m * h
            ax0, ax1 = mh * C[0, 0], mh * C[1, 0]
            ay0, ay1 = mh * C[0, 1], mh * C[1, 1]
            nv = -p_vol[p]
            sxx, syy, sxy = nv * p_stress[p, 0], nv * p_stress[p, 1], nv * p_stress[p, 3]
            base = (bx - lo[0]) * sx + (by - lo[1])
            for i in range(S):
                wi = w[0, i]
                dwi = dw[0, i]
                qi0, qi1 = q0 + i * ax0, q1 + i * ax1
                idx = base + i * sx
                for j in range(S):
                    wt = wi * w[1, j]
                    cm[idx + j] += wt * m
                    cp[idx + j, 0] += wt * (qi0 + j * ay0)
                    cp[idx + j, 1] += wt * (qi1 + j * ay1)
                    if with_force:
                        gx = dwi * w[1, j]
                        gy = wi * dw[1, j]
                        cf[idx + j, 0] += sxx * gx + sxy * gy
                        cf[idx + j, 1] += sxy * gx + syy * gy
    sum_chunks(c_mass, c_mom, c_force, g_mass, g_mom, g_force)

@njit(parallel=True, fastmath=True, cache=True)
def g2p_2d(p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
           origin, h, kind, lo, nloc, dt, mode, flip_ratio, apic_dinv, set_velocity, move, do_gradient):
    """2D G2P (see transfer.g2p); L keeps its 3x3 plane-strain form (z row and column zero)."""
    n = p_x.shape[0]
    S = support(kind)
    inv_h = 1.0 / h
    sx = nloc[1]
    nchunks = max(1, min(n, 64 * 8))
    for c in prange(nchunks):
        w = np.empty((2, 4))
        dw = np.empty((2, 4))
        L = np.zeros((3, 3))
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            bx = axis_weights((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h, w[0], dw[0])
            by = axis_weights((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h, w[1], dw[1])
            base = (bx - lo[0]) * sx + (by - lo[1])
            v0 = v1 = d0 = d1 = 0.0
            l00 = l01 = l10 = l11 = 0.0
            b00 = b01 = b10 = b11 = 0.0  # B[:, a] = sum w v_i * (node step along axis a)
            for i in range(S):
                wi = w[0, i]
                dwi = dw[0, i]
                idx = base + i * sx
                s0 = s1 = t0 = t1 = 0.0
                for j in range(S):
                    wt = wi * w[1, j]
                    u0 = g_vel[idx + j, 0]
                    u1 = g_vel[idx + j, 1]
                    s0 += wt * u0
                    s1 += wt * u1
                    t0 += j * wt * u0
                    t1 += j * wt * u1
                    if mode == 2:
                        d0 += wt * (u0 - g_vel_old[idx + j, 0])
                        d1 += wt * (u1 - g_vel_old[idx + j, 1])
                    gx = dwi * w[1, j]
                    gy = wi * dw[1, j]
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
            if set_velocity:
                ox = bx * h + origin[0] - p_x[p, 0]
                oy = by * h + origin[1] - p_x[p, 1]
                if mode == 2:
                    p_v[p, 0] = flip_ratio * (p_v[p, 0] + d0) + (1.0 - flip_ratio) * v0
                    p_v[p, 1] = flip_ratio * (p_v[p, 1] + d1) + (1.0 - flip_ratio) * v1
                else:
                    p_v[p, 0] = v0
                    p_v[p, 1] = v1
                if mode == 1 and apic_dinv > 0.0:
                    p_C[p, 0, 0] = (v0 * ox + h * b00) * apic_dinv
                    p_C[p, 0, 1] = (v0 * oy + h * b01) * apic_dinv
                    p_C[p, 1, 0] = (v1 * ox + h * b10) * apic_dinv
                    p_C[p, 1, 1] = (v1 * oy + h * b11) * apic_dinv
                elif mode == 1:
                    p_C[p, 0, 0], p_C[p, 0, 1], p_C[p, 1, 0], p_C[p, 1, 1] = l00, l01, l10, l11
                else:
                    p_C[p, 0, 0] = p_C[p, 0, 1] = p_C[p, 1, 0] = p_C[p, 1, 1] = 0.0
            if move:
                p_x[p, 0] += dt * v0
                p_x[p, 1] += dt * v1
            if do_gradient:
                L[0, 0], L[0, 1], L[1, 0], L[1, 1] = l00, l01, l10, l11
                update_volume(p, p_L, p_vol, p_rho, p_mass, L, dt)
