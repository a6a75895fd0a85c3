"""P2G and G2P specialised for 3D: the same transfers as the reference tests/support/reference_transfer.py, written
with the stencil as three nested loops so that the tensor-product weights,
gradients and APIC terms are built up axis by axis.

Per stencil node the generic kernel rebuilds the node's multi-index, weight,
gradient and offset from scratch (about 120 flops in 3D); here the x and y
factors are hoisted out of the inner loop and the affine momentum
m (v + C (x_i - x_p)) is advanced by one column of m C h per node step, so a
node costs about 20 flops (P2G, force folded) and 18 flops (G2P).  Weights
are register tuples and the support a compile-time constant (``tag``,
stencil.py).  Same particle arrays and, with split force, the same results to
rounding as the reference (tests/unit/test_transfer_specialised.py); the private P2G
grids are interleaved (``c_grid``), and P2G may fold the force into the
momentum (mpm/grid.py).  ``scheme`` (stencil.scheme_tag) selects PIC, APIC, FLIP or MLS at
compile time; MLS-MPM (Hu et al. 2018): the
force through grad w ~ D^-1 w (x_i - x_p) and L = C.
"""

import numpy as np
from numba import njit, prange
from numba.extending import overload

from geompm.kernels.chunks import CHUNK_BODY, FAR, g2p_chunks, sum_interleaved, zero_rows
from geompm.kernels.stencil import APIC, FLIP, MLS, axis_stencil, mls_derivatives
from geompm.kernels.volume import update_volume


@njit(parallel=True, fastmath=True, cache=True)
def p2g_3d(tag, scheme, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
           c_grid, split, f_scale, mls_dinv, g_mass, g_mom, g_force):
    """3D P2G: m_i, APIC momentum and f_i = -sum V_p sigma_p grad w (see tests/reference_transfer.p2g).

    ``c_grid (nchunks, >= nn, 4 or 7)``: the private grids, interleaved per node as
    [m, (mv)_x, (mv)_y, (mv)_z, f_x, f_y, f_z].  ``split``: the force goes to its own
    columns, scaled by ``f_scale`` (1, or 0 for the MUSL re-map) and then to g_force.
    Otherwise it is folded into the momentum, (mv)_i += f_scale f_i with f_scale = dt,
    and g_force is not written: 4 instead of 7 updates per node (docs/performance.md).
    MLS (``scheme``, stencil.scheme_tag): the MLS-MPM force (Hu et al. 2018), grad w replaced by D^-1 w (x_i - x_p)
    with D^-1 = mls_dinv [1/m2]; folded, it is an affine term and costs nothing per node.
    """
    nchunks = c_grid.shape[0]
    for c in prange(nchunks):
        _p2g_chunk_3d(np.uint64(c), nchunks, tag, scheme, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind,
                      lo, nloc, c_grid[c], g_mass.shape[0], split, f_scale, mls_dinv)
    sum_interleaved(c_grid, split, g_mass, g_mom, g_force)


