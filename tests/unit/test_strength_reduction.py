"""Strength reduction of the Mohr-Coulomb-type laws (materials/plasticity.py) and the strength trigger
(engine/triggers.py, schema triggers.strength_reduction).

The reduced Mohr-Coulomb envelope must be the original one divided by F at every normal stress:
tau = (c + sigma_n tan(phi)) / F (the definition of the factor of safety in Griffiths & Lane 1999,
Geotechnique 49(3):387, eq. 2).  The trigger must pack the reduced parameters into the law's own array
at the scheduled times and give the original array back at F = 1."""

import math

import numpy as np
import pytest

from geompm.contract.registry import get
from geompm.engine.triggers import StrengthSchedule
from geompm.errors import CaseError
from geompm.materials.mohr_coulomb import mc_principal_return
from geompm.materials.plasticity import reduced_angles
from geompm.schema.load import parse_case
from tests.support.cases import tiny_case


@pytest.mark.parametrize("factor", [0.7, 1.0, 1.37, 2.5])
def test_reduced_envelope_is_the_original_over_f(factor):
    law = get("materials", "mohr_coulomb")
    p = law.Params(density=2000.0, youngs_modulus=1e7, poisson_ratio=0.3, friction_angle=32.0, cohesion=5e3,
                   dilation_angle=10.0)
    r = law.strength_reduced(p, factor)
    assert r["cohesion"] == pytest.approx(5e3 / factor)
    assert math.tan(math.radians(r["friction_angle"])) == pytest.approx(math.tan(math.radians(32.0)) / factor)
    assert r["dilation_angle"] == pytest.approx(min(10.0, r["friction_angle"]))
    phi, c = math.radians(r["friction_angle"]), r["cohesion"]
    for sigma_n in (-2e5, -5e4, -1e3):  # compression negative
        # a Mohr circle tangent to tau = (c + |sigma_n| tan(phi0)) / F at the normal stress sigma_n
        tau = (5e3 - sigma_n * math.tan(math.radians(32.0))) / factor
        centre = sigma_n - tau * math.tan(phi)
        radius = tau / math.cos(phi)
        lam, G = 1e6, 1e6
        # 0.1 % inside the reduced envelope: no plastic return; 0.1 % beyond it: a return
        inside = mc_principal_return(centre + 0.999 * radius, centre, centre - 0.999 * radius, lam, G, math.sin(phi),
                                     math.cos(phi), 0.0, c)
        assert inside[3] == 0.0
        out = mc_principal_return(centre + 1.001 * radius, centre, centre - 1.001 * radius, lam, G, math.sin(phi),
                                  math.cos(phi), 0.0, c)
        assert out[3] > 0.0


def test_dilation_rule():
    """psi is kept unless it exceeds the reduced phi (Brinkgreve & Bakker 1991): associated stays associated."""
    assert reduced_angles(30.0, 30.0, 1.5) == pytest.approx((21.05172, 21.05172), abs=1e-5)
    assert reduced_angles(30.0, 5.0, 1.5)[1] == 5.0
    assert reduced_angles(30.0, 0.0, 0.5)[0] == pytest.approx(math.degrees(math.atan(2 * math.tan(math.radians(30)))))


def test_trigger_packs_the_reduced_law_in_place():
    law = get("materials", "drucker_prager")
    p = law.example_params()
    mat = law(p)
    original = mat.prm.copy()
    arr = mat.prm

    class Scene:
        materials = [mat]

    class Backend:
        told = 0

        def material_parameters_changed(self):
            self.told += 1

    be = Backend()
    s = StrengthSchedule([0.0, 1.0, 2.0], [1.0, 1.0, 2.0], [0])
    assert s.factor(-1.0) == 1.0 and s.factor(1.5) == 1.5 and s.factor(9.0) == 2.0
    s.apply(Scene, be, 0.5)
    assert be.told == 0 and np.array_equal(mat.prm, original)
    s.apply(Scene, be, 2.0)
    expect = law(p.model_copy(update=law.strength_reduced(p, 2.0))).prm
    assert mat.prm is arr and np.array_equal(mat.prm, expect) and be.told == 1
    assert mat.prm[law.layout.alpha] < original[law.layout.alpha]
    s.times = np.array([0.0, 3.0])
    s.factors = np.array([1.0, 1.0])
    s.apply(Scene, be, 2.5)
    assert np.array_equal(mat.prm, original) and be.told == 2


def _dp_case(**over):
    case = tiny_case()
    case["materials"] = {"soil": {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 1e6,
                                  "poisson_ratio": 0.3, "friction_angle": 30.0, "cohesion": 100.0},
                         "water": {"model": "newtonian", "density": 1000.0, "sound_speed": 20.0, "viscosity": 1e-3}}
    case.update(over)
    return case


@pytest.mark.parametrize("trigger, path", [
    ({"times": [0.0, 1.0], "factors": [1.0]}, "triggers.strength_reduction"),
    ({"times": [1.0, 0.5], "factors": [1.0, 2.0]}, "triggers.strength_reduction"),
    ({"times": [0.0], "factors": [0.0]}, "triggers.strength_reduction"),
    ({"times": [0.0], "factors": [2.0], "materials": ["clay"]}, "triggers.strength_reduction.materials.0"),
    ({"times": [0.0], "factors": [2.0], "materials": ["water"]}, "triggers.strength_reduction.materials.0"),
])
def test_bad_triggers_are_refused_with_their_path(trigger, path):
    with pytest.raises(CaseError) as err:
        parse_case(_dp_case(triggers={"strength_reduction": trigger}))
    assert path in [p for p, _ in err.value.problems]


def test_trigger_reaches_the_scene():
    from geompm.setup.assemble import assemble

    loaded = parse_case(_dp_case(triggers={"strength_reduction": {"times": [0.0, 1.0], "factors": [1.0, 1.5]}}))
    scene = assemble(loaded)
    times, factors, ids = scene.strength_trigger
    assert times == (0.0, 1.0) and factors == (1.0, 1.5) and [scene.material_names[i] for i in ids] == ["soil"]


def test_validate_reports_the_trigger(tmp_path, capsys):
    import json

    from geompm.cli import main

    case = tmp_path / "t.json"
    case.write_text(json.dumps(_dp_case(triggers={"strength_reduction": {"times": [0.0, 2.0], "factors": [1.0, 1.5]}})))
    assert main(["validate", str(case)]) == 0
    assert "strength trigger: the strength of soil divided by F = 1 at 0 s, 1.5 at 2 s" in capsys.readouterr().out
