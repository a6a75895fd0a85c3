"""The CPU backend's scatters of the saturated scheme: the water's P2G and the smoothing's P2G into one private
grid per chunk of particles, summed in chunk order (kernels/chunks.py), so a sum depends on the thread count
only, as the solid's P2G does.  The CUDA backend scatters the same rows with atomics (schemes/saturated/cuda.py).
Every other pass of the scheme is a per-item function of schemes/saturated/kernels.py that the backend's
generated loops run (Backend.each).
"""

from numba import njit, prange

from geompm.kernels.chunks import zero_rows
from geompm.schemes.saturated.kernels import NODE_WATER, PV, node_index, particle_stencil, water_scalars_one


@njit(parallel=True, cache=True)
def sum_chunks(c_grid, out):
    """out[i, a] = sum over chunks of c_grid[c, i, a], in chunk order (the private grids of water_p2g)."""
    nchunks = c_grid.shape[0]
    width = c_grid.shape[2]
    for i in prange(out.shape[0]):
        for a in range(width):
            t = 0.0
            for c in range(nchunks):
                t += c_grid[c, i, a]
            out[i, a] = t


@njit(parallel=True, cache=True)
def water_p2g(tag, p_x, p_vw, p_Cw, affine, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material, table,
              p_total, origin, h, kind, lo, nloc, c_grid, g_w):
    """Scatter the water into the private grids c_grid, rows [m_w, m_w v_w (d), the water's internal force
    sum V s n p grad N (d), c, V, V s p, V sigma (6)] (V the particles' volume, for the free-surface fill;
    p_total the total stress sigma, for the contact's pore water); sum_chunks adds them into g_w.  With
    ``affine`` (the solid's transfer APIC or MLS) the water's momentum carries its affine
    matrix, m_w (v_w + C_w (x_I - x_p)), as the solid's does: a water transferred by PIC would damp the
    mixture's shear and rotation each step through the drag that binds the phases, and the mixture would
    flow as if it were PIC (measured in docs/pore-water.md)."""
    n = p_x.shape[0]
    d = p_x.shape[1]
    nchunks = c_grid.shape[0]
    width = g_w.shape[1]
    nn = g_w.shape[0]
    S = len(tag)
    inv_h = 1.0 / h
    Sz = S if d == 3 else 1
    for c in prange(nchunks):
        g = c_grid[c]
        zero_rows(g, nn, width)
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
            m, npv, drag, vol, spv = water_scalars_one(p, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material,
                                                       table)
            q0 = m * p_vw[p, 0]
            q1 = m * p_vw[p, 1]
            q2 = m * p_vw[p, 2] if d == 3 else 0.0
            # the affine part m C_w (x_I - x_p), x_I - x_p = o + h (i, j, k): per axis a the row of m C_w
            c00 = c01 = c02 = c10 = c11 = c12 = c20 = c21 = c22 = 0.0
            o0 = o1 = o2 = 0.0
            if affine:
                c00, c01, c10, c11 = m * p_Cw[p, 0, 0], m * p_Cw[p, 0, 1], m * p_Cw[p, 1, 0], m * p_Cw[p, 1, 1]
                o0 = b[0] * h + origin[0] - p_x[p, 0]
                o1 = b[1] * h + origin[1] - p_x[p, 1]
                if d == 3:
                    c02, c12 = m * p_Cw[p, 0, 2], m * p_Cw[p, 1, 2]
                    c20, c21, c22 = m * p_Cw[p, 2, 0], m * p_Cw[p, 2, 1], m * p_Cw[p, 2, 2]
                    o2 = b[2] * h + origin[2] - p_x[p, 2]
            for i in range(S):
                ex = o0 + i * h
                for j in range(S):
                    ey = o1 + j * h
                    wij = wx[i] * wy[j]
                    fx = npv * dx[i] * wy[j]
                    fy = npv * wx[i] * dy[j]
                    fz = npv * wij
                    r0 = q0 + c00 * ex + c01 * ey
                    r1 = q1 + c10 * ex + c11 * ey
                    r2 = q2 + c20 * ex + c21 * ey
                    for k in range(Sz):
                        wt = wij * wz[k]
                        idx = node_index(b, lo, nloc, i, j, k, d)
                        g[idx, NODE_WATER.mass] += wt * m
                        g[idx, NODE_WATER.force_x] += fx * wz[k]
                        g[idx, NODE_WATER.force_y] += fy * wz[k]
                        if d == 3:
                            ez = o2 + k * h
                            g[idx, NODE_WATER.mom_x] += wt * (r0 + c02 * ez)
                            g[idx, NODE_WATER.mom_y] += wt * (r1 + c12 * ez)
                            g[idx, NODE_WATER.mom_z] += wt * (r2 + c22 * ez)
                            g[idx, NODE_WATER.force_z] += fz * dz[k]
                        else:
                            g[idx, NODE_WATER.mom_x] += wt * r0
                            g[idx, NODE_WATER.mom_y] += wt * r1
                        g[idx, NODE_WATER.drag] += wt * drag
                        g[idx, NODE_WATER.volume] += wt * vol
                        wv = wt * vol
                        g[idx, PV] += wt * spv
                        for q in range(6):
                            g[idx, PV + 1 + q] += wv * p_total[p, q]


@njit(parallel=True, cache=True)
def smooth_scatter(tag, p_x, p_val, p_drained, p_vol, origin, h, kind, lo, nloc, c_grid, g_vp):
    """The scatter of the smoothing S (kernels.smooth_node_one, smooth_gather_one): g_vp[i] =
    (sum N V, sum N V f) over the particles that hold pressure (p_drained 0), summed over the private grids in chunk order.  On several ranks the
    neighbours' partial sums are added to g_vp before the gather (parallel/slabs.py)."""
    n = p_x.shape[0]
    d = p_x.shape[1]
    nchunks = c_grid.shape[0]
    nn = g_vp.shape[0]
    S = len(tag)
    inv_h = 1.0 / h
    Sz = S if d == 3 else 1
    for c in prange(nchunks):
        g = c_grid[c]
        zero_rows(g, nn, 2)
        for p in range(c * n // nchunks, (c + 1) * n // nchunks):
            if p_drained[p] != 0.0:
                continue
            b, wx, dx, wy, dy, wz, dz = particle_stencil(p_x, p, origin, kind, inv_h, d)
            v = p_vol[p]
            vp = v * p_val[p]
            for i in range(S):
                for j in range(S):
                    wij = wx[i] * wy[j]
                    for k in range(Sz):
                        wt = wij * wz[k]
                        idx = node_index(b, lo, nloc, i, j, k, d)
                        g[idx, 0] += wt * v
                        g[idx, 1] += wt * vp
    for i in prange(nn):
        v = 0.0
        vp = 0.0
        for c in range(nchunks):
            v += c_grid[c, i, 0]
            vp += c_grid[c, i, 1]
        g_vp[i, 0] = v
        g_vp[i, 1] = vp
