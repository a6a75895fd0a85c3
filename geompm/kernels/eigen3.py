"""Eigenvalues and eigenvectors of a symmetric 3x3 tensor, in registers.

Cyclic Jacobi method (Golub & Van Loan 2013, Matrix Computations, 4th ed.,
sec. 8.5; the rotation in the stable form of Rutishauser 1966): each
rotation J(p, q, theta) zeroes the off-diagonal entry a_pq with

    theta = (a_qq - a_pp) / (2 a_pq),   t = sgn(theta) / (|theta| + sqrt(theta^2 + 1)),
    c = 1 / sqrt(1 + t^2),  s = t c,
    a_pp <- a_pp - t a_pq,  a_qq <- a_qq + t a_pq,  a_pq <- 0,
    a_rp <- c a_rp - s a_rq,  a_rq <- s a_rp + c a_rq   (r the third index),

and the eigenvector columns turn as v_p <- c v_p - s v_q, v_q <- s v_p + c v_q.
Sweeps over the three pairs converge quadratically; they stop when the
off-diagonal part is below machine precision of the diagonal, which gives
eigenvalues accurate to a few ulp of the tensor's norm also when two or three
of them are equal (where closed-form trigonometric solutions lose digits).

Everything is scalars and tuples: no array is allocated and no LAPACK is
called, so the function runs inside a numba stress loop without scipy and can
be compiled as a GPU device function.  Verified against ``numpy.linalg.eigh``
in tests/unit/test_eigen3.py.
"""

from __future__ import annotations

import math

from numba import njit

MAX_SWEEPS = 30  # 3x3 matrices converge in <= 6 sweeps; the cap only bounds a NaN input


@njit(cache=True, inline="always")
def _rotate(app, aqq, apq, arp, arq, vp0, vp1, vp2, vq0, vq1, vq2):
    """One Jacobi rotation zeroing a_pq: the new (a_pp, a_qq, a_rp, a_rq, v_p, v_q)."""
    theta = (aqq - app) / (2.0 * apq)
    t = 1.0 / (abs(theta) + math.sqrt(theta * theta + 1.0))
    if theta < 0.0:
        t = -t
    c = 1.0 / math.sqrt(t * t + 1.0)
    s = t * c
    return (app - t * apq, aqq + t * apq, c * arp - s * arq, s * arp + c * arq,
            c * vp0 - s * vq0, c * vp1 - s * vq1, c * vp2 - s * vq2,
            s * vp0 + c * vq0, s * vp1 + c * vq1, s * vp2 + c * vq2)


@njit(cache=True)
def sym_eig3(a00, a11, a22, a01, a12, a02):
    """Eigen-decomposition of the symmetric tensor [[a00, a01, a02], [a01, a11, a12], [a02, a12, a22]].

    Returns ``(w0, w1, w2, v00, v10, v20, v01, v11, v21, v02, v12, v22)``:
    the eigenvalues ascending (w0 <= w1 <= w2), then the eigenvectors as
    columns, ``(v0k, v1k, v2k)`` belonging to ``wk`` (orthonormal, as
    ``numpy.linalg.eigh`` returns them, up to sign).
    """
    # eigenvector columns c0, c1, c2 (component index first)
    c00, c10, c20 = 1.0, 0.0, 0.0
    c01, c11, c21 = 0.0, 1.0, 0.0
    c02, c12, c22 = 0.0, 0.0, 1.0
    for _ in range(MAX_SWEEPS):
        off = a01 * a01 + a12 * a12 + a02 * a02
        diag = a00 * a00 + a11 * a11 + a22 * a22
        if not off > 1e-36 * diag:  # also stops on a zero tensor (and on NaN)
            break
        if a01 != 0.0:  # pair (0, 1), r = 2
            a00, a11, a02, a12, c00, c10, c20, c01, c11, c21 = _rotate(
                a00, a11, a01, a02, a12, c00, c10, c20, c01, c11, c21)
            a01 = 0.0
        if a02 != 0.0:  # pair (0, 2), r = 1
            a00, a22, a01, a12, c00, c10, c20, c02, c12, c22 = _rotate(
                a00, a22, a02, a01, a12, c00, c10, c20, c02, c12, c22)
            a02 = 0.0
        if a12 != 0.0:  # pair (1, 2), r = 0
            a11, a22, a01, a02, c01, c11, c21, c02, c12, c22 = _rotate(
                a11, a22, a12, a01, a02, c01, c11, c21, c02, c12, c22)
            a12 = 0.0
    # sort ascending, carrying the columns (three compare-and-swaps)
    if a00 > a11:
        a00, a11 = a11, a00
        c00, c10, c20, c01, c11, c21 = c01, c11, c21, c00, c10, c20
    if a11 > a22:
        a11, a22 = a22, a11
        c01, c11, c21, c02, c12, c22 = c02, c12, c22, c01, c11, c21
    if a00 > a11:
        a00, a11 = a11, a00
        c00, c10, c20, c01, c11, c21 = c01, c11, c21, c00, c10, c20
    return a00, a11, a22, c00, c10, c20, c01, c11, c21, c02, c12, c22
