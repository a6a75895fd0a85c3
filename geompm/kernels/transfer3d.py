"""P2G and G2P specialised for 3D: the same transfers as transfer.py, written
with the stencil as three nested loops so that the tensor-product weights,
gradients and APIC terms are built up axis by axis.

Per stencil node the generic kernel rebuilds the node's multi-index, weight,
gradient and offset from scratch (about 120 flops in 3D); here the x and y
factors are hoisted out of the inner loop and the affine momentum
m (v + C (x_i - x_p)) is advanced by one column of m C h per node step, so a
node costs about 30 flops (P2G) and 25 flops (G2P).  Same arrays, same
arguments, same results to rounding as transfer.py; see that module for the
array shapes and the chunked, deterministic P2G.
"""

import numpy as np
from numba import njit, prange

from .shape import axis_weights, support
from .volume import update_volume


@njit(parallel=True, fastmath=True, cache=True)
def p2g_3d(p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
           c_mass, c_mom, c_force, with_force, g_mass, g_mom, g_force):
    """3D P2G: m_i, APIC momentum and f_i = -sum V_p sigma_p grad w (see transfer.p2g)."""
    n = p_x.shape[0]
    nchunks = c_mass.shape[0]
    nn = g_mass.shape[0]
    S = support(kind)
    inv_h = 1.0 / h
    sz = 1
    sy = nloc[2]
    sx = nloc[1] * nloc[2]
    for c in prange(nchunks):
        cm = c_mass[c]
        cp = c_mom[c]
        cf = c_force[c]
        for i in range(nn):
            cm[i] = 0.0
            for a in range(3):
                cp[i, a] = 0.0
                cf[i, a] = 0.0
        w = np.empty((3, 4))
        dw = np.empty((3, 4))
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            bx = axis_weights((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h, w[0], dw[0])
            by = axis_weights((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h, w[1], dw[1])
            bz = axis_weights((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h, w[2], dw[2])
            m = p_mass[p]
            # offset of the first stencil node from the particle [m]
            ox = bx * h + origin[0] - p_x[p, 0]
            oy = by * h + origin[1] - p_x[p, 1]
            oz = bz * h + origin[2] - p_x[p, 2]
            C = p_C[p]
            # momentum at the first node, and its increments per node step along x, y, z
            q0 = m * (p_v[p, 0] + C[0, 0] * ox + C[0, 1] * oy + C[0, 2] * oz)
            q1 = m * (p_v[p, 1] + C[1, 0] * ox + C[1, 1] * oy + C[1, 2] * oz)
            q2 = m * (p_v[p, 2] + C[2, 0] * ox + C[2, 1] * oy + C[2, 2] * oz)
            mh = m * h
            ax0, ax1, ax2 = mh * C[0, 0], mh * C[1, 0], mh * C[2, 0]
            ay0, ay1, ay2 = mh * C[0, 1], mh * C[1, 1], mh * C[2, 1]
            az0, az1, az2 = mh * C[0, 2], mh * C[1, 2], mh * C[2, 2]
            # -V sigma (Voigt xx, yy, zz, xy, yz, xz)
            nv = -p_vol[p]
            sxx, syy, szz = nv * p_stress[p, 0], nv * p_stress[p, 1], nv * p_stress[p, 2]
            sxy, syz, sxz = nv * p_stress[p, 3], nv * p_stress[p, 4], nv * p_stress[p, 5]
            base = (bx - lo[0]) * sx + (by - lo[1]) * sy + (bz - lo[2]) * sz
            for i in range(S):
                wi = w[0, i]
                dwi = dw[0, i]
                qi0, qi1, qi2 = q0 + i * ax0, q1 + i * ax1, q2 + i * ax2
                for j in range(S):
                    wij = wi * w[1, j]
                    gxij = dwi * w[1, j]
                    gyij = wi * dw[1, j]
                    qj0, qj1, qj2 = qi0 + j * ay0, qi1 + j * ay1, qi2 + j * ay2
                    idx = base + i * sx + j * sy
                    for k in range(S):
                        wk = w[2, k]
                        wt = wij * wk
                        cm[idx + k] += wt * m
                        cp[idx + k, 0] += wt * (qj0 + k * az0)
                        cp[idx + k, 1] += wt * (qj1 + k * az1)
                        cp[idx + k, 2] += wt * (qj2 + k * az2)
                        if with_force:
                            gx = gxij * wk
                            gy = gyij * wk
                            gz = wij * dw[2, k]
                            cf[idx + k, 0] += sxx * gx + sxy * gy + sxz * gz
                            cf[idx + k, 1] += sxy * gx + syy * gy + syz * gz
                            cf[idx + k, 2] += sxz * gx + syz * gy + szz * gz
    for i in prange(nn):
        m = 0.0
        for c in range(nchunks):
            m += c_mass[c, i]
        g_mass[i] = m
        for a in range(3):
            mv = 0.0
            f = 0.0
            for c in range(nchunks):
                mv += c_mom[c, i, a]
                f += c_force[c, i, a]
            g_mom[i, a] = mv
            g_force[i, a] = f


@njit(parallel=True, fastmath=True, cache=True)
def g2p_3d(p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
           origin, h, kind, lo, nloc, dt, mode, flip_ratio, apic_dinv, set_velocity, move, do_gradient):
    """3D G2P (see transfer.g2p for the modes and flags).

    The APIC sum  B = sum w v_i (x_i - x_p)^T  is split as
    (sum w v_i) o^T + h (sum w v_i (i, j, k)^T), o the first node's offset.
    """
    n = p_x.shape[0]
    S = support(kind)
    inv_h = 1.0 / h
    sy = nloc[2]
    sx = nloc[1] * nloc[2]
    nchunks = max(1, min(n, 64 * 8))
    flip = mode == 2
    for c in prange(nchunks):
        w = np.empty((3, 4))
        dw = np.empty((3, 4))
        L = np.zeros((3, 3))
        B = np.zeros((3, 3))
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            bx = axis_weights((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h, w[0], dw[0])
            by = axis_weights((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h, w[1], dw[1])
            bz = axis_weights((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h, w[2], dw[2])
            base = (bx - lo[0]) * sx + (by - lo[1]) * sy + (bz - lo[2])
            v0 = v1 = v2 = 0.0  # sum w v_i
            d0 = d1 = d2 = 0.0  # sum w (v_i - v_old_i)   (FLIP)
            # L = sum v_i (x) grad w, and B[:, a] = sum w v_i * (node step along axis a)
            l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
            b00 = b01 = b02 = b10 = b11 = b12 = b20 = b21 = b22 = 0.0
            for i in range(S):
                wi = w[0, i]
                dwi = dw[0, i]
                for j in range(S):
                    wij = wi * w[1, j]
                    gxij = dwi * w[1, j]
                    gyij = wi * dw[1, j]
                    idx = base + i * sx + j * sy
                    s0 = s1 = s2 = 0.0  # sum over k of w v
                    t0 = t1 = t2 = 0.0  # sum over k of w v k
                    for k in range(S):
                        wk = w[2, k]
                        wt = wij * wk
                        u0 = g_vel[idx + k, 0]
                        u1 = g_vel[idx + k, 1]
                        u2 = g_vel[idx + k, 2]
                        s0 += wt * u0
                        s1 += wt * u1
                        s2 += wt * u2
                        t0 += k * wt * u0
                        t1 += k * wt * u1
                        t2 += k * wt * u2
                        if flip:
                            d0 += wt * (u0 - g_vel_old[idx + k, 0])
                            d1 += wt * (u1 - g_vel_old[idx + k, 1])
                            d2 += wt * (u2 - g_vel_old[idx + k, 2])
                        gx = gxij * wk
                        gy = gyij * wk
                        gz = wij * dw[2, k]
                        l00 += u0 * gx
                        l01 += u0 * gy
                        l02 += u0 * gz
                        l10 += u1 * gx
                        l11 += u1 * gy
                        l12 += u1 * gz
                        l20 += u2 * gx
                        l21 += u2 * gy
                        l22 += u2 * gz
                    v0 += s0
                    v1 += s1
                    v2 += s2
                    b00 += i * s0
                    b10 += i * s1
                    b20 += i * s2
                    b01 += j * s0
                    b11 += j * s1
                    b21 += j * s2
                    b02 += t0
                    b12 += t1
                    b22 += t2
            L[0, 0], L[0, 1], L[0, 2] = l00, l01, l02
            L[1, 0], L[1, 1], L[1, 2] = l10, l11, l12
            L[2, 0], L[2, 1], L[2, 2] = l20, l21, l22
            B[0, 0], B[0, 1], B[0, 2] = b00, b01, b02
            B[1, 0], B[1, 1], B[1, 2] = b10, b11, b12
            B[2, 0], B[2, 1], B[2, 2] = b20, b21, b22
            _finish(p, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, origin, h, bx, by, bz,
                    v0, v1, v2, d0, d1, d2, L, B, dt, mode, flip_ratio, apic_dinv, set_velocity, move,
                    do_gradient)


@njit(cache=True)
def _finish(p, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, origin, h, bx, by, bz,
            v0, v1, v2, d0, d1, d2, L, B, dt, mode, flip_ratio, apic_dinv, set_velocity, move, do_gradient):
    """Per-particle end of G2P: C from B, velocity, position, then L, volume and density."""
    if set_velocity:
        vp = (v0, v1, v2)
        dv = (d0, d1, d2)
        o = (bx * h + origin[0] - p_x[p, 0], by * h + origin[1] - p_x[p, 1], bz * h + origin[2] - p_x[p, 2])
        for a in range(3):
            if mode == 2:
                p_v[p, a] = flip_ratio * (p_v[p, a] + dv[a]) + (1.0 - flip_ratio) * vp[a]
            else:
                p_v[p, a] = vp[a]
            for b in range(3):
                if mode == 1:
                    if apic_dinv > 0.0:
                        p_C[p, a, b] = (vp[a] * o[b] + h * B[a, b]) * apic_dinv
                    else:
                        p_C[p, a, b] = L[a, b]
                else:
                    p_C[p, a, b] = 0.0
    if move:
        p_x[p, 0] += dt * v0
        p_x[p, 1] += dt * v1
        p_x[p, 2] += dt * v2
    if do_gradient:
        update_volume(p, p_L, p_vol, p_rho, p_mass, L, dt)

