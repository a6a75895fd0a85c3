"""Shape-function weights as register values, with the support known at compile time.

The same B-splines as shape.py (linear, quadratic, cubic; Steffen, Kirby &
Berzins 2008), returned as tuples ``(base, w, dw)`` with ``w``/``dw`` padded to
4 entries, so that a kernel keeps them in registers instead of a scratch
array.  The transfer kernels loop over ``range(len(tag))`` where ``tag`` is
``stencil_tag(kind)``, a tuple of zeros whose *length* is the support: numba
compiles one specialisation per length, the loops get a constant trip count
and are unrolled.  With a run-time support the same 3D G2P ran 1.55x slower
(docs/performance.md).  A tuple argument, unlike a closure or a function
argument, keeps the kernels in numba's on-disk cache.
"""

import math

from numba import njit

from .shape import support


def stencil_tag(kind: int) -> tuple:
    """The compile-time support marker of a shape-function kind (see module docstring)."""
    return (0.0,) * support(kind)


@njit(cache=True, inline="always")
def axis_stencil(xi, kind, inv_h):
    """Weights w and x-derivatives dw [1/m] of the nodes base, base+1, ... at xi = (x - origin)/h."""
    if kind == 1:
        base = math.floor(xi - 0.5)
        f = xi - base  # in [0.5, 1.5)
        a = 1.5 - f
        b = f - 1.0
        c = f - 0.5
        return (int(base), (0.5 * a * a, 0.75 - b * b, 0.5 * c * c, 0.0),
                (-a * inv_h, -2.0 * b * inv_h, c * inv_h, 0.0))
    if kind == 0:
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


@njit(cache=True, inline="always")
def mls_derivatives(w, o, h, dinv):
    """MLS-MPM pseudo-derivatives along one axis, D^-1 w_k (o + k h) [1/m]: the factors of
    grad w_ip ~ D^-1 w_ip (x_i - x_p) (Hu et al. 2018), o the first node's offset x_0 - x_p."""
    return (dinv * w[0] * o, dinv * w[1] * (o + h), dinv * w[2] * (o + 2.0 * h),
            dinv * w[3] * (o + 3.0 * h))
