"""The Duvaut-Lions regularisation (kernels/viscoplastic.py) through the engine's own law loops.

Reference: Simo & Hughes (1998), Computational Inelasticity, sec. 2.7.2: for a perfectly plastic element driven
at a constant plastic-flow rate, d sigma/dt = C:D - (sigma - sigma_inf)/tau has the steady overstress
sigma - sigma_inf = tau C:D, and the backward-Euler step keeps it exactly: s = (s_tr + r s_inf)/(1 + r) with
s_tr = s + 2 G D_xy dt gives s - s_inf = 2 G D_xy tau at the fixed point.  An element that stays elastic is
not changed, and the internal variables relax with the same weights.
"""

from __future__ import annotations

import numpy as np
import pytest

from geompm.backend.cpu_loops import update_law_block
from geompm.materials.drucker_prager import DruckerPrager
from geompm.materials.linear_elastic import LinearElastic
from geompm.materials.mohr_coulomb import MohrCoulomb

G_RATE = 0.5  # D_xy [1/s]: pure shear, no spin
E, NU = 2.0e6, 0.3
G = E / (2 * (1 + NU))


def _shear(law, params, steps, dt, tau=None):
    """One particle in pure shear D_xy = G_RATE for ``steps``; returns (stress history xy, state)."""
    mat = law(law.Params(**params))
    L = np.zeros((1, 3, 3))
    L[0, 0, 1] = L[0, 1, 0] = G_RATE
    rho = np.full(1, params["density"])
    s = np.zeros((1, 6))
    sv = np.zeros((1, len(law.state_vars)))
    old = np.zeros((1, 6 + sv.shape[1]))
    out = []
    for _ in range(steps):
        relax = None if tau is None else (old, dt / tau)
        update_law_block(mat, dt, L, rho, s, sv, relax)
        out.append(s[0, 3])
    return np.array(out), sv[0].copy()


@pytest.mark.parametrize("law", [DruckerPrager, MohrCoulomb])
@pytest.mark.parametrize("tau", [0.002, 0.01])
def test_steady_overstress_is_tau_times_the_elastic_rate(law, tau):
    """Past yield at a constant rate the regularised shear stress runs tau * 2 G D_xy above the inviscid one
    (to 1e-9 relative after 40 tau), at two relaxation times and two laws; both reach yield at the same time."""
    params = dict(density=2000.0, youngs_modulus=E, poisson_ratio=NU, friction_angle=0.0, dilation_angle=0.0,
                  cohesion=10.0e3)
    dt = 1e-4
    steps = int(0.05 / dt) + int(40 * tau / dt)
    inviscid, _ = _shear(law, params, steps, dt)
    viscous, _ = _shear(law, params, steps, dt, tau)
    expected = tau * 2.0 * G * G_RATE
    assert expected > 0.01 * inviscid[-1]  # the overstress is measurable against the strength
    assert viscous[-1] - inviscid[-1] == pytest.approx(expected, rel=1e-9)
    elastic = inviscid < 0.999 * inviscid[-1]
    assert elastic.sum() > 10
    np.testing.assert_allclose(viscous[elastic], inviscid[elastic], rtol=1e-12)


def test_plastic_strain_relaxes_with_the_stress():
    """The plastic strain (the state) of the regularised element lags the inviscid one by the overstress over
    G: eps_p,inv - eps_p,visc = (s_visc - s_inv) / G in the equivalent strain sqrt(2/3 e:e) of pure shear,
    where the lag is 2 tau D_xy / sqrt(3): the internal variables follow the same backward-Euler relaxation."""
    params = dict(density=2000.0, youngs_modulus=E, poisson_ratio=NU, friction_angle=0.0, dilation_angle=0.0,
                  cohesion=10.0e3)
    dt, tau = 1e-4, 0.005
    steps = int(0.05 / dt) + int(40 * tau / dt)
    _, q_inv = _shear(DruckerPrager, params, steps, dt)
    _, q_vis = _shear(DruckerPrager, params, steps, dt, tau)
    lag = 2.0 * tau * G_RATE / np.sqrt(3.0)
    assert q_inv[0] - q_vis[0] == pytest.approx(lag, rel=1e-6)


def test_a_law_without_an_elastic_predictor_is_not_regularised():
    """Only laws that declare an elastic predictor are regularised (Material.elastic_predictor): the frictional
    laws do, the linear-elastic one (no return to relax) does not, so the backend runs it inviscid."""
    from geompm.backend.base import relaxed_materials

    scene = type("S", (), {"viscoplastic_time": 0.01,
                           "materials": [MohrCoulomb(MohrCoulomb.example_params()),
                                         LinearElastic(LinearElastic.example_params())]})()
    assert relaxed_materials(scene) == [True, False]
    scene.viscoplastic_time = None
    assert relaxed_materials(scene) == [False, False]
