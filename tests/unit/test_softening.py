"""Strain-softening Mohr-Coulomb and Drucker-Prager (materials/softening.py and the two laws).

Checked against exact values: the softening curve at its thresholds; the thresholds' scaling h_ref / h;
and a particle sheared in plane strain (phi = psi = 0, so both laws' yield stress in simple shear is the
current cohesion: tau = c(eps_p), with eps_p = gamma_p / sqrt(3), the equivalent plastic shear strain of
simple shear) following the curve from peak to residual, for the linear and the exponential curve.
Also: strength reduction divides peak and residual alike, and residual above peak or thresholds out of
order are refused with their JSON path."""

import math

import numpy as np
import pytest

from geompm.contract.registry import get
from geompm.errors import CaseError
from geompm.materials.softening import LN100, SOFT_BASE, softened
from geompm.schema.load import parse_case
from tests.support.cases import tiny_case


def test_curve_values():
    assert softened(10.0, 2.0, 0.01, 0.02, 0.1, 0.0) == 10.0
    assert softened(10.0, 2.0, 0.06, 0.02, 0.1, 0.0) == pytest.approx(6.0)
    assert softened(10.0, 2.0, 0.5, 0.02, 0.1, 0.0) == 2.0
    assert softened(10.0, 2.0, 0.1, 0.02, 0.1, 1.0) == pytest.approx(2.0 + 8.0 * 0.01)
    assert softened(10.0, 2.0, 0.06, 0.02, 0.1, 1.0) == pytest.approx(2.0 + 8.0 * math.exp(-LN100 / 2))


def _params(name, **soft):
    law = get("materials", name)
    return law, law.Params(density=2000.0, youngs_modulus=1e8, poisson_ratio=0.25, friction_angle=0.0, cohesion=1e4,
                           dilation_angle=0.0, residual_cohesion=2e3, residual_friction_angle=0.0,
                           softening={"start": 0.01, "end": 0.05, **soft})


@pytest.mark.parametrize("name", ["mohr_coulomb_softening", "drucker_prager_softening"])
def test_thresholds_scale_with_the_cell(name):
    law, p = _params(name, reference_cell_size=0.05)
    q = law.at_cell_size(p, 0.025)
    assert (q.softening.start, q.softening.end) == pytest.approx((0.02, 0.10))
    assert law.at_cell_size(_params(name)[1], 0.025).softening.end == 0.05  # no reference: strains as given
    assert law(q).prm[law.layout.soft_end] == pytest.approx(0.10)
    assert law.layout.phi_peak == SOFT_BASE  # strength_at reads the SOFT slots from there


@pytest.mark.parametrize("shape", ["linear", "exponential"])
@pytest.mark.parametrize("name", ["mohr_coulomb_softening", "drucker_prager_softening"])
def test_simple_shear_follows_the_curve(name, shape):
    law, p = _params(name, shape=shape)
    mat = law(p)
    s, state = np.zeros(6), np.zeros(2)
    L = np.zeros((3, 3))
    dt, rate = 1e-4, 1.0  # shear strain 1e-4 a step: eps_p moves by 5.8e-5 a step
    L[0, 1] = rate
    worst, plastic = 0.0, 0
    for _ in range(1500):
        before = state[0]
        law.particle_stress(mat.prm, dt, L, 2000.0, s, state)
        if state[0] > before:  # a plastic step returns to the strength at the plastic strain it started from
            c = softened(1e4, 2e3, before, 0.01, 0.05, 1.0 if shape == "exponential" else 0.0)
            worst = max(worst, abs(math.sqrt(0.25 * (s[0] - s[1]) ** 2 + s[3] ** 2) - c) / 1e4)
            plastic += 1
    assert state[0] > 0.06 and plastic > 1000  # past the end of softening
    assert worst < 1e-12
    assert state[1] == pytest.approx(0.0, abs=1e-12)  # psi = 0: no plastic volume change


def test_reduction_divides_peak_and_residual():
    law, p = _params("mohr_coulomb_softening")
    p = p.model_copy(update={"friction_angle": 30.0, "residual_friction_angle": 20.0})
    r = law.strength_reduced(p, 2.0)
    assert r["cohesion"] == 5e3 and r["residual_cohesion"] == 1e3
    assert math.tan(math.radians(r["residual_friction_angle"])) == pytest.approx(math.tan(math.radians(20.0)) / 2)


@pytest.mark.parametrize("change, path, words", [
    ({"residual_cohesion": 2e4}, "materials.soil", "residual_cohesion"),
    ({"residual_friction_angle": 35.0}, "materials.soil", "residual_friction_angle"),
    ({"softening": {"start": 0.05, "end": 0.01}}, "materials.soil.softening", "above softening.start"),
])
def test_bad_softening_is_refused(change, path, words):
    soil = {"model": "drucker_prager_softening", "density": 2000.0, "youngs_modulus": 1e6, "poisson_ratio": 0.3,
            "friction_angle": 30.0, "cohesion": 1e4, "residual_cohesion": 1e3, "residual_friction_angle": 25.0,
            "softening": {"start": 0.0, "end": 0.1}, **change}
    with pytest.raises(CaseError) as err:
        parse_case(tiny_case(materials={"soil": soil}))
    assert any(p == path and words in m for p, m in err.value.problems), err.value.problems
