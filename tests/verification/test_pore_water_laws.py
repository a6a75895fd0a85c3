"""Every registered law that is not a fluid runs saturated, unchanged (geompm/testing/saturated.py): in a
sealed column loaded by q over 2 ms the mixture carries the load (total stress within 2 % of q) and the
water its undrained share, 1 / (1 + n M / K_w) from the law's own constrained modulus (Skempton 1954, in
its oedometric form; docs/pore-water.md). The third-party mu_i plugin of plugins/ is among them."""

import pytest

from geompm.contract import registry
from geompm.testing.saturated import check_saturated, saturated_element

LAWS = sorted(name for name in registry.available("materials")
              if not registry.get("materials", name).fluid)


def test_the_suite_covers_the_soil_laws():
    """The built-in soil laws and the installed plugin are all checked (a registry that hid them would
    make the next test pass vacuously)."""
    assert {"drucker_prager", "mohr_coulomb", "linear_elastic", "mu_i"} <= set(LAWS)


@pytest.mark.parametrize("name", LAWS)
def test_law_runs_saturated_unchanged(name):
    check_saturated(name)


def test_linear_elastic_water_share_is_exact():
    """For the elastic law the water's share is the closed form to 1.5e-3 (measured 1.2e-3 with the
    pore-pressure smoothing, 1e-6 without: the smoothing spreads the drained top row's increments into the
    4-cell column). A formulation without K_w / n gives p = 0; incompressible water gives 1.8e-3 here
    (n M / K_w is small with water's K_w), which this bound separates only narrowly: the discriminating
    check of the water's compressibility is the undrained column (B = 0.962, test_pore_water.py)."""
    r = saturated_element("linear_elastic")
    assert abs(r["p_over_q"] / r["skempton"] - 1) < 1.5e-3, r
