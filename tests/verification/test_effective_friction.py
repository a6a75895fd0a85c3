"""Basal friction on the effective normal force (docs/pore-water.md, Friction on effective stress): a saturated
elastic layer on an impermeable plane at 25 degrees, periodic along it (the infinite slope's layer), mu = 0.6,
k = 1e-8 m/s, slides at a = g (sin b - (1 - lambda) mu cos b) with lambda = p_b / sigma_n its base's
pore-pressure ratio (Iverson 1997, Rev. Geophys. 35:245, eq. 2): rho_w / rho_sat with the table at its top and
parallel to the plane, more with a uniform excess.  Its dry twin stands (tan 25 = 0.47 < 0.6).  Three cell
sizes in benchmarks/pore_water/sliding_block.py (raw output benchmarks/results/2026-12-05-issue52/); this
runs the coarse pair with linear shape functions and PIC (the transfer that is stable here: docs, Limits)."""

from __future__ import annotations

import pytest

from geompm.testing.verification import flowing_strip
from geompm.testing.verification import sliding_block as sb

pytestmark = pytest.mark.slow

#: the excess pore pressure [Pa] that makes the base's lambda 0.7
EXCESS = sb.excess_for(0.7)


def test_the_dry_layer_stands_on_the_25_degree_plane():
    """tan 25 = 0.466 < mu = 0.6: friction on the total (here the effective) weight holds the dry layer."""
    r = sb.block_acceleration(sb.block_case(0.05, saturated=False, transfer="pic", shape="linear", end=0.3))
    assert abs(r["acceleration"]) < 1e-3 and abs(r["speed"]) < 1e-3


@pytest.mark.parametrize("excess, update", [(0.0, "saturated"), (EXCESS, "saturated"), (0.0, "saturated_musl")],
                         ids=["table-at-top", "excess", "table-at-top-musl"])
def test_the_saturated_layer_slides_on_its_effective_weight(excess, update):
    """The layer's acceleration against g (sin b - (1 - lambda) mu cos b): 1.492 m/s2 with the table at the
    top (lambda 0.5025), 2.546 m/s2 with lambda 0.7; measured -3.8 % / -1.8 % and +2.5 % / +0.3 % at
    h = 0.05 / 0.025 m, in MUSL order (saturated_musl) -3.8 / -1.8 % with the table at the top.  Total-stress
    friction would hold it (a = 0): the pore pressure must reach the base."""
    lam = sb.block_lambda(excess)
    expected = sb.closed_form(lam)
    errors = []
    for h in (0.05, 0.025):
        case = sb.block_case(h, excess=excess, transfer="pic", shape="linear", end=0.4)
        case["solver"]["update"] = update
        r = sb.block_acceleration(case)
        errors.append(r["acceleration"] / expected - 1.0)
        assert r["lambda_base"] == pytest.approx(lam, abs=0.02)
    assert abs(errors[0]) < 0.045, errors
    assert abs(errors[1]) < 0.02 and abs(errors[1]) < abs(errors[0]), errors


@pytest.mark.slow
def test_a_flowing_saturated_layer_slides_on_its_effective_basal_friction():
    """A saturated Drucker-Prager layer (phi = 40, psi = 0, k = 1e-5 m/s) flowing down a periodic strip of a
    31 degree slope (geompm/testing/verification/flowing_strip.py; linear PIC): its base slides at
    a = g (sin b - mu (1 - lambda) cos b) with the basal ratio lambda it carries, within 2 % at h = 0.04 and
    0.02 m (measured +0.43 / +0.23 %), and the total normal stress on the bed is the weight above the lowest
    row within 5 % (measured +3.5 / -0.3 %).  The layer keeps its basal pressure, unlike a finite block
(docs/validation/wet-bed-entrainment.md): lambda rises from its hydrostatic 0.495 to 0.64 within 0.1 s (measured 0.644 /
    0.645): the undrained stress path of a soil sheared from its K0 start to the flowing state, not a grid
    artefact (docs/pore-water.md, Friction on effective stress)."""
    for h in (0.04, 0.02):
        r = flowing_strip.flow(h)
        assert abs(r["a_error"]) < 0.02, r
        assert abs(r["sigma_error"]) < 0.05, r
        assert r["lambda"] > r["lambda_start"], r  # the infinite layer keeps (here raises) its basal pressure
