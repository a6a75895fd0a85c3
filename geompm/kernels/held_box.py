"""The held step's box (engine/held_step.py) and its test, ``fits``: one ``@njit`` function that the CUDA backend
runs in a one-thread kernel (backend/cuda_kernels.held_gate) and the CPU backend on the host.

The box, one float64 array: the largest |v| [m/s] and |L_ii| [1/s] allowed, the space dimension, the material
blocks, the particles' lowest and highest coordinates per axis [m] (three slots each), then per block the
lowest and the highest density [kg/m3].
"""

from __future__ import annotations

import math

from numba import njit

from geompm.kernels.step_end import BAD, END_ROW, RHO_MAX, RHO_MIN, SPEED

#: the box's layout: largest |v| [m/s], largest |L_ii| [1/s], space dimension, material blocks, the particles'
#: lowest and highest coordinates per axis [m], then per block the lowest and the highest density [kg/m3]
V_ALLOW, RATE_ALLOW, DIM, BLOCKS, X_LO, X_HI, RHO = 0, 1, 2, 3, 4, 7, 10


@njit(cache=True)
def fits(rows, rate, box) -> bool:
    """Whether a step may be taken at the held step from the state whose step-end ``rows`` (blocks * END_ROW,
    kernels/step_end.py) and largest |L_ii| ``rate`` [1/s] are given: inside ``box`` (engine/held_step.limits), every
    particle finite.  A NaN anywhere fails a comparison, so it fails."""
    d, nb = int(box[DIM]), int(box[BLOCKS])
    if not rate <= box[RATE_ALLOW]:
        return False
    for k in range(nb):
        r = k * END_ROW
        if not (rows[r + BAD] == 0.0 and rows[r + SPEED] <= box[V_ALLOW]):
            return False
        if not (-rows[r + RHO_MIN] >= box[RHO + k] and rows[r + RHO_MAX] <= box[RHO + nb + k]):
            return False
        for a in range(d):
            if not (math.isfinite(rows[r + 6 + a]) and -rows[r + a] >= box[X_LO + a] and
                    rows[r + 3 + a] <= box[X_HI + a]):
                return False
    return True


