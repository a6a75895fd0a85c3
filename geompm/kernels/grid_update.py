"""Explicit update of grid velocities (momentum balance on the nodes).

v_old_i = (mv)_i / m_i,  v_i = v_old_i + dt (f_i / m_i + g)
for nodes with m_i > mass_eps; other nodes get zero velocity.  When P2G has
folded the force into the momentum ((mv)_i + dt f_i, mpm/grid.py), the
update is v_i = ((mv)_i + dt f_i) / m_i + dt g (``grid_update_folded``).
Arrays: g_mass (nn,), g_mom/g_force/g_vel/g_vel_old (nn, d), gravity (d,) [m/s2].
"""

from numba import njit, prange


@njit(parallel=True, fastmath=True, cache=True)
def grid_update(g_mass, g_mom, g_force, gravity, dt, mass_eps, g_vel, g_vel_old):
    nn, d = g_mom.shape
    for i in prange(nn):
        m = g_mass[i]
        if m > mass_eps:
            for a in range(d):
                vo = g_mom[i, a] / m
                g_vel_old[i, a] = vo
                g_vel[i, a] = vo + dt * (g_force[i, a] / m + gravity[a])
        else:
            for a in range(d):
                g_vel_old[i, a] = 0.0
                g_vel[i, a] = 0.0


@njit(parallel=True, fastmath=True, cache=True)
def momentum_to_velocity(g_mass, g_mom, mass_eps, g_vel):
    """v_i = (mv)_i / m_i (MUSL re-mapping of updated particle momenta)."""
    nn, d = g_mom.shape
    for i in prange(nn):
        m = g_mass[i]
        for a in range(d):
            g_vel[i, a] = g_mom[i, a] / m if m > mass_eps else 0.0


@njit(parallel=True, fastmath=True, cache=True)
def grid_update_folded(g_mass, g_mom, gravity, dt, mass_eps, g_vel):
    """v_i = ((mv)_i + dt f_i) / m_i + dt g, g_mom holding the folded momentum."""
    nn, d = g_mom.shape
    for i in prange(nn):
        m = g_mass[i]
        for a in range(d):
            g_vel[i, a] = g_mom[i, a] / m + dt * gravity[a] if m > mass_eps else 0.0
