"""Bad input to the critical-state laws is refused (or warned) before any work, naming its JSON path
(docs/materials.md, critical_state_sand and modified_cam_clay)."""

import pytest

from geompm.api import scene_from_dict
from geompm.cli import main
from geompm.errors import CaseError

SAND = {"model": "critical_state_sand", "density": 2650.0, "youngs_modulus": 1e7, "poisson_ratio": 0.3,
        "critical_friction_angle": 30.0, "critical_solid_fraction": 0.58, "dilatancy_coefficient": 4.09}
CLAY = {"model": "modified_cam_clay", "density": 1800.0, "poisson_ratio": 0.3, "critical_friction_angle": 25.0,
        "compression_index": 0.2, "swelling_index": 0.04, "void_ratio": 1.0}


def case(material: dict, pore_water=None) -> dict:
    m = dict(material)
    if pore_water is not None:
        m["pore_water"] = pore_water
    return {"name": "cs", "dimension": 2, "grid": {"origin": [0, 0], "extent": [1.0, 1.0], "cell_size": 0.1},
            "time": {"end": 0.01}, "gravity": [0, -9.81], "materials": {"soil": m},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0], "max": [1.0, 0.5]},
                        "initial_stress": "geostatic"}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "fixed"}], "outputs": []}


def water(n):
    return {"porosity": n, "hydraulic_conductivity": 1e-4, "fluid": {"bulk_modulus": 2e7}}


@pytest.mark.parametrize("raw, path, words", [
    (case(SAND), "materials.soil.solid_fraction", "needs its initial solid volume fraction"),
    (case(dict(SAND, solid_fraction=0.70, max_solid_fraction=0.65)), "materials.soil.solid_fraction",
     "denser than max_solid_fraction"),
    (case(dict(SAND, solid_fraction=0.40)), "materials.soil.solid_fraction", "looser than the loosest state"),
    (case(SAND, water(0.62)), "materials.soil.pore_water.porosity", "looser than the loosest state"),
    (case(dict(SAND, max_solid_fraction=0.62), water(0.36)), "materials.soil.pore_water.porosity",
     "denser than max_solid_fraction"),
    (case(dict(CLAY, compression_index=0.5)), "materials.soil.compression_index", "negative void ratio"),
    (case(dict(CLAY, swelling_index=0.3)), "materials.soil", "must be below compression_index"),
])
def test_bad_critical_state_input_is_refused_with_its_path(raw, path, words):
    """The loosest state is phi_c - tan(phi_cs) / K = 0.58 - 0.577 / 4.09 = 0.439; a clay with lambda = 0.5 and
    e0 = 1.0 reaches e = 1.0 - 0.5 ln 10 = -0.15 within a decade of stress."""
    with pytest.raises(CaseError) as err:
        scene_from_dict(raw)
    text = str(err.value)
    assert path in text and words in text, text


def test_valid_states_assemble_and_warn_what_looks_wrong(tmp_path, capsys):
    """A saturated sand whose solid_fraction disagrees with its porosity is warned (the porosity sets it,
    0.55 here), a clay whose preconsolidation pressure is below the initial mean effective stress at depth is
    warned (4.9 kPa of buoyant overburden at 0.5 m beside p_c = 1 kPa), and both assemble."""
    sand = scene_from_dict(case(dict(SAND, solid_fraction=0.6), water(0.45)))
    assert sand.materials[0].params.solid_fraction == pytest.approx(0.55)
    path = tmp_path / "clay.json"
    path.write_text(__import__("json").dumps(case(dict(CLAY, preconsolidation_pressure=1000.0))))
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    assert "materials.soil.preconsolidation_pressure" in out and "below the initial mean effective stress" in out