@njit(**CHUNK_BODY)
def _p2g_chunk_3d(c, nchunks, tag, scheme, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
                  g, nn, split, f_scale, mls_dinv):
    """P2G of chunk c of nchunks (a contiguous range of particles) into its private grid g (its first nn rows
    zeroed first): the body of p2g_3d's parallel loop (chunks.CHUNK_BODY)."""
    n = p_x.shape[0]
    width = g.shape[1]
    S = len(tag)
    inv_h = 1.0 / h
    sy = nloc[2]
    sx = nloc[1] * nloc[2]
    mls = len(scheme) - 1 == MLS  # compile-time (stencil.scheme_tag)
    affine_force = mls and not split
    zero_rows(g, nn, width)
    for p in range(c * n // nchunks, (c + 1) * n // nchunks):
        bx, wx, dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
        by, wy, dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
        bz, wz, dz = axis_stencil((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h)
        m = p_mass[p]
        # offset of the first stencil node from the particle [m]
        ox = bx * h + origin[0] - p_x[p, 0]
        oy = by * h + origin[1] - p_x[p, 1]
        oz = bz * h + origin[2] - p_x[p, 2]
        # -V sigma f_scale (Voigt xx, yy, zz, xy, yz, xz)
        nv = -p_vol[p] * f_scale
        sxx, syy, szz = nv * p_stress[p, 0], nv * p_stress[p, 1], nv * p_stress[p, 2]
        sxy, syz, sxz = nv * p_stress[p, 3], nv * p_stress[p, 4], nv * p_stress[p, 5]
        # affine momentum matrix A = m C [kg/s]
        a00, a01, a02 = m * p_C[p, 0, 0], m * p_C[p, 0, 1], m * p_C[p, 0, 2]
        a10, a11, a12 = m * p_C[p, 1, 0], m * p_C[p, 1, 1], m * p_C[p, 1, 2]
        a20, a21, a22 = m * p_C[p, 2, 0], m * p_C[p, 2, 1], m * p_C[p, 2, 2]
        if affine_force:  # MLS, folded: -f_scale V sigma D^-1 joins A (Hu et al. 2018)
            a00, a01, a02 = a00 + mls_dinv * sxx, a01 + mls_dinv * sxy, a02 + mls_dinv * sxz
            a10, a11, a12 = a10 + mls_dinv * sxy, a11 + mls_dinv * syy, a12 + mls_dinv * syz
            a20, a21, a22 = a20 + mls_dinv * sxz, a21 + mls_dinv * syz, a22 + mls_dinv * szz
        elif mls:  # MLS, split: the same force through grad w ~ D^-1 w (x_i - x_p)
            dx = mls_derivatives(wx, ox, h, mls_dinv)
            dy = mls_derivatives(wy, oy, h, mls_dinv)
            dz = mls_derivatives(wz, oz, h, mls_dinv)
        # momentum at the first node, and its increments per node step along x, y, z
        q0 = m * p_v[p, 0] + a00 * ox + a01 * oy + a02 * oz
        q1 = m * p_v[p, 1] + a10 * ox + a11 * oy + a12 * oz
        q2 = m * p_v[p, 2] + a20 * ox + a21 * oy + a22 * oz
        ax0, ax1, ax2 = h * a00, h * a10, h * a20
        ay0, ay1, ay2 = h * a01, h * a11, h * a21
        az0, az1, az2 = h * a02, h * a12, h * a22
        base = (bx - lo[0]) * sx + (by - lo[1]) * sy + (bz - lo[2])
        for i in range(S):
            wi = wx[i]
            dwi = dx[i]
            qi0, qi1, qi2 = q0 + i * ax0, q1 + i * ax1, q2 + i * ax2
            for j in range(S):
                wij = wi * wy[j]
                gx = dwi * wy[j]
                gy = wi * dy[j]
                # node (i, j, k): mass mij wk, momentum Q wk + R k wk, force Fa wk + Fb dwk
                mij = wij * m
                Q0, Q1, Q2 = wij * (qi0 + j * ay0), wij * (qi1 + j * ay1), wij * (qi2 + j * ay2)
                R0, R1, R2 = wij * az0, wij * az1, wij * az2
                Fa0 = sxx * gx + sxy * gy
                Fa1 = sxy * gx + syy * gy
                Fa2 = sxz * gx + syz * gy
                Fb0, Fb1, Fb2 = sxz * wij, syz * wij, szz * wij
                idx = base + i * sx + j * sy
                if split:
                    for k in range(S):
                        wk = wz[k]
                        kwk = k * wk
                        dwk = dz[k]
                        r = g[idx + k]
                        r[0] += mij * wk
                        r[1] += Q0 * wk + R0 * kwk
                        r[2] += Q1 * wk + R1 * kwk
                        r[3] += Q2 * wk + R2 * kwk
                        r[4] += Fa0 * wk + Fb0 * dwk
                        r[5] += Fa1 * wk + Fb1 * dwk
                        r[6] += Fa2 * wk + Fb2 * dwk
                elif affine_force:
                    for k in range(S):
                        wk = wz[k]
                        kwk = k * wk
                        r = g[idx + k]
                        r[0] += mij * wk
                        r[1] += Q0 * wk + R0 * kwk
                        r[2] += Q1 * wk + R1 * kwk
                        r[3] += Q2 * wk + R2 * kwk
                else:
                    Q0 += Fa0
                    Q1 += Fa1
                    Q2 += Fa2
                    for k in range(S):
                        wk = wz[k]
                        kwk = k * wk
                        dwk = dz[k]
                        r = g[idx + k]
                        r[0] += mij * wk
                        r[1] += Q0 * wk + R0 * kwk + Fb0 * dwk
                        r[2] += Q1 * wk + R1 * kwk + Fb1 * dwk
                        r[3] += Q2 * wk + R2 * kwk + Fb2 * dwk


@njit(parallel=True, fastmath=True, cache=True)
def g2p_3d(tag, scheme, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
           origin, h, kind, lo, nloc, dt, flip_ratio, apic_dinv, set_velocity, move, do_gradient, p_box):
    """3D G2P (see tests/reference_transfer.g2p for the modes and flags).

    With ``move``, ``p_box[c] = (lowest, highest)`` position of chunk c's moved particles [m]
    (chunks: ``g2p_chunks``), the particles' box at no extra pass (backend/cpu.py).

    The APIC sum  B = sum w v_i (x_i - x_p)^T  is split as
    (sum w v_i) o^T + h (sum w v_i (i, j, k)^T), o the first node's offset.
    """
    n = p_x.shape[0]
    S = len(tag)
    inv_h = 1.0 / h
    sy = nloc[2]
    sx = nloc[1] * nloc[2]
    nchunks = g2p_chunks(n)
    mode = len(scheme) - 1  # compile-time (stencil.scheme_tag)
    mls = mode == MLS
    for c in prange(nchunks):
        L = np.zeros((3, 3))
        B = np.zeros((3, 3))
        lo0 = lo1 = lo2 = FAR  # finite: the kernel's fastmath assumes no infinities
        hi0 = hi1 = hi2 = -FAR
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            bx, wx, dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
            by, wy, dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
            bz, wz, dz = axis_stencil((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h)
            base = (bx - lo[0]) * sx + (by - lo[1]) * sy + (bz - lo[2])
            (v0, v1, v2, l00, l01, l02, l10, l11, l12, l20, l21, l22,
             b00, b01, b02, b10, b11, b12, b20, b21, b22, d0, d1, d2) = _gather_scheme(
                scheme, S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel, g_vel_old)
            if not mls:
                L[0, 0], L[0, 1], L[0, 2] = l00, l01, l02
                L[1, 0], L[1, 1], L[1, 2] = l10, l11, l12
                L[2, 0], L[2, 1], L[2, 2] = l20, l21, l22
            B[0, 0], B[0, 1], B[0, 2] = b00, b01, b02
            B[1, 0], B[1, 1], B[1, 2] = b10, b11, b12
            B[2, 0], B[2, 1], B[2, 2] = b20, b21, b22
            if mls:  # L = C = (v o^T + h B) D^-1, o the first node's offset
                vp = (v0, v1, v2)
                o = (bx * h + origin[0] - p_x[p, 0], by * h + origin[1] - p_x[p, 1],
                     bz * h + origin[2] - p_x[p, 2])
                for a in range(3):
                    for b in range(3):
                        L[a, b] = (vp[a] * o[b] + h * B[a, b]) * apic_dinv
            _finish(p, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, origin, h, bx, by, bz,
                    v0, v1, v2, d0, d1, d2, L, B, dt, S, mode, flip_ratio, apic_dinv, set_velocity, move,
                    do_gradient)
            if move:
                lo0, hi0 = min(lo0, p_x[p, 0]), max(hi0, p_x[p, 0])
                lo1, hi1 = min(lo1, p_x[p, 1]), max(hi1, p_x[p, 1])
                lo2, hi2 = min(lo2, p_x[p, 2]), max(hi2, p_x[p, 2])
        if move:
            p_box[c, 0, 0], p_box[c, 0, 1], p_box[c, 0, 2] = lo0, lo1, lo2
            p_box[c, 1, 0], p_box[c, 1, 1], p_box[c, 1, 2] = hi0, hi1, hi2


def _gather_scheme(scheme, S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel, g_vel_old):
    """One particle's gathered sums for its transfer scheme: (v (3), L (9, zero for MLS), B (9), FLIP increment
    (3, zero but for FLIP)).  A numba-only function (its overload below): the scheme's tag picks the sums while
    numba types the call, so only that scheme's gather reaches G2P's code.  With every scheme's gather behind
    a run-time test, numba's parallel-loop passes (quadratic in the loop body's blocks) took 9-13 s of a cold
    start over the 3D G2P; with the scheme's own, about half (docs/performance.md)."""
    raise TypeError("_gather_scheme is compiled by numba only (transfer3d.g2p_3d)")


@overload(_gather_scheme, inline="always")
def _gather_scheme_numba(scheme, S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel, g_vel_old):
    mode = len(scheme.types) - 1  # the tag's length (stencil.scheme_tag)
    if mode == MLS:
        def affine(scheme, S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel, g_vel_old):
            (v0, v1, v2, b00, b01, b02, b10, b11, b12, b20, b21, b22) = _gather_affine(
                S, wx, wy, wz, base, sx, sy, g_vel)
            return (v0, v1, v2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                    b00, b01, b02, b10, b11, b12, b20, b21, b22, 0.0, 0.0, 0.0)
        return affine
    if mode == FLIP:
        def flip(scheme, S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel, g_vel_old):
            # the FLIP increment a pass of its own: in the sums' loop the branch cost 16 % of G2P
            return (_gather_full(S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel)
                    + _flip_increment(S, wx, wy, wz, base, sx, sy, g_vel, g_vel_old))
        return flip

    def full(scheme, S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel, g_vel_old):
        return _gather_full(S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel) + (0.0, 0.0, 0.0)
    return full


@njit(cache=True, inline="always")
def _gather_full(S, wx, dx, wy, dy, wz, dz, base, sx, sy, g_vel):
    """v = sum w v_i, L = sum v_i (x) grad w and B[:, a] = sum w v_i (node step along axis a),
    as separable sums: innermost over k, then j, then i (tensor-product weights)."""
    v0 = v1 = v2 = 0.0  # sum w v_i
    # L = sum v_i (x) grad w, and B[:, a] = sum w v_i * (node step along axis a)
    l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
    b00 = b01 = b02 = b10 = b11 = b12 = b20 = b21 = b22 = 0.0
    # separable sums: innermost over k, then j, then i (tensor-product weights)
    for i in range(S):
        wi = wx[i]
        dwi = dx[i]
        A0 = A1 = A2 = 0.0  # sum_jk wy wz v
        Y0 = Y1 = Y2 = 0.0  # sum_jk dwy wz v
        Z0 = Z1 = Z2 = 0.0  # sum_jk wy dwz v
        J0 = J1 = J2 = 0.0  # sum_jk j wy wz v
        K0 = K1 = K2 = 0.0  # sum_jk k wy wz v
        for j in range(S):
            wj = wy[j]
            dwj = dy[j]
            idx = base + i * sx + j * sy
            S0 = S1 = S2 = 0.0  # sum_k wz v
            T0 = T1 = T2 = 0.0  # sum_k dwz v
            U0 = U1 = U2 = 0.0  # sum_k k wz v
            for k in range(S):
                wk = wz[k]
                dwk = dz[k]
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
    return (v0, v1, v2, l00, l01, l02, l10, l11, l12, l20, l21, l22,
            b00, b01, b02, b10, b11, b12, b20, b21, b22)


@njit(cache=True, inline="always")
def _gather_affine(S, wx, wy, wz, base, sx, sy, g_vel):
    """v = sum w v_i and B (as in _gather_full) without the gradient sums: the MLS-MPM
    gather (Hu et al. 2018), where L = C comes from B."""
    v0 = v1 = v2 = 0.0
    b00 = b01 = b02 = b10 = b11 = b12 = b20 = b21 = b22 = 0.0
    for i in range(S):
        wi = wx[i]
        A0 = A1 = A2 = 0.0  # sum_jk wy wz v
        J0 = J1 = J2 = 0.0  # sum_jk j wy wz v
        K0 = K1 = K2 = 0.0  # sum_jk k wy wz v
        for j in range(S):
            wj = wy[j]
            idx = base + i * sx + j * sy
            S0 = S1 = S2 = 0.0  # sum_k wz v
            U0 = U1 = U2 = 0.0  # sum_k k wz v
            for k in range(S):
                wk = wz[k]
                kwk = k * wk
                u0 = g_vel[idx + k, 0]
                u1 = g_vel[idx + k, 1]
                u2 = g_vel[idx + k, 2]
                S0 += wk * u0
                S1 += wk * u1
                S2 += wk * u2
                U0 += kwk * u0
                U1 += kwk * u1
                U2 += kwk * u2
            A0 += wj * S0
            A1 += wj * S1
            A2 += wj * S2
            J0 += j * wj * S0
            J1 += j * wj * S1
            J2 += j * wj * S2
            K0 += wj * U0
            K1 += wj * U1
            K2 += wj * U2
        v0 += wi * A0
        v1 += wi * A1
        v2 += wi * A2
        b00 += i * wi * A0
        b10 += i * wi * A1
        b20 += i * wi * A2
        b01 += wi * J0
        b11 += wi * J1
        b21 += wi * J2
        b02 += wi * K0
        b12 += wi * K1
        b22 += wi * K2
    return v0, v1, v2, b00, b01, b02, b10, b11, b12, b20, b21, b22


@njit(cache=True, inline="always")
def _flip_increment(S, wx, wy, wz, base, sx, sy, g_vel, g_vel_old):
    """sum_i w_ip (v_i - v_old_i): the FLIP velocity increment of one particle."""
    d0 = d1 = d2 = 0.0
    for i in range(S):
        for j in range(S):
            wij = wx[i] * wy[j]
            idx = base + i * sx + j * sy
            for k in range(S):
                wt = wij * wz[k]
                d0 += wt * (g_vel[idx + k, 0] - g_vel_old[idx + k, 0])
                d1 += wt * (g_vel[idx + k, 1] - g_vel_old[idx + k, 1])
                d2 += wt * (g_vel[idx + k, 2] - g_vel_old[idx + k, 2])
    return d0, d1, d2


@njit(cache=True, inline="always")
def _finish(p, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, origin, h, bx, by, bz,
            v0, v1, v2, d0, d1, d2, L, B, dt, S, mode, flip_ratio, apic_dinv, set_velocity, move, do_gradient):
    """Per-particle end of G2P: C from B, velocity, position, then L, volume and density."""
    if set_velocity:
        vp = (v0, v1, v2)
        dv = (d0, d1, d2)
        o = (bx * h + origin[0] - p_x[p, 0], by * h + origin[1] - p_x[p, 1], bz * h + origin[2] - p_x[p, 2])
        for a in range(3):
            if mode == FLIP:
                p_v[p, a] = flip_ratio * (p_v[p, a] + dv[a]) + (1.0 - flip_ratio) * vp[a]
            else:
                p_v[p, a] = vp[a]
            for b in range(3):
                if mode == APIC or mode == MLS:
                    if S > 2:  # APIC needs D: linear hats fall back to C = L
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

