"""Velocity gradient and volume update shared by the G2P kernels.

F_{n+1} = (I + dt L) F_n gives V_{n+1} = V0 det F_{n+1} = V_n det(I + dt L):
the volume is advanced by the determinant of the increment, so the
deformation gradient itself (72 bytes per particle) is never stored; no
law in geompm needs it (stress laws take L and rho, materials/base.py).
"""

from numba import njit


@njit(cache=True, inline="always")
def det_increment(L, dt):
    """det(I + dt L): the ratio V_{n+1} / V_n of a step (L a 3x3 velocity gradient [1/s])."""
    a00, a01, a02 = 1.0 + dt * L[0, 0], dt * L[0, 1], dt * L[0, 2]
    a10, a11, a12 = dt * L[1, 0], 1.0 + dt * L[1, 1], dt * L[1, 2]
    a20, a21, a22 = dt * L[2, 0], dt * L[2, 1], 1.0 + dt * L[2, 2]
    return a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20)


@njit(cache=True, inline="always")
def update_volume(p, p_L, p_vol, p_rho, p_mass, L, dt):
    """p_L[p] = L (3x3, plane strain: z row and column zero);  V <- V det(I + dt L);  rho = m / V."""
    for a in range(3):
        for b in range(3):
            p_L[p, a, b] = L[a, b]
    p_vol[p] *= det_increment(L, dt)
    p_rho[p] = p_mass[p] / p_vol[p]
