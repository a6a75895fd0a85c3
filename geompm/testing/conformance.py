"""Conformance checks that every material plugin must pass.

Use from a plugin package's tests:

    from geompm.testing import check_material
    def test_conformance():
        check_material(MyLaw)          # raises AssertionError with the failing check

Each check drives the law's own ``stress_kernel`` on a block of particles with
``MyLaw.example_params()``:

- ``zero_rate``: rate-independent laws (``rate_dependent = False``) leave the
  stress and state unchanged when the velocity gradient is zero;
- ``objectivity``: a rigid rotation (L = W, skew) leaves the stress invariants
  I1, J2 and J3 unchanged (relative 1e-6 over 0.01 rad in 100 steps; the
  Jaumann update is first order in the rotation per step);
- ``state_shape``: state arrays keep their shape (n, len(state_vars)) and
  the stress its shape (n, 6);
- ``finite``: no NaN or Inf for strain increments |L dt| from 1e-12 to 1e-1.
"""

from __future__ import annotations

import numpy as np

N = 64


def _start(law):
    """A compressive, slightly deviatoric stress state; density 0.1% above the reference
    so that EOS-based laws carry a pressure too."""
    rng = np.random.default_rng(0)
    mat = law(law.example_params())
    stress = np.zeros((N, 6))
    stress[:, :3] = -2.0e4 + rng.uniform(-1e3, 1e3, size=(N, 3))
    stress[:, 3:] = rng.uniform(-5e2, 5e2, size=(N, 3))
    rho = np.full(N, mat.density * 1.001)
    return mat, stress, rho, mat.initial_state(N)


def _invariants(s):
    m = s[:, :3].sum(axis=1) / 3
    M = np.zeros((len(s), 3, 3))
    for k, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        M[:, a, b] = M[:, b, a] = s[:, k]
    dev = M - m[:, None, None] * np.eye(3)
    return 3 * m, 0.5 * np.einsum("nij,nij->n", dev, dev), np.linalg.det(dev)


def check_zero_rate(law):
    if law.rate_dependent:
        return
    mat, stress, rho, state = _start(law)
    # bring the stress onto the law's admissible set first, then a zero-rate step must change nothing
    mat.update_stress(1e-3, np.zeros((N, 3, 3)), rho, stress, state)
    s0, q0 = stress.copy(), state.copy()
    mat.update_stress(1e-3, np.zeros((N, 3, 3)), rho, stress, state)
    np.testing.assert_array_equal(stress, s0, err_msg=f"{law.name}: stress changed at zero strain rate")
    np.testing.assert_array_equal(state, q0, err_msg=f"{law.name}: state changed at zero strain rate")


def check_objectivity(law):
    mat, stress, rho, state = _start(law)
    mat.update_stress(1e-3, np.zeros((N, 3, 3)), rho, stress, state)
    before = _invariants(stress)
    omega, dt = 1.0, 1e-4
    L = np.zeros((N, 3, 3))
    L[:, 0, 1], L[:, 1, 0] = -omega, omega  # rigid rotation about z
    L[: N // 2, 0, 1], L[: N // 2, 1, 0], L[: N // 2, 1, 2], L[: N // 2, 2, 1] = 0.0, 0.0, -omega, omega
    for _ in range(100):
        mat.update_stress(dt, L, rho, stress, state)
    after = _invariants(stress)
    scale = np.abs(stress).max()
    for name, b, a, power in zip(("I1", "J2", "J3"), before, after, (1, 2, 3)):
        err = np.abs(a - b).max() / scale ** power
        assert err < 1e-6, f"{law.name}: invariant {name} changed by {err:.2e} (relative) under rigid rotation"


def check_state_shape(law):
    mat, stress, rho, state = _start(law)
    L = np.random.default_rng(1).normal(scale=0.1, size=(N, 3, 3))
    mat.update_stress(1e-3, L, rho, stress, state)
    assert stress.shape == (N, 6), f"{law.name}: stress shape {stress.shape}"
    assert state.shape == (N, len(law.state_vars)), f"{law.name}: state shape {state.shape}"


def check_finite(law):
    rng = np.random.default_rng(2)
    for magnitude in 10.0 ** np.arange(-12, 0):
        mat, stress, rho, state = _start(law)
        L = rng.normal(size=(N, 3, 3))
        L *= magnitude / np.abs(L).max(axis=(1, 2))[:, None, None]
        dt = 1.0
        for _ in range(3):
            mat.update_stress(dt, L / dt, rho, stress, state)
        assert np.isfinite(stress).all() and np.isfinite(state).all(), \
            f"{law.name}: NaN/Inf for strain increments of {magnitude:.0e}"


MATERIAL_CHECKS = {
    "zero_rate": check_zero_rate,
    "objectivity": check_objectivity,
    "state_shape": check_state_shape,
    "finite": check_finite,
}


def check_material(law) -> None:
    """Run every conformance check on a material plugin class."""
    for check in MATERIAL_CHECKS.values():
        check(law)
