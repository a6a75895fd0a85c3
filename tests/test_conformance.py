"""The conformance suite of geompm.testing over every registered material, third-party included."""

import pytest

from geompm import registry
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

    def overshooting(prm, dt, p_L, p_rho, p_stress, p_state):
        old = p_stress.copy()
        DruckerPrager.stress_kernel(prm, dt, p_L, p_rho, p_stress, p_state)
        p_stress[:] = old + 1.5 * (p_stress - old)

    class Overshoot(DruckerPrager):
        name = "dp_overshoot"
        stress_kernel = staticmethod(overshooting)

    with pytest.raises(AssertionError, match="negative plastic dissipation"):
        check_plastic_dissipation(Overshoot)
    work = plastic_work_per_step(DruckerPrager)
    assert work.min() > -1e-6 and work.max() > 1e3
