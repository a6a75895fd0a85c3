"""The dimension-generic reference P2G and G2P, any dimension d: what the 2D and 3D kernels the
engine runs (geompm/kernels/transfer2d.py, transfer3d.py) are tested against.  Written for
clarity, not speed: the node multi-index, weight and gradient are rebuilt per stencil node.

Arrays (n particles, d dimensions, nn nodes of the active grid window):
    p_x (n, d) position [m]        p_v (n, d) velocity [m/s]
    p_C (n, d, d) APIC affine velocity matrix [1/s]
    p_mass (n,) [kg]  p_vol (n,) [m^d]  p_stress (n, 6) Voigt, see voigt.py
    p_L (n, 3, 3) velocity gradient [1/s] (plane strain: z row/column zero)
    g_mass (nn,) [kg]  g_mom (nn, d) [kg m/s]  g_force (nn, d) [N]
    g_vel, g_vel_old (nn, d) [m/s]

The window is the block of grid nodes ``lo[a] <= i_a < lo[a] + nloc[a]``
(global node indices; node i sits at origin + i h).  Node (i_0..i_{d-1}) has
the flat index sum((i_a - lo[a]) * stride[a]), last axis fastest.

P2G is race-free: particles are split into ``nchunks`` fixed contiguous chunks,
each scattering into its own private grid; the private grids are summed in
chunk order.  The result therefore depends on the chunk count only, not on
thread scheduling, and is deterministic for a fixed thread count.
"""

import numpy as np
from numba import njit, prange

from geompm.kernels.shape import axis_weights, support
from geompm.kernels.voigt import VOIGT_INDEX
from geompm.kernels.volume import update_volume


@njit(cache=True)
def zero_chunk(cm, cp, cf, nn):
    """Zero the first nn nodes of one chunk's mass, momentum and force."""
    d = cp.shape[1]
    for i in range(nn):
        cm[i] = 0.0
        for a in range(d):
            cp[i, a] = 0.0
            cf[i, a] = 0.0


@njit(parallel=True, fastmath=True, cache=True)
def sum_chunks(c_mass, c_mom, c_force, g_mass, g_mom, g_force):
    """g_* = sum over chunks of c_*, node by node, in chunk order."""
    nchunks = c_mass.shape[0]
    nn, d = g_mom.shape
    for i in prange(nn):
        m = 0.0
        for c in range(nchunks):
            m += c_mass[c, i]
        g_mass[i] = m
        for a in range(d):
            mv = 0.0
            f = 0.0
            for c in range(nchunks):
                mv += c_mom[c, i, a]
                f += c_force[c, i, a]
            g_mom[i, a] = mv
            g_force[i, a] = f


@njit(cache=True, inline="always")
def _strides(nloc, stride):
    d = nloc.shape[0]
    stride[d - 1] = 1
    for a in range(d - 2, -1, -1):
        stride[a] = stride[a + 1] * nloc[a + 1]


@njit(cache=True, inline="always")
def _node(s, S, d, base, lo, stride, w, dw, k, gw):
    """Flat node index and weight of stencil entry s; gradient into gw."""
    t = s
    for a in range(d - 1, -1, -1):
        k[a] = t % S
        t //= S
    idx = 0
    wt = 1.0
    for a in range(d):
        wt *= w[a, k[a]]
        idx += (base[a] + k[a] - lo[a]) * stride[a]
    for a in range(d):
        g = dw[a, k[a]]
        for b in range(d):
            if b != a:
                g *= w[b, k[b]]
        gw[a] = g
    return idx, wt


