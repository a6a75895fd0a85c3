"""Grid shape functions along one axis (tensor products give 2D/3D weights).

``xi`` is the particle coordinate in node units, (x - origin) / h.  Each
function writes the weights ``w[k]`` and their x-derivatives ``dw[k]`` [1/m]
of the ``support`` nodes base, base+1, ... and returns ``base``.

- linear (kind 0): hat function, support 2.
- quadratic B-spline (kind 1), support 3 (Steffen, Kirby, Berzins 2008).
- cubic B-spline (kind 2), support 4.
"""

import math

from numba import njit

LINEAR, QUADRATIC, CUBIC = 0, 1, 2
KIND = {"linear": LINEAR, "quadratic": QUADRATIC, "cubic": CUBIC}
#: APIC inertia-like tensor D = h^2 * factor (diagonal, constant for B-splines):
#: Jiang et al. (2015) "The affine particle-in-cell method", SIGGRAPH, sec. 5.3.
APIC_D_FACTOR = {LINEAR: 0.0, QUADRATIC: 0.25, CUBIC: 1.0 / 3.0}


@njit(cache=True, inline="always")
def support(kind):
    return kind + 2


@njit(cache=True)
def axis_weights(xi, kind, inv_h, w, dw):
    if kind == 0:
        base = math.floor(xi)
        f = xi - base
        w[0] = 1.0 - f
        w[1] = f
        dw[0] = -inv_h
        dw[1] = inv_h
    elif kind == 1:
        base = math.floor(xi - 0.5)
        f = xi - base  # in [0.5, 1.5)
        a = 1.5 - f
        b = f - 1.0
        c = f - 0.5
        w[0] = 0.5 * a * a
        w[1] = 0.75 - b * b
        w[2] = 0.5 * c * c
        dw[0] = -a * inv_h
        dw[1] = -2.0 * b * inv_h
        dw[2] = c * inv_h
    else:
        base = math.floor(xi) - 1
        f = xi - base  # in [1, 2)
        for k in range(4):
            r = f - k
            s = 1.0 if r >= 0.0 else -1.0
            r = abs(r)
            if r < 1.0:
                w[k] = 0.5 * r * r * r - r * r + 2.0 / 3.0
                dw[k] = s * (1.5 * r * r - 2.0 * r) * inv_h
            else:
                t = 2.0 - r
                w[k] = t * t * t / 6.0
                dw[k] = s * (-0.5 * t * t) * inv_h
    return base
