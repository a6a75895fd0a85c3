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

from numba import njit, prange


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