@njit(parallel=True, fastmath=True, cache=True)
def p2g(p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc,
        c_mass, c_mom, c_force, with_force, g_mass, g_mom, g_force):
    """Scatter mass, APIC momentum and (if with_force) internal force to the grid.

    m_i = sum w m_p;  (mv)_i = sum w m_p (v_p + C_p (x_i - x_p));
    f_i = -sum V_p sigma_p . grad w.   c_* are private buffers (nchunks, >= nn[, d]).
    """
    n, d = p_x.shape
    nchunks = c_mass.shape[0]
    nn = g_mass.shape[0]
    S = support(kind)
    nst = S ** d
    inv_h = 1.0 / h
    stride = np.empty(d, np.int64)
    _strides(nloc, stride)
    for c in prange(nchunks):
        cm = c_mass[c]
        cp = c_mom[c]
        cf = c_force[c]
        zero_chunk(cm, cp, cf, nn)
        w = np.empty((d, 4))
        dw = np.empty((d, 4))
        base = np.empty(d, np.int64)
        k = np.empty(d, np.int64)
        gw = np.empty(d)
        dx = np.empty(d)
        sig = np.empty((d, d))
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            for a in range(d):
                base[a] = axis_weights((p_x[p, a] - origin[a]) * inv_h, kind, inv_h, w[a], dw[a])
                for b in range(d):
                    sig[a, b] = p_stress[p, VOIGT_INDEX[a, b]]
            m = p_mass[p]
            vol = p_vol[p]
            for s in range(nst):
                idx, wt = _node(s, S, d, base, lo, stride, w, dw, k, gw)
                for a in range(d):
                    dx[a] = (base[a] + k[a]) * h + origin[a] - p_x[p, a]
                cm[idx] += wt * m
                for a in range(d):
                    mv = p_v[p, a]
                    for b in range(d):
                        mv += p_C[p, a, b] * dx[b]
                    cp[idx, a] += wt * m * mv
                if with_force:
                    for a in range(d):
                        f = 0.0
                        for b in range(d):
                            f += sig[a, b] * gw[b]
                        cf[idx, a] -= vol * f
    sum_chunks(c_mass, c_mom, c_force, g_mass, g_mom, g_force)

@njit(parallel=True, fastmath=True, cache=True)
def g2p(p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old,
        origin, h, kind, lo, nloc, dt, mode, flip_ratio, apic_dinv, set_velocity, move, do_gradient):
    """Gather grid velocities to particles.

    mode 0 PIC, 1 APIC, 2 FLIP blend.  With ``set_velocity``: v_p and C_p;
    with ``move``: x_p += dt v_pic.  With ``do_gradient``: L_p = sum v_i (x) grad w, then
    V <- V det(I + dt L) (= V0 det F, F <- (I + dt L) F, without storing F), rho = m / V.  APIC uses
    C_p = sum w v_i (x_i - x_p)^T D^-1 with D^-1 = apic_dinv (B-splines), or
    C_p = L_p when apic_dinv == 0 (linear basis).
    """
    n, d = p_x.shape
    S = support(kind)
    nst = S ** d
    inv_h = 1.0 / h
    stride = np.empty(d, np.int64)
    _strides(nloc, stride)
    nchunks = max(1, min(n, 64 * 8))
    for c in prange(nchunks):
        w = np.empty((d, 4))
        dw = np.empty((d, 4))
        base = np.empty(d, np.int64)
        k = np.empty(d, np.int64)
        gw = np.empty(d)
        dx = np.empty(d)
        vpic = np.empty(d)
        dv = np.empty(d)
        B = np.empty((d, d))
        L = np.zeros((3, 3))
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            for a in range(d):
                base[a] = axis_weights((p_x[p, a] - origin[a]) * inv_h, kind, inv_h, w[a], dw[a])
                vpic[a] = 0.0
                dv[a] = 0.0
                for b in range(d):
                    B[a, b] = 0.0
                    L[a, b] = 0.0
            for s in range(nst):
                idx, wt = _node(s, S, d, base, lo, stride, w, dw, k, gw)
                for a in range(d):
                    vi = g_vel[idx, a]
                    vpic[a] += wt * vi
                    if mode == 2:
                        dv[a] += wt * (vi - g_vel_old[idx, a])
                    for b in range(d):
                        L[a, b] += vi * gw[b]
                if mode == 1 and apic_dinv > 0.0:
                    for b in range(d):
                        dx[b] = (base[b] + k[b]) * h + origin[b] - p_x[p, b]
                    for a in range(d):
                        vw = wt * g_vel[idx, a]
                        for b in range(d):
                            B[a, b] += vw * dx[b]
            if move:
                for a in range(d):
                    p_x[p, a] += dt * vpic[a]
            if set_velocity:
                for a in range(d):
                    if mode == 2:
                        p_v[p, a] = flip_ratio * (p_v[p, a] + dv[a]) + (1.0 - flip_ratio) * vpic[a]
                    else:
                        p_v[p, a] = vpic[a]
                    for b in range(d):
                        if mode == 1:
                            p_C[p, a, b] = B[a, b] * apic_dinv if apic_dinv > 0.0 else L[a, b]
                        else:
                            p_C[p, a, b] = 0.0
            if do_gradient:
                update_volume(p, p_L, p_vol, p_rho, p_mass, L, dt)
