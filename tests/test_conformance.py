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
