"""The MLS-MPM transfer (``solver.transfer: "mls"``): Hu, Fang, Ge, Qu, Zhu, Pradhana & Jiang
(2018) "A moving least squares material point method with displacement discontinuity and
two-way rigid body coupling", ACM Trans. Graph. 37(4):150.

MLS keeps the APIC transfer (Jiang et al. 2015) and replaces the shape-function gradient by
its moving-least-squares estimate grad w_ip ~ D^-1 w_ip (x_i - x_p), D = h^2/4 (quadratic)
or h^2/3 (cubic B-spline); the velocity gradient of the stress update is then the APIC
matrix, L_p = C_p.  Checked here against those definitions evaluated node by node with
numpy, and on the closed-form vibration of an elastic bar.
"""

import itertools

import numpy as np
import pytest

from geompm.api import scene_from_file
from geompm.backend.cpu import TRANSFERS
from geompm.kernels.chunks import G2P_CHUNKS
from geompm.kernels.shape import APIC_D_FACTOR, axis_weights, support
from geompm.kernels.stencil import scheme_tag, stencil_tag

from tests.support.cases import CASES
from tests.support.elastic_bar import run_bar

H = 0.1


def _stencil(xp, kind, origin):
    """Nodes (global index tuples) and weights of one particle, from kernels/shape.py."""
    S = support(kind)
    w, dw = np.zeros((len(xp), 4)), np.zeros((len(xp), 4))
    base = [axis_weights((xp[a] - origin[a]) / H, kind, 1.0 / H, w[a], dw[a]) for a in range(len(xp))]
    for ks in itertools.product(range(S), repeat=len(xp)):
        yield tuple(b + k for b, k in zip(base, ks)), np.prod([w[a, k] for a, k in enumerate(ks)])


def _voigt_to_tensor(s, dim):
    full = np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
    return full[:dim, :dim]


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kind", [1, 2])
def test_mls_force_and_velocity_gradient_follow_the_definitions(dim, kind):
    """P2G: f_i = -sum_p V_p sigma_p D^-1 w_ip (x_i - x_p); G2P: L_p = C_p = D^-1 sum_i w_ip v_i
    (x_i - x_p)^T and v_p = sum_i w_ip v_i, all to 1e-10 of their scale."""
    rng = np.random.default_rng(3 + dim + kind)
    n = 40
    origin = np.zeros(dim)
    x = 0.6 + rng.random((n, dim)) * 0.5
    lo = np.full(dim, 2, np.int64)
    nloc = np.full(dim, 14, np.int64)
    nn = int(np.prod(nloc))
    v, C = rng.normal(size=(n, dim)), rng.normal(size=(n, dim, dim))
    m, vol, sig = rng.random(n) + 0.5, rng.random(n) * 1e-3, rng.normal(size=(n, 6)) * 1e3
    dinv = 1.0 / (APIC_D_FACTOR[kind] * H * H)
    p2g, g2p = TRANSFERS[dim]
    g = (np.zeros(nn), np.zeros((nn, dim)), np.zeros((nn, dim)))
    p2g(stencil_tag(kind), scheme_tag("mls"), x, v, C, m, vol, sig, origin, H, kind, lo, nloc,
        np.zeros((2, nn, 1 + 2 * dim)), True, 1.0, dinv, *g)

    def flat(node):
        return int(np.ravel_multi_index(tuple(np.array(node) - lo), tuple(nloc)))

    force = np.zeros((nn, dim))
    for p in range(n):
        s = _voigt_to_tensor(sig[p], dim)
        for node, w in _stencil(x[p], kind, origin):
            force[flat(node)] -= vol[p] * s @ (dinv * w * (np.array(node) * H - x[p]))
    np.testing.assert_allclose(g[2], force, rtol=0, atol=1e-10 * np.abs(force).max())

    g_vel = rng.normal(size=(nn, dim))
    out_v, out_C, out_L = v.copy(), C.copy(), np.zeros((n, 3, 3))
    g2p(stencil_tag(kind), scheme_tag("mls"), x.copy(), out_v, out_C, out_L, vol.copy(), np.zeros(n), m, g_vel,
        g_vel, origin, H, kind, lo, nloc, 1e-3, 0.0, dinv, True, True, True, np.zeros((G2P_CHUNKS, 2, 3)))
    for p in range(n):
        vp, B = np.zeros(dim), np.zeros((dim, dim))
        for node, w in _stencil(x[p], kind, origin):
            vi = g_vel[flat(node)]
            vp += w * vi
            B += w * np.outer(vi, np.array(node) * H - x[p])
        np.testing.assert_allclose(out_v[p], vp, rtol=0, atol=1e-12)
        np.testing.assert_allclose(out_C[p], dinv * B, rtol=0, atol=1e-10 * max(1.0, np.abs(dinv * B).max()))
        np.testing.assert_allclose(out_L[p, :dim, :dim], out_C[p], rtol=0, atol=1e-12 * np.abs(out_C[p]).max())


def test_mls_elastic_bar_period_and_energy(refdata):
    """The fixed-free elastic bar (cases/elastic_bar.json, closed form in test_elastic_bar.py:
    T1 = 4 L / sqrt(E / rho) = 10 s) run with MLS: first-mode period within 2 %, energy drift
    below 1 % over 3 periods, as for APIC."""
    period, exact, drift, _, _ = run_bar(("solver.transfer=mls",))
    assert abs(period / exact - 1) < 0.02, f"period {period:.4f} s vs {exact:.4f} s"
    assert drift < 0.01, f"energy drift {drift:.4%} over 3 periods"


def test_mls_with_linear_shape_functions_is_refused():
    """MLS needs the constant inertia D of B-splines: a linear-shape case is refused at
    'solver.transfer' before any work."""
    from geompm.errors import CaseError

    with pytest.raises(CaseError) as exc:
        scene_from_file(CASES / "elastic_bar.json", ["solver.transfer=mls", "grid.shape_function=linear"])
    assert "solver.transfer" in str(exc.value) and "quadratic" in str(exc.value)
