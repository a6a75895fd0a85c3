"""The 2D and 3D transfer kernels the scheduler runs (kernels/transfer2d.py,
transfer3d.py) equal the dimension-generic reference (tests/support/reference_transfer.py).

The specialised kernels reorder the same sums (weights and APIC terms built
axis by axis, docs/performance.md), so every output must agree to rounding:
grid mass, momentum and force after P2G; position, velocity, C, L,
volume and density after G2P; for every shape function, PIC/APIC/FLIP, and a window that
does not start at node 0.  A wrong stride, offset or gradient factor would
show as an O(1) difference.
"""

import numpy as np
import pytest

from geompm.kernels.shape import APIC_D_FACTOR
from tests.support.reference_transfer import g2p, p2g

from tests.support.transfer_kernels import kernels

H = 0.1


def _scene(dim, rng, n=600):
    origin = np.array([0.05, -0.2, 0.1])[:dim]
    x = origin + 0.35 + rng.random((n, dim)) * 0.6
    lo = np.floor((x.min(0) - origin) / H).astype(np.int64) - 2
    nloc = np.ceil((x.max(0) - origin) / H).astype(np.int64) + 3 - lo
    return origin, x, lo, nloc


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kind", [0, 1, 2])
@pytest.mark.parametrize("mode", [0, 1, 2])
def test_specialised_transfers_equal_the_reference(dim, kind, mode):
    rng = np.random.default_rng(10 * dim + kind)
    origin, x, lo, nloc = _scene(dim, rng)
    n, nn = len(x), int(np.prod(nloc))
    v, C = rng.normal(size=(n, dim)), rng.normal(size=(n, dim, dim))
    m, vol, sig = rng.random(n) + 0.5, rng.random(n) * 1e-3, rng.normal(size=(n, 6))
    fast_p2g, fast_g2p = kernels("specialised", dim)
    grids = []
    for kernel in (p2g, fast_p2g):
        g = (np.zeros(nn), np.zeros((nn, dim)), np.zeros((nn, dim)))
        bufs = (np.zeros((2, nn)), np.zeros((2, nn, dim)), np.zeros((2, nn, dim)))
        kernel(x, v, C, m, vol, sig, origin, H, kind, lo, nloc, *bufs, True, *g)
        grids.append(g)
    for ref, got in zip(*grids):
        assert np.abs(ref).max() > 0
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.abs(ref).max())

    g_vel, g_vel_old = rng.normal(size=(nn, dim)), rng.normal(size=(nn, dim))
    dinv = 1.0 / (APIC_D_FACTOR[kind] * H * H) if kind else 0.0
    particles = []
    for kernel in (g2p, fast_g2p):
        out = (x.copy(), v.copy(), C.copy(), np.zeros((n, 3, 3)), vol.copy(), np.zeros(n))
        kernel(*out, m, g_vel, g_vel_old,
               origin, H, kind, lo, nloc, 1e-3, mode, 0.95, dinv, True, True, True)
        particles.append(out)
    for ref, got in zip(*particles):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * max(np.abs(ref).max(), 1.0))


