"""P2G then G2P conserves mass, linear momentum and (APIC) angular momentum.

Reference: Jiang, Schroeder, Selle, Teran & Stomakhin (2015) "The affine
particle-in-cell method", ACM Trans. Graph. 34(4):51, sec. 5: with
D = h^2/4 (quadratic) or h^2/3 (cubic B-spline), the angular momentum
sum m_p (x_p x v_p) + m_p eps:(C_p D)^T is preserved exactly by both transfers.
"""

import numpy as np
import pytest

from geompm.kernels.grid_update import momentum_to_velocity
from geompm.kernels.shape import APIC_D_FACTOR, KIND

from tests.support.transfer_kernels import kernels as _kernels

H = 0.1


def _angular(x, v, C, m, D):
    """Total angular momentum about the origin (z component in 2D, vector in 3D)."""
    d = x.shape[1]
    if d == 2:
        return np.sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0] + D * (C[:, 1, 0] - C[:, 0, 1])))
    orbital = np.cross(x, v) * m[:, None]
    spin = np.stack([C[:, 2, 1] - C[:, 1, 2], C[:, 0, 2] - C[:, 2, 0], C[:, 1, 0] - C[:, 0, 1]], axis=1)
    return (orbital + D * spin * m[:, None]).sum(axis=0)


def _grid_angular(g_mass, g_vel, xi):
    if xi.shape[1] == 2:
        return np.sum(g_mass * (xi[:, 0] * g_vel[:, 1] - xi[:, 1] * g_vel[:, 0]))
    return (np.cross(xi, g_vel) * g_mass[:, None]).sum(axis=0)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("shape", ["quadratic", "cubic"])
@pytest.mark.parametrize("nchunks", [1, 3])
@pytest.mark.parametrize("impl", ["generic", "specialised"])
def test_apic_round_trip_conserves(dim, shape, nchunks, impl):
    p2g, g2p = _kernels(impl, dim)
    rng = np.random.default_rng(7)
    n = 400
    kind = KIND[shape]
    x = rng.uniform(0.3, 1.0, size=(n, dim))
    v = rng.normal(size=(n, dim))
    C = rng.normal(size=(n, dim, dim))
    m = rng.uniform(0.5, 2.0, size=n)
    D = APIC_D_FACTOR[kind] * H * H
    origin = np.zeros(dim)
    lo = np.zeros(dim, np.int64)
    nloc = np.full(dim, 16, np.int64)
    nn = int(np.prod(nloc))
    bufs = (np.zeros((nchunks, nn)), np.zeros((nchunks, nn, dim)), np.zeros((nchunks, nn, dim)))
    g_mass, g_mom, g_force = np.zeros(nn), np.zeros((nn, dim)), np.zeros((nn, dim))
    p2g(x, v, C, m, np.ones(n), np.zeros((n, 6)), origin, H, kind, lo, nloc, *bufs, False, g_mass, g_mom, g_force)
    g_vel = np.zeros((nn, dim))
    momentum_to_velocity(g_mass, g_mom, 0.0, g_vel)
    xi = (np.stack(np.unravel_index(np.arange(nn), tuple(nloc)), axis=1) + lo) * H

    assert g_mass.sum() == pytest.approx(m.sum(), rel=1e-13)
    np.testing.assert_allclose(g_mom.sum(axis=0), (m[:, None] * v).sum(axis=0), rtol=1e-12, atol=1e-11)
    L0 = _angular(x, v, C, m, D)
    np.testing.assert_allclose(_grid_angular(g_mass, g_vel, xi), L0, rtol=1e-11, atol=1e-11)

    v2, C2 = v.copy(), C.copy()
    g2p(x, v2, C2, np.zeros((n, 3, 3)), np.ones(n), np.ones(n), m, g_vel, g_vel.copy(),
        origin, H, kind, lo, nloc, 0.0, 1, 0.0, 1.0 / D, True, False, False)
    np.testing.assert_allclose((m[:, None] * v2).sum(axis=0), (m[:, None] * v).sum(axis=0), rtol=1e-12, atol=1e-11)
    np.testing.assert_allclose(_angular(x, v2, C2, m, D), L0, rtol=1e-11, atol=1e-11)
    # the transfer is a projection: it must lose kinetic energy, never gain it
    assert 0.5 * (m[:, None] * v2 ** 2).sum() < 0.5 * (m[:, None] * v ** 2).sum()


@pytest.mark.parametrize("impl", ["generic", "specialised"])
def test_p2g_is_deterministic_for_a_fixed_chunk_count(impl):
    """Same chunk count -> bit-identical grid, whatever the thread schedule."""
    p2g = _kernels(impl, 3)[0]
    rng = np.random.default_rng(3)
    n, dim = 2000, 3
    x = rng.uniform(0.3, 1.0, size=(n, dim))
    args = (x, rng.normal(size=(n, dim)), rng.normal(size=(n, dim, dim)), np.ones(n), np.ones(n),
            rng.normal(size=(n, 6)), np.zeros(dim), H, 1, np.zeros(dim, np.int64), np.full(dim, 16, np.int64))
    nn = 16 ** 3
    outs = []
    for _ in range(3):
        g = (np.zeros(nn), np.zeros((nn, dim)), np.zeros((nn, dim)))
        p2g(*args, np.zeros((4, nn)), np.zeros((4, nn, dim)), np.zeros((4, nn, dim)), True, *g)
        outs.append(g)
    for g in outs[1:]:
        for a, b in zip(g, outs[0]):
            assert np.array_equal(a, b)
