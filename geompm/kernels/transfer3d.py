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

from .chunks import sum_chunks, zero_chunk
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
        zero_chunk(cm, cp, cf, nn)
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
                    # node (i, j, k): mass mij wk, momentum Q wk + R k wk, force Fa wk + Fb dwk
                    mij = wij * m
                    Q0, Q1, Q2 = wij * (qi0 + j * ay0), wij * (qi1 + j * ay1), wij * (qi2 + j * ay2)
                    R0, R1, R2 = wij * az0, wij * az1, wij * az2
                    Fa0 = sxx * gxij + sxy * gyij
                    Fa1 = sxy * gxij + syy * gyij
                    Fa2 = sxz * gxij + syz * gyij
                    Fb0, Fb1, Fb2 = sxz * wij, syz * wij, szz * wij
                    idx = base + i * sx + j * sy
                    for k in range(S):
                        wk = w[2, k]
                        kwk = k * wk
                        cm[idx + k] += mij * wk
                        cp[idx + k, 0] += Q0 * wk + R0 * kwk
                        cp[idx + k, 1] += Q1 * wk + R1 * kwk
                        cp[idx + k, 2] += Q2 * wk + R2 * kwk
                        if with_force:
                            dwk = dw[2, k]
                            cf[idx + k, 0] += Fa0 * wk + Fb0 * dwk
                            cf[idx + k, 1] += Fa1 * wk + Fb1 * dwk
                            cf[idx + k, 2] += Fa2 * wk + Fb2 * dwk
    sum_chunks(c_mass, c_mom, c_force, g_mass, g_mom, g_force)

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
            # separable sums: innermost over k, then j, then i (tensor-product weights)
            for i in range(S):
                wi = w[0, i]
                dwi = dw[0, i]
                A0 = A1 = A2 = 0.0  # sum_jk wy wz v
                Y0 = Y1 = Y2 = 0.0  # sum_jk dwy wz v
                Z0 = Z1 = Z2 = 0.0  # sum_jk wy dwz v
                J0 = J1 = J2 = 0.0  # sum_jk j wy wz v
                K0 = K1 = K2 = 0.0  # sum_jk k wy wz v
                E0 = E1 = E2 = 0.0  # sum_jk wy wz (v - v_old)
                for j in range(S):
                    wj = w[1, j]
                    dwj = dw[1, j]
                    idx = base + i * sx + j * sy
                    S0 = S1 = S2 = 0.0  # sum_k wz v
                    T0 = T1 = T2 = 0.0  # sum_k dwz v
                    U0 = U1 = U2 = 0.0  # sum_k k wz v
                    for k in range(S):
                        wk = w[2, k]
                        dwk = dw[2, k]
                        kwk = k * wk
                        u0 = g_vel[idx + k, 0]
                        u1 = g_vel[idx + k, 1]
                        u2 = g_vel[idx + k, 2]
                        S0 += wk * u0
                        S1 += wk * u1
                        S2 += wk * u2
                        T0 += dwk * u0
                        T1 += dwk * u1
                        T2 += dwk * u2
                        U0 += kwk * u0
                        U1 += kwk * u1
                        U2 += kwk * u2
                        if flip:
                            wjk = wj * wk
                            E0 += wjk * (u0 - g_vel_old[idx + k, 0])
                            E1 += wjk * (u1 - g_vel_old[idx + k, 1])
                            E2 += wjk * (u2 - g_vel_old[idx + k, 2])
                    A0 += wj * S0
                    A1 += wj * S1
                    A2 += wj * S2
                    Y0 += dwj * S0
                    Y1 += dwj * S1
                    Y2 += dwj * S2
                    Z0 += wj * T0
                    Z1 += wj * T1
                    Z2 += wj * T2
                    J0 += j * wj * S0
                    J1 += j * wj * S1
                    J2 += j * wj * S2
                    K0 += wj * U0
                    K1 += wj * U1
                    K2 += wj * U2
                v0 += wi * A0
                v1 += wi * A1
                v2 += wi * A2
                d0 += wi * E0
                d1 += wi * E1
                d2 += wi * E2
                l00 += dwi * A0
                l10 += dwi * A1
                l20 += dwi * A2
                l01 += wi * Y0
                l11 += wi * Y1
                l21 += wi * Y2
                l02 += wi * Z0
                l12 += wi * Z1
                l22 += wi * Z2
                b00 += i * wi * A0
                b10 += i * wi * A1
                b20 += i * wi * A2
                b01 += wi * J0
                b11 += wi * J1
                b21 += wi * J2
                b02 += wi * K0
                b12 += wi * K1
                b22 += wi * K2
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