def test_volume_follows_det_F_without_storing_F():
    """V_n = V0 det F_n with F_n = prod (I + dt L_k): kernels/volume.py advances V by det(I + dt L)
    each step instead of storing F (continuum kinematics, e.g. Belytschko et al. 2000, sec. 3.2)."""
    from geompm.kernels.volume import update_volume

    rng = np.random.default_rng(5)
    p_L, p_vol, p_rho, p_mass = np.zeros((1, 3, 3)), np.array([2.0e-3]), np.zeros(1), np.array([3.0])
    F, dt = np.eye(3), 1e-2
    for _ in range(50):
        L = rng.normal(scale=2.0, size=(3, 3)) + 0.5 * np.eye(3)
        update_volume(0, p_L, p_vol, p_rho, p_mass, L, dt)
        F = (np.eye(3) + dt * L) @ F
        np.testing.assert_array_equal(p_L[0], L)
    assert abs(np.linalg.det(F) - 1.0) > 0.05  # the test deforms the volume noticeably
    assert p_vol[0] == pytest.approx(2.0e-3 * np.linalg.det(F), rel=1e-12)
    assert p_rho[0] == pytest.approx(3.0 / p_vol[0], rel=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kind,mls", [(0, False), (1, False), (2, False), (1, True), (2, True)])
def test_folded_p2g_equals_momentum_plus_dt_force(dim, kind, mls):
    """Folded P2G (mpm/grid.py: no stage reads f_i) must give (mv)_i + dt f_i of the split
    P2G, node by node, and leave the force array alone: the explicit update
    v_i = ((mv)_i + dt f_i)/m_i + dt g is then the same as v_i = v_old + dt (f_i/m_i + g).
    For MLS the folded force is an affine term and the split one goes through
    pseudo-derivatives: two different code paths that must agree."""
    from geompm.backend.cpu import TRANSFERS
    from geompm.kernels.stencil import scheme_tag, stencil_tag

    rng = np.random.default_rng(40 + 10 * dim + kind)
    origin, x, lo, nloc = _scene(dim, rng)
    n, nn = len(x), int(np.prod(nloc))
    v, C = rng.normal(size=(n, dim)), rng.normal(size=(n, dim, dim))
    m, vol, sig = rng.random(n) + 0.5, rng.random(n) * 1e-3, rng.normal(size=(n, 6)) * 1e5
    p2g_fast, dt = TRANSFERS[dim][0], 3e-3
    mls_dinv = 1.0 / (APIC_D_FACTOR[kind] * H * H) if mls else 0.0
    args = (stencil_tag(kind), scheme_tag("mls" if mls else "apic"), x, v, C, m, vol, sig, origin, H, kind, lo, nloc)
    split = (np.zeros(nn), np.zeros((nn, dim)), np.zeros((nn, dim)))
    p2g_fast(*args, np.zeros((2, nn, 1 + 2 * dim)), True, 1.0, mls_dinv, *split)
    folded = (np.zeros(nn), np.zeros((nn, dim)), np.full((nn, dim), 7.0))
    p2g_fast(*args, np.zeros((2, nn, 1 + dim)), False, dt, mls_dinv, *folded)
    assert np.abs(dt * split[2]).max() > 0.1 * np.abs(split[1]).max()  # the force term matters
    np.testing.assert_allclose(folded[0], split[0], rtol=0, atol=1e-13 * split[0].max())
    expect = split[1] + dt * split[2]
    np.testing.assert_allclose(folded[1], expect, rtol=0, atol=1e-12 * np.abs(expect).max())
    assert (folded[2] == 7.0).all()


@pytest.mark.parametrize("kind", [0, 1, 2])
def test_register_stencil_satisfies_the_b_spline_identities(kind):
    """kernels/shape.axis_stencil, the register form every 2D/3D kernel uses, at 2000 points:
    sum w = 1, sum dw = 0, sum w_k (x_k - x) = 0 and sum dw_k x_k = 1 (Steffen, Kirby &
    Berzins 2008), w >= 0, the particle inside the support, zeros in the padding, and a
    support equal to len(stencil_tag(kind)), the kernels' compile-time loop length."""
    from geompm.kernels.shape import axis_stencil, support
    from geompm.kernels.stencil import stencil_tag

    S, h = support(kind), 0.25
    assert len(stencil_tag(kind)) == S == kind + 2
    for xi in np.random.default_rng(kind).uniform(-3.0, 30.0, 2000):
        base, w, dw = axis_stencil(xi, kind, 1.0 / h)
        xk = (base + np.arange(4)) * h  # node positions [m], particle at xi h
        w, dw = np.array(w), np.array(dw)
        assert base <= xi <= base + S - 1
        assert (w[S:] == 0.0).all() and (dw[S:] == 0.0).all() and (w >= 0.0).all()
        assert w.sum() == pytest.approx(1.0, abs=1e-14)
        assert dw.sum() == pytest.approx(0.0, abs=1e-12)
        assert (w * (xk - xi * h)).sum() == pytest.approx(0.0, abs=1e-14)
        assert (dw * xk).sum() == pytest.approx(1.0, abs=1e-12)
