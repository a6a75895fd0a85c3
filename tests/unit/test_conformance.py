"""The conformance suite of geompm.testing over every registered material, third-party included."""

import numpy as np
import pytest
from numba import njit

from geompm.contract import registry
from geompm.materials.drucker_prager import dp_stress
from geompm.testing import MATERIAL_CHECKS

LAWS = sorted(registry.available("materials").items())


def test_the_seed_laws_are_registered():
    names = {name for name, _ in LAWS}
    assert {"linear_elastic", "newtonian", "drucker_prager", "mohr_coulomb", "bingham", "cross"} <= names


@pytest.mark.parametrize("check", sorted(MATERIAL_CHECKS))
@pytest.mark.parametrize("name,info", LAWS, ids=[n for n, _ in LAWS])
def test_material_conformance(name, info, check):
    MATERIAL_CHECKS[check](info.plugin)


def test_plastic_dissipation_check_catches_a_law_that_returns_energy():
    """The plastic-dissipation check (geompm.testing) must fail a law whose return adds energy.

    The mutant is Drucker-Prager whose stress change is 1.5 times what its declared E and nu give:
    C^-1 (sigma_n+1 - sigma_n) then exceeds the strain increment, the implied plastic strain runs
    against the stress, and sigma : de_p < 0 on every loading step. The real law passes the same
    paths with its smallest plastic work at round-off (measured -1.3e-10 J/m3 against a largest
    4.4e3 J/m3), its stretched quarter of the particles ending on the apex."""
    from geompm.materials.drucker_prager import DruckerPrager
    from geompm.testing.conformance import check_plastic_dissipation, plastic_work_per_step

    class Overshoot(DruckerPrager):
        name = "dp_overshoot"
        particle_stress = overshooting_dp_stress

    with pytest.raises(AssertionError, match="negative plastic dissipation"):
        check_plastic_dissipation(Overshoot)
    work = plastic_work_per_step(DruckerPrager)
    assert work.min() > -1e-6 and work.max() > 1e3


@njit(cache=True)
def overshooting_dp_stress(prm, dt, L, rho, s, state):
    """Drucker-Prager with its stress change scaled by 1.5 (the mutant above)."""
    s0, s1, s2, s3, s4, s5 = s[0], s[1], s[2], s[3], s[4], s[5]
    dp_stress(prm, dt, L, rho, s, state)
    s[0] = s0 + 1.5 * (s[0] - s0)
    s[1] = s1 + 1.5 * (s[1] - s1)
    s[2] = s2 + 1.5 * (s[2] - s2)
    s[3] = s3 + 1.5 * (s[3] - s3)
    s[4] = s4 + 1.5 * (s[4] - s4)
    s[5] = s5 + 1.5 * (s[5] - s5)


def test_no_allocation_check_catches_a_law_that_allocates():
    """A Drucker-Prager that copies its stress into a fresh array per particle (np.empty) must fail the
    no_allocation check; the real law passes it (above)."""
    from geompm.materials.drucker_prager import DruckerPrager
    from geompm.testing.conformance import check_no_allocation

    class Allocating(DruckerPrager):
        name = "dp_allocating"
        particle_stress = allocating_dp_stress

    with pytest.raises(AssertionError, match="must not allocate"):
        check_no_allocation(Allocating)


@njit(cache=True)
def allocating_dp_stress(prm, dt, L, rho, s, state):
    """Drucker-Prager through a per-particle temporary array (the mutant above)."""
    tmp = np.empty(6)
    for k in range(6):
        tmp[k] = s[k]
    dp_stress(prm, dt, L, rho, tmp, state)
    for k in range(6):
        s[k] = tmp[k]
