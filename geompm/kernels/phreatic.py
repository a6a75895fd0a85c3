"""The pore pressure under a water table and the total stress it makes (mpm/water_table.py).

A planar water table at height z_wt along its unit normal n (out of the ground) with the water seeping
parallel to it has equipotentials normal to the table, so the pressure grows with the distance below it at
the rate of the gravity component along n:

    p(x) = rho_w (-g . n) max(z_wt - x . n, 0)        [Pa, compression positive]

With n against gravity this is hydrostatic, rho_w |g| depth; under a table parallel to an infinite slope of
angle beta it is gamma_w z cos^2(beta) at vertical depth z (the pressure of slope-parallel seepage: Skempton
& DeLory 1957, Proc. 4th ICSMFE 2:378; Duncan, Wright & Brandon 2014, sec. 6.2).  Above the table p = 0 (no
suction).  The grid then sees the total stress sigma = sigma' - p I of the effective stress sigma' that the
law integrates (Terzaghi's principle), with p weighed by V0 / V: a particle's mass is fixed, but a drained
soil that dilates draws water into its pores (and one that compacts expels it), so its true weight changes by
rho_w (V - V0) g.  The pressure's force on a particle, -V grad p, is its uplift rho_w (-g . n) V; taken as
-V0 grad p, the particle's buoyant weight stays (m - rho_w V0) g, as it is with the water it drew in
weighed, instead of falling with its dilation until it floats (a strongly dilating soil, psi = 40 deg,
doubles its volume in a shear band).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from geompm.kernels.lattice import bilinear, trilinear
from geompm.kernels.shape import point_stencil


@njit(parallel=True, cache=True)
def phreatic_pressure(p_x, p_material, acts, normal, height, gradient, out):
    """out[p] = gradient * max(height - x_p . normal, 0) [Pa] for a particle of a material with acts[m] = 1,
    else 0; gradient = rho_w (-g . n) [Pa/m]."""
    d = p_x.shape[1]
    for p in prange(p_x.shape[0]):
        depth = height
        for a in range(d):
            depth -= p_x[p, a] * normal[a]
        out[p] = gradient * depth * acts[p_material[p]] if depth > 0.0 else 0.0


@njit(parallel=True, cache=True)
def polyline_pressure(p_x, p_material, acts, xs, zs, rise, gradient, out):
    """out[p] = gradient * max(z_s(x) + rise - y, 0) in 2D: hydrostatic along the vertical below the phreatic
    line through (xs, zs) (xs increasing, held level beyond its ends), y up; gradient = rho_w |g| [Pa/m]."""
    for p in prange(p_x.shape[0]):
        depth = np.interp(p_x[p, 0], xs, zs) + rise - p_x[p, 1]
        out[p] = gradient * depth * acts[p_material[p]] if depth > 0.0 else 0.0


@njit(parallel=True, cache=True)
def lattice_pressure(p_x, p_material, acts, z, x0, y0, dx, dy, rise, gradient, out):
    """out[p] = gradient * max(z_s(x, y) + rise - z, 0) in 3D below a phreatic surface given on a lattice
    (kernels/lattice.bilinear: z[i, j] at x0 + i dx, y0 + j dy, the edge values continued beyond), z up."""
    for p in prange(p_x.shape[0]):
        depth = bilinear(z, x0, y0, dx, dy, p_x[p, 0], p_x[p, 1]) + rise - p_x[p, 2]
        out[p] = gradient * depth * acts[p_material[p]] if depth > 0.0 else 0.0


@njit(parallel=True, cache=True)
def pond_pressure(p_x, p_material, acts, up, level, gradient, out_pond, p_head):
    """out_pond[p] = gradient * max(level - x_up, 0) (a pond's hydrostatic pressure, gradient = rho_w |g|,
    axis ``up`` against gravity) on the soils with acts = 1, and p_head[p] raised to it where the pond's
    head is the higher (under a pond the water in the soil stands at least at the pond's level)."""
    for p in prange(p_x.shape[0]):
        depth = level - p_x[p, up]
        q = gradient * depth * acts[p_material[p]] if depth > 0.0 else 0.0
        out_pond[p] = q
        if q > p_head[p]:
            p_head[p] = q


@njit(cache=True)
def scatter_buoyancy(p_x, p_pond, p_vol0, weight, up, origin, inv_h, kind, lo, nloc, scale, g_force):
    """g_force[k, up] += scale * w_kp rho_w |g| V0_p over the submerged particles (p_pond > 0): the pond's
    buoyancy, the force -V0 grad p_pond that stands for the pond's pressure on the soil's submerged faces
    (mpm/water_table.py), an external nodal force as gravity is (Cundall's local damping sees it); ``scale``
    1 into the split force, dt where P2G folds the force into the momentum.  Serial (no races): its cost is
    the submerged particles' only."""
    d = p_x.shape[1]
    for p in range(p_x.shape[0]):
        if p_pond[p] <= 0.0:
            continue
        f = scale * weight * p_vol0[p]
        b0, w0, b1, w1, b2, w2, s2 = point_stencil(p_x[p], origin, inv_h, kind)
        for i in range(4):
            i0 = b0 + i - lo[0]
            if w0[i] == 0.0 or i0 < 0 or i0 >= nloc[0]:
                continue
            for j in range(4):
                j0 = b1 + j - lo[1]
                if w1[j] == 0.0 or j0 < 0 or j0 >= nloc[1]:
                    continue
                for l in range(s2):
                    w = w0[i] * w1[j] * w2[l]
                    if w == 0.0:
                        continue
                    k = i0 * nloc[1] + j0
                    if d == 3:
                        l0 = b2 + l - lo[2]
                        if l0 < 0 or l0 >= nloc[2]:
                            continue
                        k = k * nloc[2] + l0
                    g_force[k, up] += w * f


@njit(parallel=True, cache=True)
def total_stress(p_stress, p_table, p_vol, p_vol0, out):
    """out = sigma' - (V0 / V) p I (Voigt, tension positive; p = p_table, the water table's pore pressure,
    compression positive, not the saturated scheme's p_pore): the stress the grid sees (module docstring)."""
    for p in prange(p_stress.shape[0]):
        pore = p_table[p] * p_vol0[p] / p_vol[p]
        for k in range(3):
            out[p, k] = p_stress[p, k] - pore
        for k in range(3, 6):
            out[p, k] = p_stress[p, k]


@njit(parallel=True, cache=True)
def pore_work(p_table, p_vol, p_vol0, p_x, p_x0, normal, gradient):
    """An upper bound of the work a water table has done on the soil [J]: sum p max(V - V0, 0) (the water
    that flows in at pressure p as the skeleton dilates) + sum rho_w (-g . n) V max((x - x0) . n, 0) (the
    uplift on a particle that rose); the run's health check adds it to the energy the run can supply."""
    d = p_x.shape[1]
    w = 0.0
    for p in prange(p_x.shape[0]):
        rise = 0.0
        for a in range(d):
            rise += (p_x[p, a] - p_x0[p, a]) * normal[a]
        uplift = gradient * p_vol[p] * rise if (rise > 0.0 and p_table[p] > 0.0) else 0.0
        w += p_table[p] * max(p_vol[p] - p_vol0[p], 0.0) + uplift
    return w


@njit(parallel=True, cache=True)
def head_pressure_2d(p_x, p_material, acts, head, origin, h, weight, out):
    """out[p] = weight * max(H(x) - y, 0) for a particle of a soil with acts = 1: H the steady seepage's head on
    the grid's nodes (mpm/seepage.py), bilinear; weight = rho_w |g| [Pa/m]."""
    for p in prange(p_x.shape[0]):
        depth = bilinear(head, origin[0], origin[1], h, h, p_x[p, 0], p_x[p, 1]) - p_x[p, 1]
        out[p] = weight * depth * acts[p_material[p]] if depth > 0.0 else 0.0


@njit(parallel=True, cache=True)
def head_pressure_3d(p_x, p_material, acts, head, origin, h, weight, out):
    """head_pressure_2d in 3D: H trilinear, z the vertical."""
    for p in prange(p_x.shape[0]):
        depth = trilinear(head, origin[0], origin[1], origin[2], h, p_x[p, 0], p_x[p, 1], p_x[p, 2]) - p_x[p, 2]
        out[p] = weight * depth * acts[p_material[p]] if depth > 0.0 else 0.0
