"""A material point under the kinematics of an infinite slope reaches Davis's strength.

In an infinite slope the strain rate has no component along the slope (D_xx = 0) nor out of plane (D_zz = 0)
and the slope-normal stress is held by the weight above.  Steady plastic flow then carries on the slope-parallel
plane tau / sigma_n = tan(phi*) = sin(phi) cos(psi) / (1 - sin(phi) sin(psi)) (Davis 1968, in Lee (ed.), Soil
Mechanics: Selected Topics, 341-380): sin(phi) for psi = 0, tan(phi) for psi = phi.  Both Mohr-Coulomb and the
plane-strain Drucker-Prager cone must reach it from an elastic K0 state (docs/slope-stability.md: the MPM
slope with psi = 0 falls below it, so the law alone is not the cause)."""

import math

import numpy as np
import pytest

from geompm.contract.registry import get

E, NU = 2.0e6, 0.3
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))


def _sheared(name, phi, psi, steps=6000):
    law = get("materials", name)
    mat = law(law.Params(density=2000.0, youngs_modulus=E, poisson_ratio=NU, friction_angle=phi, cohesion=0.0,
                         dilation_angle=psi))
    target = -18320.0
    s = np.array([NU / (1 - NU) * target, target, NU / (1 - NU) * target, 0.0, 0.0, 0.0])
    state, dt = np.zeros(2), 1e-4
    for _ in range(steps):
        L = np.zeros((3, 3))
        L[0, 1] = 0.5
        e = 0.0
        for _ in range(3):  # the slope-normal strain rate that holds sigma_yy at the weight (a Newton step on M)
            trial, st = s.copy(), state.copy()
            L[1, 1] = e
            law.particle_stress(mat.prm, dt, L, 2000.0, trial, st)
            e -= (trial[1] - target) / (M * dt)
        s, state = trial, st
    return s[3] / -s[1]


@pytest.mark.parametrize("name", ["mohr_coulomb", "drucker_prager"])
@pytest.mark.parametrize("phi, psi", [(25.0, 0.0), (30.0, 0.0), (30.0, 30.0)])
def test_point_reaches_davis_strength(name, phi, psi):
    sp, spsi = math.sin(math.radians(phi)), math.sin(math.radians(psi))
    davis = sp * math.cos(math.radians(psi)) / (1 - sp * spsi)
    assert _sheared(name, phi, psi) == pytest.approx(davis, rel=0.01)
