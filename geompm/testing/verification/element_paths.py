"""Single-element stress paths of a law: triaxial (drained at constant cell pressure, undrained at constant volume)
and simple shear (drained at constant normal stress, or undrained through the two-phase step's own per-particle
water passes), each driven by the law's ``particle_stress`` as the engine calls it.

A mixed path (a stress component held) takes the free strain rate each step by Newton's method on the law itself
(a finite-difference derivative of the held stress), to 1e-10 of the held stress.  Compression is negative in the
stresses the laws see (tension positive); the results are reported with p and q compression positive.
"""

from __future__ import annotations

import numpy as np

from geompm.schemes.saturated.kernels import WATER, add_increment_one, porosity_one, pressure_increment_one


def _solve_free(step, target, guess=0.0, scale=1.0):
    """The free rate r with step(r)[held] = target: Newton with a finite-difference slope."""
    r = guess
    for _ in range(40):
        res = step(r) - target
        if abs(res) <= 1e-10 * scale:
            break
        h = 1e-7 * max(abs(r), 1e-3)
        slope = (step(r + h) - target - res) / h
        r -= res / slope
    return r


def pq(s) -> tuple[float, float]:
    """(p, q) [Pa], compression positive, of a Voigt stress (tension positive)."""
    p = -(s[0] + s[1] + s[2]) / 3.0
    d = np.array(s[:3]) + p
    q = np.sqrt(1.5 * ((d ** 2).sum() + 2.0 * (np.asarray(s[3:]) ** 2).sum()))
    return p, q


def triaxial(law, prm, p0: float, rho: float, strain: float, steps: int, drained: bool, state=None):
    """Axial compression to ``strain`` in ``steps`` from the isotropic p0: drained at constant cell pressure
    (sigma_r = -p0), undrained at constant volume.  Rows (axial strain, volumetric strain (compression
    positive), p, q, state...)."""
    s = np.array([-p0, -p0, -p0, 0.0, 0.0, 0.0])
    st = np.zeros(len(state) if state is not None else 3) if state is None else np.array(state, float)
    de = strain / steps
    rows, ev, er = [], 0.0, 0.0

    def run(rate, commit=False):
        s2, st2 = s.copy(), st.copy()
        law(prm, 1.0, np.diag([-de, rate, rate]), rho, s2, st2)
        if commit:
            s[:], st[:] = s2, st2
        return s2[1]

    for k in range(steps):
        er = _solve_free(run, -p0, er, p0) if drained else 0.5 * de
        run(er, commit=True)
        ev += de - 2.0 * er
        rows.append((de * (k + 1), ev, *pq(s), *st))
    return np.array(rows)


def simple_shear(law, prm, rho0: float, sigma_n: float, gamma: float, steps: int, k0: float = 0.5, state=None,
                 water=None, porosity: float = 0.0):
    """Simple shear (v_x = gamma_dot y) to ``gamma`` in ``steps`` from sigma_yy = -sigma_n, sigma_xx = sigma_zz =
    -k0 sigma_n.  The normal strain rate D_yy keeps the total normal stress at -sigma_n: drained (``water``
    None) on the skeleton, the density following the volume; undrained with ``water`` a pore-water table row
    (schemes/saturated/kernels.WATER) and the initial ``porosity``: each step the two-phase step's own passes
    (pressure_increment_one with the water moving with the skeleton, add_increment_one, porosity_one) update
    the pore pressure p_w and the law sees the skeleton's rate, sigma'_yy - p_w = -sigma_n.  Rows (gamma, eps_v
    (compression positive), sigma'_n, tau, p_w, rho, state...)."""
    s = np.array([-k0 * sigma_n, -sigma_n, -k0 * sigma_n, 0.0, 0.0, 0.0])
    st = np.array(state, float)
    dg = gamma / steps
    rho = rho0
    table = None if water is None else np.asarray(water, float)[None, :]
    one = np.zeros(1)
    pw = {"carried": np.zeros(1), "pore": np.zeros(1), "n": np.array([porosity]), "vol": np.ones(1),
          "vol0": np.ones(1)}
    mat = np.zeros(1, dtype=np.int32)
    rows, ev, dy = [], 0.0, 0.0

    def run(rate, commit=False):
        L = np.zeros((3, 3))
        L[0, 1] = dg
        L[1, 1] = rate
        r2 = rho / (1.0 + rate)
        s2, st2 = s.copy(), st.copy()
        law(prm, 1.0, L, r2, s2, st2)
        dp = np.zeros(1)
        if table is not None:
            div = np.array([rate])
            pressure_increment_one(0, dp, div, div, pw["n"], mat, table, 1.0)
        if commit:
            s[:], st[:] = s2, st2
            if table is not None:
                add_increment_one(0, pw["carried"], pw["pore"], dp, one * 0.0, mat, table)
                pw["vol"][0] *= 1.0 + rate
                porosity_one(0, pw["n"], pw["vol"], pw["vol0"], mat, table)
        return s2[1] - (pw["pore"][0] + dp[0])

    for k in range(steps):
        dy = _solve_free(run, -sigma_n, dy, sigma_n)
        run(dy, commit=True)
        rho = rho / (1.0 + dy)
        ev -= dy
        rows.append((dg * (k + 1), ev, -s[1], s[3], pw["pore"][0], rho, *st))
    return np.array(rows)


def water_row(k_w: float, porosity: float, rho_w: float = 1000.0) -> np.ndarray:
    """A pore-water table row (WATER) of water of bulk modulus ``k_w`` [Pa] in a sealed element."""
    row = np.zeros(len(WATER))
    row[WATER.rho_w], row[WATER.k_w], row[WATER.mu_w] = rho_w, k_w, 1e-3
    row[WATER.n0], row[WATER.kappa0], row[WATER.n_max], row[WATER.p_cav] = porosity, 1e-12, 0.99, -1e12
    return row
