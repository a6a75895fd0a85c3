"""The one Voigt order of geompm, used by every array named ``*_stress``.

``p_stress (n, 6)`` holds the symmetric Cauchy stress [Pa] as
(xx, yy, zz, xy, yz, xz), tension positive.  This is also the component order
ParaView expects for a 6-component symmetric tensor.  Plane strain keeps
sigma_zz; xz and yz stay zero.
"""

import numpy as np
from numba import njit

#: VOIGT_INDEX[a, b] is the Voigt slot of tensor component (a, b).
VOIGT_INDEX = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2]], dtype=np.int64)


@njit(cache=True, inline="always")
def jaumann_increment(s, L, dt):
    """dt * (W s - s W) in Voigt as a 6-tuple, W = (L - L^T)/2 the spin.

    Adding ``out`` to a stress updated with a material-frame rate makes the
    update objective (Jaumann rate), e.g. Belytschko et al., Nonlinear Finite
    Elements for Continua and Structures (2000), sec. 5.7.
    """
    w01 = 0.5 * (L[0, 1] - L[1, 0])
    w02 = 0.5 * (L[0, 2] - L[2, 0])
    w12 = 0.5 * (L[1, 2] - L[2, 1])
    sxx, syy, szz, sxy, syz, sxz = s[0], s[1], s[2], s[3], s[4], s[5]
    # (W s - s W) = W s + (W s)^T since W^T = -W and s symmetric
    return (
        dt * 2.0 * (w01 * sxy + w02 * sxz),
        dt * 2.0 * (-w01 * sxy + w12 * syz),
        dt * 2.0 * (-w02 * sxz - w12 * syz),
        dt * (w01 * (syy - sxx) + w02 * syz + w12 * sxz),
        dt * (-w01 * sxz + w12 * (szz - syy) - w02 * sxy),
        dt * (w02 * (szz - sxx) + w01 * syz - w12 * sxy),
    )
