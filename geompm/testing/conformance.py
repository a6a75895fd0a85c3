"""Conformance checks that every material plugin must pass.

Use from a plugin package's tests:

    from geompm.testing import check_material
    def test_conformance():
        check_material(MyLaw)          # raises AssertionError with the failing check

Each check drives the law through the loop the engine runs (``update_stress``, backend/cpu_loops.py,
backend/cpu_loops.py) on a block of particles with
``MyLaw.example_params()``:

- ``zero_rate``: rate-independent laws (``rate_dependent = False``) leave the
  stress and state unchanged when the velocity gradient is zero;
- ``objectivity``: a rigid rotation (L = W, skew) leaves the stress invariants
  I1, J2 and J3 unchanged (relative 1e-6 over 0.01 rad in 100 steps; the
  Jaumann update is first order in the rotation per step);
- ``state_shape``: state arrays keep their shape (n, len(state_vars)) and
  the stress its shape (n, 6);
- ``finite``: no NaN or Inf for strain increments |L dt| from 1e-12 to 1e-1;
- ``wave_speed_monotone``: ``particle_wave_speed`` is positive, finite and monotone
  in the density from rho0/100 to 10 rho0 (the backend evaluates it at a block's
  lowest and highest density only);
- ``no_allocation``: the stress loop over 4 N particles makes as many numba
  allocations as over N (the law allocates nothing per particle);
- ``plastic_dissipation``: laws with an isotropic elastic part (``youngs_modulus``
  and ``poisson_ratio`` among their parameters) never return energy from plastic
  flow.  Over random strain paths, a quarter of them stretched through the apex
  of the yield surface, the plastic work of every step,
      d = sigma_{n+1} : (de - C^-1 : (sigma_{n+1} - sigma_n)),
  the backward-Euler dissipation of the return (Simo & Hughes 1998,
  Computational Inelasticity, sec. 3.3), is >= 0 to round-off.  An apex or
  tension branch that puts the stress where it does work against its own plastic
  strain fails here.
"""

from __future__ import annotations

import numpy as np

from geompm.backend.cpu_loops import update_law_block as update_stress

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
    update_stress(mat, 1e-3, np.zeros((N, 3, 3)), rho, stress, state)
    s0, q0 = stress.copy(), state.copy()
    update_stress(mat, 1e-3, np.zeros((N, 3, 3)), rho, stress, state)
    np.testing.assert_array_equal(stress, s0, err_msg=f"{law.name}: stress changed at zero strain rate")
    np.testing.assert_array_equal(state, q0, err_msg=f"{law.name}: state changed at zero strain rate")


