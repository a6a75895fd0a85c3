"""The register Jacobi eigen-solver (geompm/kernels/eigen3.py) against numpy.linalg.eigh (LAPACK).

Checks, to 1e-12 relative to the tensor's largest eigenvalue magnitude: the
eigenvalues, the reconstruction V diag(w) V^T = A, and V^T V = I, on random
symmetric tensors of stress-like scale and on the degenerate ones a stress
loop meets (hydrostatic: three equal eigenvalues; triaxial compression and
extension: two equal; a zero tensor; eigenvalues 1e-12 apart; diagonal and
rank-one tensors).  Where the eigenvalues are well separated the eigenvectors
themselves must agree with LAPACK's up to sign.
"""

import numpy as np
import pytest

from geompm.kernels.eigen3 import sym_eig3

TOL = 1e-12


def _ours(A):
    e = sym_eig3(A[0, 0], A[1, 1], A[2, 2], A[0, 1], A[1, 2], A[0, 2])
    w = np.array(e[:3])
    V = np.array([[e[3], e[6], e[9]], [e[4], e[7], e[10]], [e[5], e[8], e[11]]])
    return w, V


def _rotation(rng):
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    return q * np.sign(np.diag(r))


def _check(A):
    w, V = _ours(A)
    w_ref, V_ref = np.linalg.eigh(A)
    scale = max(np.abs(w_ref).max(), np.finfo(float).tiny)
    assert np.all(np.diff(w) >= 0.0)
    assert np.abs(w - w_ref).max() <= TOL * scale
    assert np.abs(V @ np.diag(w) @ V.T - A).max() <= TOL * scale
    assert np.abs(V.T @ V - np.eye(3)).max() <= TOL
    return w, V, w_ref, V_ref


def test_random_symmetric_tensors_match_lapack():
    """2 000 random tensors with entries of 1 Pa to 1 GPa (log-uniform scales), eigenvectors up to sign."""
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(2000):
        B = rng.standard_normal((3, 3)) * 10.0 ** rng.uniform(0, 9)
        A = 0.5 * (B + B.T)
        w, V, w_ref, V_ref = _check(A)
        gap = np.diff(w_ref).min() / np.abs(w_ref).max()
        if gap > 1e-3:
            align = np.abs(np.sum(V * V_ref, axis=0))
            worst = max(worst, np.abs(align - 1.0).max())
    assert worst <= 1e-10


@pytest.mark.parametrize("eigs", [
    (-1e5, -1e5, -1e5),            # hydrostatic: three equal
    (-3e5, -1e5, -1e5),            # triaxial compression: sigma_2 = sigma_3
    (-3e5, -3e5, -1e5),            # triaxial extension: sigma_1 = sigma_2
    (0.0, 0.0, 0.0),               # zero tensor
    (-1e5, -1e5 * (1 + 1e-12), 2e4),  # two eigenvalues 1e-12 apart
    (0.0, 0.0, 7e6),               # rank one
    (-2.5e4, 0.0, 2.5e4),          # pure shear
])
def test_degenerate_tensors_in_random_orientations(eigs):
    """Tensors Q diag(eigs) Q^T in 200 random orientations, plus the diagonal tensor itself."""
    rng = np.random.default_rng(11)
    _check(np.diag(eigs))
    for _ in range(200):
        Q = _rotation(rng)
        A = Q @ np.diag(eigs) @ Q.T
        A = 0.5 * (A + A.T)
        _check(A)


def test_nan_input_stops_and_returns_nan():
    """A NaN tensor must not loop: the sweep cap bounds it and NaN comes out (the health check sees it)."""
    e = sym_eig3(np.nan, 1.0, 2.0, 0.5, 0.1, 0.2)
    assert np.isnan(np.array(e[:3])).any()
