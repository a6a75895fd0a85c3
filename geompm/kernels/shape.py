"""Grid shape functions along one axis (tensor products give 2D/3D weights).

``xi`` is the particle coordinate in node units, (x - origin) / h.
``axis_stencil`` returns ``base`` and the weights ``w[k]`` and x-derivatives
``dw[k]`` [1/m] of the ``support`` nodes base, base+1, ...; ``axis_weights``
writes them into arrays.

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


@njit(cache=True, inline="always")
def axis_stencil(xi, kind, inv_h):
    """Weights w and x-derivatives dw [1/m] of the nodes base, base+1, ... at xi = (x - origin)/h,
    as 4-tuples (zero beyond the support): the register form the 2D/3D kernels use."""
    if kind == QUADRATIC:
        base = math.floor(xi - 0.5)
        f = xi - base  # in [0.5, 1.5)
        a = 1.5 - f
        b = f - 1.0
        c = f - 0.5
        return (int(base), (0.5 * a * a, 0.75 - b * b, 0.5 * c * c, 0.0),
                (-a * inv_h, -2.0 * b * inv_h, c * inv_h, 0.0))
    if kind == LINEAR:
        base = math.floor(xi)
        f = xi - base
        return int(base), (1.0 - f, f, 0.0, 0.0), (-inv_h, inv_h, 0.0, 0.0)
    base = math.floor(xi) - 1
    f = xi - base  # in [1, 2): distances to the 4 nodes are f, f-1 (inner), 2-f... (outer)
    r0, r1, r2, r3 = f, f - 1.0, 2.0 - f, 3.0 - f  # |x - x_k| / h for k = 0..3
    t0, t3 = 2.0 - r0, 2.0 - r3
    w = (t0 * t0 * t0 / 6.0, 0.5 * r1 * r1 * r1 - r1 * r1 + 2.0 / 3.0,
         0.5 * r2 * r2 * r2 - r2 * r2 + 2.0 / 3.0, t3 * t3 * t3 / 6.0)
    dw = (-0.5 * t0 * t0 * inv_h, (1.5 * r1 * r1 - 2.0 * r1) * inv_h,
          -(1.5 * r2 * r2 - 2.0 * r2) * inv_h, 0.5 * t3 * t3 * inv_h)
    return int(base), w, dw




@njit(cache=True)
def axis_weights(xi, kind, inv_h, w, dw):
    """axis_stencil written into the arrays w, dw (the generic kernel's form); returns base."""
    base, wt, dwt = axis_stencil(xi, kind, inv_h)
    for k in range(support(kind)):
        w[k] = wt[k]
        dw[k] = dwt[k]
    return base


@njit(cache=True, inline="always")
def point_stencil(x, origin, inv_h, kind):
    """The stencil of a point x (2 or 3 coordinates) for a scatter of one value per node: (b0, w0, b1, w1, b2,
    w2, n2), the bases and weights along each axis (axis_stencil) and the node count along z (1 in 2D, with
    w2 = (1, 0, 0, 0) and b2 = 0)."""
    b0, w0, _ = axis_stencil((x[0] - origin[0]) * inv_h, kind, inv_h)
    b1, w1, _ = axis_stencil((x[1] - origin[1]) * inv_h, kind, inv_h)
    if x.shape[0] == 3:
        b2, w2, _ = axis_stencil((x[2] - origin[2]) * inv_h, kind, inv_h)
        return b0, w0, b1, w1, b2, w2, 4
    return b0, w0, b1, w1, 0, (1.0, 0.0, 0.0, 0.0), 1