def check_objectivity(law):
    mat, stress, rho, state = _start(law)
    update_stress(mat, 1e-3, np.zeros((N, 3, 3)), rho, stress, state)
    before = _invariants(stress)
    omega, dt = 1.0, 1e-4
    L = np.zeros((N, 3, 3))
    L[:, 0, 1], L[:, 1, 0] = -omega, omega  # rigid rotation about z
    L[: N // 2, 0, 1], L[: N // 2, 1, 0], L[: N // 2, 1, 2], L[: N // 2, 2, 1] = 0.0, 0.0, -omega, omega
    for _ in range(100):
        update_stress(mat, dt, L, rho, stress, state)
    after = _invariants(stress)
    scale = np.abs(stress).max()
    for name, b, a, power in zip(("I1", "J2", "J3"), before, after, (1, 2, 3)):
        err = np.abs(a - b).max() / scale ** power
        assert err < 1e-6, f"{law.name}: invariant {name} changed by {err:.2e} (relative) under rigid rotation"


def check_state_shape(law):
    mat, stress, rho, state = _start(law)
    L = np.random.default_rng(1).normal(scale=0.1, size=(N, 3, 3))
    update_stress(mat, 1e-3, L, rho, stress, state)
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
            update_stress(mat, dt, L / dt, rho, stress, state)
        assert np.isfinite(stress).all() and np.isfinite(state).all(), \
            f"{law.name}: NaN/Inf for strain increments of {magnitude:.0e}"


def _voigt_sym(L):
    """Symmetric part of (n, 3, 3) as Voigt tensor components (xx, yy, zz, xy, yz, xz)."""
    D = 0.5 * (L + np.transpose(L, (0, 2, 1)))
    return np.stack([D[:, 0, 0], D[:, 1, 1], D[:, 2, 2], D[:, 0, 1], D[:, 1, 2], D[:, 0, 2]], axis=1)


def _double_dot(a, b):
    """a : b of Voigt tensors (shear components counted twice)."""
    return (a[:, :3] * b[:, :3]).sum(axis=1) + 2.0 * (a[:, 3:] * b[:, 3:]).sum(axis=1)


def plastic_work_per_step(law, steps: int = 80, seed: int = 3) -> np.ndarray:
    """(steps, N) plastic work per unit volume [J/m3] of each step along random strain paths.

    Paths are symmetric (no spin, so the Jaumann term is zero); each particle changes direction every 10
    steps.  Particles 0 .. N/4 get a volumetric stretch on top that carries them through the apex,
    N/4 .. N/2 a compression.  The density follows the path, rho <- rho / (1 + tr(D) dt) (the engine's
    det(I + dt L) to first order, and the volume ratio of plasticity.kirchhoff_trial), and the work is that of the Kirchhoff stress tau = (rho0 / rho) sigma per unit reference volume
    (geompm's elastoplastic laws integrate tau with constant moduli, materials/plasticity.current_moduli):
    C^-1 (tau_{n+1} - tau_n) is then the elastic strain increment exactly.  A law that keeps constant
    moduli in sigma instead shows a negative work of order sigma tr(D) dt here."""
    p = law.example_params()
    E, nu = float(p.youngs_modulus), float(p.poisson_ratio)
    G, lam = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
    mat, stress, rho, state = _start(law)
    rng = np.random.default_rng(seed)
    dt, de = 1e-3, 40.0 * abs(stress).max() / E / steps  # the strain of one step: a path of 40 yield strains
    out = np.empty((steps, N))
    for k in range(steps):
        if k % 10 == 0:
            L = rng.normal(size=(N, 3, 3))
            L = 0.5 * (L + np.transpose(L, (0, 2, 1)))
            L[: N // 4] += 1.5 * np.eye(3)
            L[N // 4: N // 2] -= 0.5 * np.eye(3)
            L *= de / dt / np.abs(L).max(axis=(1, 2))[:, None, None]
        tau_old = stress * (mat.density / rho)[:, None]
        rho = rho / (1.0 + dt * np.trace(L, axis1=1, axis2=2))
        update_stress(mat, dt, L, rho, stress, state)
        tau = stress * (mat.density / rho)[:, None]
        ds = tau - tau_old
        tr = ds[:, :3].sum(axis=1)
        de_el = ds / (2 * G)
        de_el[:, :3] -= (lam / (2 * G * (3 * lam + 2 * G)) * tr)[:, None]
        out[k] = _double_dot(tau, _voigt_sym(L) * dt - de_el)
    return out


def check_plastic_dissipation(law):
    names = law.Params.model_fields
    if "youngs_modulus" not in names or "poisson_ratio" not in names:
        return
    work = plastic_work_per_step(law)
    sigma = np.abs(_start(law)[1]).max()
    scale = 1e-9 * sigma * 40.0 * sigma / law.example_params().youngs_modulus  # round-off of sigma : (40 sigma / E)
    k, p = np.unravel_index(np.argmin(work), work.shape)
    assert work[k, p] >= -scale, (
        f"{law.name}: negative plastic dissipation {work[k, p]:.3e} J/m3 at step {k} of particle {p} "
        f"(sigma_n+1 : de_p must be >= 0)")


def check_wave_speed_monotone(law):
    """The wave speed is monotone in the density from rho0 / 100 to 10 rho0 (the backend evaluates it at
    a block's lowest and highest density only), positive and finite."""
    from geompm.backend.cpu_loops import block_loops

    mat = law(law.example_params())
    wave = block_loops(law)[1]
    rho = mat.density * np.geomspace(1e-2, 10.0, 200)
    c = np.array([wave(mat.prm, np.array([r])) for r in rho])
    assert np.isfinite(c).all() and (c > 0).all(), f"{law.name}: wave speed not positive and finite: {c.min()}"
    step = np.diff(c)
    tol = 1e-12 * c.max()
    assert (step >= -tol).all() or (step <= tol).all(), (
        f"{law.name}: particle_wave_speed is not monotone in the density (it rises and falls between "
        f"{rho[0]:.3g} and {rho[-1]:.3g} kg/m3); the backend evaluates it at a block's extreme densities only")
    both = wave(mat.prm, np.array([rho[0], rho[-1]]))
    assert both == max(c[0], c[-1]), f"{law.name}: the block's speed {both} is not the larger of its extremes"


def check_no_allocation(law):
    """One pass of the engine's stress loop over N and over 4 N particles: the same number of numba
    allocations (numba's runtime counters), so the law allocates nothing per particle."""
    from numba.core.runtime import _nrt_python, rtsys

    from geompm.backend.cpu_loops import block_loops

    stress_block = block_loops(law)[0]
    counts = []
    enabled = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    try:
        for reps in (1, 4, 1, 4):
            mat, stress, rho, state = _start(law)
            stress, rho, state = np.tile(stress, (reps, 1)), np.tile(rho, reps), np.tile(state, (reps, 1))
            L = np.zeros((len(rho), 3, 3))
            L[:, 0, 1] = 1.0
            before = rtsys.get_allocation_stats().alloc
            stress_block(mat.prm, 1e-4, L, rho, stress, state)
            counts.append(rtsys.get_allocation_stats().alloc - before)
    finally:
        if not enabled:
            _nrt_python.memsys_disable_stats()
    assert counts[2] == counts[3], (
        f"{law.name}: the stress loop allocated {counts[3] - counts[2]} more arrays over {4 * N} particles "
        f"than over {N}: particle_stress must not allocate (no np.empty, no slicing copies)")


MATERIAL_CHECKS = {
    "no_allocation": check_no_allocation,
    "wave_speed_monotone": check_wave_speed_monotone,
    "plastic_dissipation": check_plastic_dissipation,
    "zero_rate": check_zero_rate,
    "objectivity": check_objectivity,
    "state_shape": check_state_shape,
    "finite": check_finite,
}


def check_material(law) -> None:
    """Run every conformance check on a material plugin class."""
    for check in MATERIAL_CHECKS.values():
        check(law)
