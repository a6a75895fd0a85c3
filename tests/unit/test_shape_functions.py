"""Shape functions, checked through the real P2G kernel in 2D and 3D.

Reference: the B-spline identities every MPM basis must satisfy (e.g. Steffen,
Kirby & Berzins 2008, Int. J. Numer. Meth. Eng. 76:922):
  sum_i w_i = 1 (partition of unity), sum_i grad w_i = 0,
  sum_i w_i (x_i - x_p) = 0 (linear completeness),
  sum_i grad w_i (x) x_i = I.
"""

import numpy as np
import pytest

from geompm.kernels.shape import KIND
from tests.support.reference_transfer import p2g


def _scatter(x, v, C, stress, kind, h=0.1):
    d = x.shape[1]
    n = len(x)
    origin = np.zeros(d)
    lo = np.full(d, -3, np.int64)
    nloc = np.full(d, 16, np.int64)
    nn = int(np.prod(nloc))
    bufs = (np.zeros((1, nn)), np.zeros((1, nn, d)), np.zeros((1, nn, d)))
    g = (np.zeros(nn), np.zeros((nn, d)), np.zeros((nn, d)))
    p2g(x, v, C, np.ones(n), np.ones(n), stress, origin, h, kind, lo, nloc, *bufs, True, *g)
    idx = np.stack(np.unravel_index(np.arange(nn), tuple(nloc)), axis=1) + lo
    return g, idx * h


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("shape", ["linear", "quadratic", "cubic"])
def test_partition_of_unity_and_gradient_identities(dim, shape):
    """At 50 random points: sum w = 1, sum grad w = 0, sum w (x_i - x_p) = 0, sum grad w x_i^T = I."""
    rng = np.random.default_rng(1)
    for _ in range(50):
        x = rng.uniform(0.0, 0.9, size=(1, dim))
        stress = np.zeros((1, 6))
        stress[0, :3] = -1.0  # sigma = -I  ->  f_i = grad w_i (volume 1)
        C = np.eye(dim)[None]  # v = 0, C = I  ->  (mv)_i = w_i (x_i - x_p)
        (g_mass, g_mom, g_force), xi = _scatter(x, np.zeros((1, dim)), C, stress, KIND[shape])
        assert g_mass.sum() == pytest.approx(1.0, abs=1e-13)
        np.testing.assert_allclose(g_force.sum(axis=0), 0.0, atol=1e-11)
        np.testing.assert_allclose(g_mom.sum(axis=0), 0.0, atol=1e-14)
        np.testing.assert_allclose(g_force.T @ xi, np.eye(dim), atol=1e-11)
        assert (g_mass >= -1e-15).all()
