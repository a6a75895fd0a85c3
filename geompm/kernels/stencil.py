"""Shape-function weights as register values, with the support known at compile time.

The B-splines of shape.py come back from ``shape.axis_stencil`` as tuples
``(base, w, dw)`` with ``w``/``dw`` padded to 4 entries, so that a kernel keeps
them in registers instead of a scratch array.  The transfer kernels loop over
``range(len(tag))`` where ``tag`` is ``stencil_tag(kind)``, a tuple of zeros whose *length* is the support: numba
compiles one specialisation per length, the loops get a constant trip count
and are unrolled.  With a run-time support the same 3D G2P ran 1.55x slower
(docs/performance.md).  A tuple argument, unlike a closure or a function
argument, keeps the kernels in numba's on-disk cache.
"""

from numba import njit

from geompm.kernels.shape import axis_stencil, support

__all__ = ["AFFINE", "APIC", "FLIP", "LINEAR_APIC", "MLS", "PIC", "SCHEMES", "axis_stencil", "linear_apic",
           "mls_derivatives", "scheme_tag", "stencil_tag"]

#: the velocity-transfer schemes in the order of their compile-time tags: a kernel reads
#: ``mode = len(scheme) - 1`` and compares it with these names, constants numba folds into every
#: branch on them, so each scheme runs its own specialisation with no run-time test of the scheme
SCHEMES = ("pic", "apic", "flip", "mls")
PIC, APIC, FLIP, MLS = (SCHEMES.index(s) for s in ("pic", "apic", "flip", "mls"))
#: the transfers whose particles carry an affine matrix (the water of saturated soil then carries one too)
AFFINE = ("apic", "mls")
#: why 'apic' with linear hats is refused for saturated soil and warned for a dry case (measured:
#: benchmarks/envelope/free_flight.py, docs/numerical-envelope.md, Linear hats and APIC)
LINEAR_APIC = ("'apic' with grid.shape_function 'linear' is unstable in motion: with linear hats the affine "
               "matrix is the velocity gradient and its inertia D = f (1 - f) h^2 vanishes at the nodes, so a "
               "moving particle carries round-off in C from where it costs no energy to where it does (a "
               "linear-elastic block in free flight at 3 m/s leaves the grid after 0.13 s dry, 0.33 s "
               "saturated); set solver.transfer to 'flip' or 'pic', or grid.shape_function to 'quadratic'")


def linear_apic(case) -> bool:
    """Whether a case asks for APIC with linear hats (LINEAR_APIC)."""
    return case.solver.transfer == "apic" and case.grid.shape_function == "linear"


def stencil_tag(kind: int) -> tuple:
    """The compile-time support marker of a shape-function kind (see module docstring)."""
    return (0.0,) * support(kind)


def scheme_tag(transfer: str) -> tuple:
    """The compile-time marker of a transfer scheme (``SCHEMES``): a tuple whose length is its
    position + 1."""
    return (0.0,) * (SCHEMES.index(transfer) + 1)


@njit(cache=True, inline="always")
def mls_derivatives(w, o, h, dinv):
    """MLS-MPM pseudo-derivatives along one axis, D^-1 w_k (o + k h) [1/m]: the factors of
    grad w_ip ~ D^-1 w_ip (x_i - x_p) (Hu et al. 2018), o the first node's offset x_0 - x_p."""
    return (dinv * w[0] * o, dinv * w[1] * (o + h), dinv * w[2] * (o + 2.0 * h),
            dinv * w[3] * (o + 3.0 * h))
