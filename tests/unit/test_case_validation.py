"""Malformed cases are refused by `geompm validate` with exit code 2 and the JSON path.

Each case mutates a valid tiny case (tests/support/cases.py) in one place; the test
asserts the exit code and that stderr names the offending path and says what
is wrong.
"""

import json

import pytest

from geompm.cli import main

from tests.support.cases import tiny_case


def _set(case, path, value):
    keys = path.split(".")
    node = case
    for k in keys[:-1]:
        node = node[int(k)] if isinstance(node, list) else node[k]
    last = keys[-1]
    if value is _DELETE:
        del node[last]
    elif isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value
    return case


_DELETE = object()

MALFORMED = [
    # (mutation path, new value, expected path in the message, expected words)
    ("materials.soil.poisson_ratio", 0.5, "materials.soil.poisson_ratio", "must be < 0.5"),
    ("materials.soil.youngs_modulus", -1.0, "materials.soil.youngs_modulus", "must be > 0"),
    ("materials.soil.density", "heavy", "materials.soil.density", "must be a number"),
    ("materials.soil.youngs_modulos", 1e6, "materials.soil.youngs_modulos", "did you mean 'youngs_modulus'"),
    ("materials.soil.model", "linear_elastc", "materials.soil.model", "did you mean 'linear_elastic'"),
    ("grid.cell_size", 0.0, "grid.cell_size", "must be > 0"),
    ("grid.origin", [0.0, 0.0, 0.0], "grid.origin", "must have 2 entries"),
    ("gravity", [0.0], "gravity", "must have 2 entries"),
    ("dimension", 4, "dimension", "must be one of"),
    ("time.end", _DELETE, "time.end", "required key is missing"),
    ("time.cfll", 0.5, "time.cfll", "did you mean 'cfl'"),
    ("bodies.0.material", "sand", "bodies.0.material", "no material named 'sand'"),
    ("bodies.0.particles_per_cell", 0, "bodies.0.particles_per_cell", "must be >= 1"),
    ("bodies.0.geometry.max", [2.0, 0.4], "bodies.0.geometry", "outside the grid"),
    ("bodies.0.geometry.type", "sphere", "bodies.0.geometry", "sphere"),
    ("bodies.0.geometry.mn", [0.1, 0.1], "bodies.0.geometry.mn", "did you mean 'min'"),
    ("boundaries.0.side", "z-", "boundaries.0.side", "does not exist in a 2D case"),
    ("boundaries.0.condition", "sticky", "boundaries.0.condition", "must be one of"),
    ("outputs.0.writer", "vtk", "outputs.0.writer", "did you mean 'vtu'"),
    ("outputs.0.interval", -1.0, "outputs.0.interval", "must be >= 0"),
    ("solver.transfer", "usf", "solver.transfer", "must be one of"),
    ("bodies.0.surface_normal", [0.0, 1.0], "bodies.0.surface_normal", "only used with"),
    ("bodies.0.surface_normal", [0.0, 1.0, 0.0], "bodies.0.surface_normal", "must have 2 entries"),
]


@pytest.mark.parametrize("path,value,where,words", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_case_is_refused_with_its_json_path(tmp_path, capsys, path, value, where, words):
    f = tmp_path / "case.json"
    f.write_text(json.dumps(_set(tiny_case(), path, value)))
    assert main(["validate", str(f)]) == 2
    err = capsys.readouterr().err
    lines = [ln.strip() for ln in err.splitlines() if ln.strip().startswith(where + ":")]
    assert lines, f"no line for {where!r} in:\n{err}"
    assert any(words in ln for ln in lines), err


def test_malformed_json_reports_line_and_column(tmp_path, capsys):
    f = tmp_path / "case.json"
    f.write_text('{\n  "name": "x",\n  "dimension": 2,,\n}')
    assert main(["validate", str(f)]) == 2
    assert "line 3, column 18" in capsys.readouterr().err


def test_every_problem_is_reported_at_once(tmp_path, capsys):
    case = tiny_case()
    case["materials"]["soil"]["poisson_ratio"] = 0.7
    case["bodies"][0]["material"] = "rock"
    f = tmp_path / "case.json"
    f.write_text(json.dumps(case))
    assert main(["validate", str(f)]) == 2
    err = capsys.readouterr().err
    assert "materials.soil.poisson_ratio" in err and "bodies.0.material" in err


def test_surface_normal_must_point_against_gravity(tmp_path, capsys):
    """A ground-surface normal along gravity would put the overburden below each particle."""
    case = tiny_case()
    case["bodies"][0].update(initial_stress="geostatic", surface_normal=[0.5, -0.866])
    f = tmp_path / "case.json"
    f.write_text(json.dumps(case))
    assert main(["validate", str(f)]) == 2
    assert "bodies.0.surface_normal: must point out of the ground" in capsys.readouterr().err


def test_valid_case_prints_a_summary(tmp_path, capsys):
    """The tiny case: 0.4 m x 0.4 m box, h = 0.1 m, 2 x 2 particles per cell -> 64 particles."""
    f = tmp_path / "case.json"
    f.write_text(json.dumps(tiny_case()))
    assert main(["validate", str(f)]) == 0
    out = capsys.readouterr().out
    assert "64 particles" in out and "100 grid cells" in out


def test_set_override_is_validated(tmp_path, capsys):
    f = tmp_path / "case.json"
    f.write_text(json.dumps(tiny_case()))
    assert main(["validate", str(f), "--set", "materials.soil.poisson_ratio=0.6"]) == 2
    assert "materials.soil.poisson_ratio: must be < 0.5" in capsys.readouterr().err
    assert main(["validate", str(f), "--set", "grid.nope.x=1"]) == 2
