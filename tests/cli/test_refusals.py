"""Bad input is refused by `geompm run` before anything is computed: exit code 2, the JSON path
and what is wrong on stderr, and no run folder left behind (issue 5, point 6).

Each case mutates the valid tiny case (tests/support/cases.py) in one way.  The
physical bounds are those of the laws' definitions: 0 <= nu < 0.5 for an
isotropic elastic solid with positive bulk modulus, rho > 0, E > 0,
0 <= phi < 90 deg for a friction angle.
"""

import json
import sys
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geompm.cli import main
from geompm.engine.launch import MPI_SIZE_VARIABLES, launched, world
from geompm.errors import CaseError
from geompm.schema import parse_case

from tests.support.cases import tiny_case


def _dp(case):
    case["materials"]["soil"] = {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 1e6,
                                 "poisson_ratio": 0.3, "friction_angle": 30.0}
    return case


def _overlap(case):
    case["bodies"].append({"material": "soil", "geometry": {"type": "box", "min": [0.5, 0.3], "max": [0.8, 0.6]}})
    return case


def _mesh_body(name):
    def mutate(case):
        case["dimension"] = 3
        case["grid"] = {"origin": [0, 0, 0], "extent": [1, 1, 1], "cell_size": 0.1}
        case["gravity"] = [0, -9.81, 0]
        case["bodies"][0]["geometry"] = {"type": "stl", "file": name}
        return case
    return mutate


def _set(path, value):
    def mutate(case):
        node = case
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[int(k)] if isinstance(node, list) else node[k]
        node[keys[-1]] = value
        return case
    return mutate


REFUSED = [
    ("unknown key", _set("time.cfll", 0.5), "time.cfll", "did you mean 'cfl'"),
    ("wrong type", _set("grid.cell_size", "fine"), "grid.cell_size", "must be a number"),
    ("nu = 0.5", _set("materials.soil.poisson_ratio", 0.5), "materials.soil.poisson_ratio", "< 0.5"),
    ("density 0", _set("materials.soil.density", 0.0), "materials.soil.density", "> 0"),
    ("modulus < 0", _set("materials.soil.youngs_modulus", -1e6), "materials.soil.youngs_modulus", "> 0"),
    ("phi = 90", lambda c: _set("materials.soil.friction_angle", 90.0)(_dp(c)),
     "materials.soil.friction_angle", "< 90"),
    ("phi < 0", lambda c: _set("materials.soil.friction_angle", -5.0)(_dp(c)),
     "materials.soil.friction_angle", ">= 0"),
    ("ppc 0", _set("bodies.0.particles_per_cell", 0), "bodies.0.particles_per_cell", ">= 1"),
    ("body outside", _set("bodies.0.geometry.max", [1.5, 0.4]), "bodies.0.geometry", "outside the grid"),
    ("overlap", _overlap, "bodies.1.geometry", "overlaps bodies.0"),
    ("missing mesh", _mesh_body("meshes/none.stl"), "bodies.0.geometry.file", "not found"),
    ("memory", _set("grid.cell_size", 2e-5), "grid.cell_size", "GiB"),
    ("output interval", _set("outputs.0.interval", 1e-6), "outputs.0.interval", "shorter than the time step"),
]


@pytest.mark.parametrize("mutate,where,words", [r[1:] for r in REFUSED], ids=[r[0] for r in REFUSED])
def test_run_refuses_bad_input_before_work(tmp_path, capsys, mutate, where, words):
    f = tmp_path / "case.json"
    f.write_text(json.dumps(mutate(tiny_case())))
    run = tmp_path / "run"
    assert main(["run", str(f), "--out", str(run), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert any(ln.strip().startswith(f"{where}:") and words in ln for ln in err.splitlines()), err
    assert not run.exists()


def test_malformed_json_names_line_and_column(tmp_path, capsys):
    f = tmp_path / "case.json"
    f.write_text('{"name": "x",\n "dimension": 2\n "grid": {}}')
    assert main(["run", str(f), "--out", str(tmp_path / "run")]) == 2
    assert "line 3, column 2" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads any file; the permission check cannot be seen")
def test_unreadable_mesh_is_refused(tmp_path, capsys):
    (tmp_path / "meshes").mkdir()
    mesh = tmp_path / "meshes" / "m.stl"
    mesh.write_text("solid x\nendsolid x\n")
    mesh.chmod(0)
    f = tmp_path / "case.json"
    f.write_text(json.dumps(_mesh_body("meshes/m.stl")(tiny_case())))
    assert main(["validate", str(f)]) == 2
    assert "cannot be read" in capsys.readouterr().err


# -- property-based: any mutation loads or fails with CaseError and a JSON path -----------------

_LEAF = st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**6),
                  st.floats(allow_nan=False, allow_infinity=False, width=32), st.text(max_size=8),
                  st.lists(st.floats(-2.0, 2.0, allow_nan=False), max_size=4))


def _paths(node, prefix=()):
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


def _mutate(draw, leaf, actions):
    """tiny_case with 1-3 mutations: replace a value anywhere by a draw of ``leaf``, delete a key, add one."""
    case = tiny_case()
    paths = [p for p in _paths(case) if p]
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(paths))
        node = case
        try:
            for k in path[:-1]:
                node = node[k]
            action = draw(st.sampled_from(actions))
            if action == "replace":
                node[path[-1]] = draw(leaf)
            elif action == "delete" and isinstance(node, dict):
                del node[path[-1]]
            elif isinstance(node, dict):
                node[draw(st.text(min_size=1, max_size=6))] = draw(leaf)
        except (KeyError, IndexError, TypeError):
            pass  # an earlier mutation changed the shape above this path
    return case


@st.composite
def mutated_cases(draw):
    return _mutate(draw, _LEAF, ["replace", "delete", "add"])


@settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_cases())
def test_mutated_cases_load_or_fail_with_a_json_path(case):
    """250 mutated cases (replace, delete or add a key anywhere, up to 3 times): the loader and the
    assembly either succeed or raise CaseError whose every problem has a JSON path and a message."""
    from geompm.setup.assemble import assemble

    try:
        assemble(parse_case(case))
    except CaseError as exc:
        assert exc.problems
        for path, msg in exc.problems:
            assert isinstance(path, str) and msg
            assert path or "case" in msg or "grid" in msg or "JSON" in msg, exc.problems


# -- property-based, hostile numbers and shapes (issue 14): NaN, +/-Infinity, 1e308, -0.0, deep nesting,
# wrong types inside lists, through the file and through --set; geompm validate answers 0 or 2, never a traceback

def _nested(depth):
    node: list = [1.0]
    for _ in range(depth):
        node = [node]
    return node


_HOSTILE = st.one_of(
    st.sampled_from([float("nan"), float("inf"), -float("inf"), 1e308, -1e308, -0.0, 0.0, 5e-324, 10**400]),
    st.floats(), st.integers(-10**30, 10**30), st.text(max_size=6), st.none(), st.booleans(),
    st.lists(st.one_of(st.floats(), st.text(max_size=3), st.none(), st.booleans()), max_size=4),
    st.integers(33, 80).map(_nested),
)


def _hostile_inside(node, depth=0) -> bool:
    """A non-finite float, an integer beyond a double, or nesting deeper than 32 anywhere in ``node``."""
    if depth > 32:
        return True
    if isinstance(node, dict):
        return any(_hostile_inside(v, depth + 1) for v in node.values())
    if isinstance(node, list):
        return any(_hostile_inside(v, depth + 1) for v in node)
    if isinstance(node, float):
        return node != node or node in (float("inf"), -float("inf"))
    return isinstance(node, int) and abs(node) > 10**308


@st.composite
def hostile_cases(draw):
    return _mutate(draw, _HOSTILE, ["replace", "add"])


def _validate_exit(tmp_path, case, sets=()) -> tuple[int, str]:
    import io
    from contextlib import redirect_stderr, redirect_stdout

    f = tmp_path / "case.json"
    f.write_text(json.dumps(case, allow_nan=True))
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(["validate", str(f), *sum((["--set", s] for s in sets), [])])
    return code, err.getvalue()


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                 HealthCheck.function_scoped_fixture])
@given(hostile_cases())
def test_hostile_numbers_give_exit_0_or_2_and_a_json_path(tmp_path, case):
    """150 cases with NaN, Infinity, 1e308, -0.0, 5e-324, a 400-digit integer, 33-80-deep lists or wrong
    types put anywhere: `geompm validate` exits 0 or 2, a non-finite number is always refused, and every
    refusal names a JSON path.  Any other exception fails the test (main() lets it through)."""
    code, err = _validate_exit(tmp_path, case)
    assert code in (0, 2)
    if _hostile_inside(case):
        assert code == 2 and ("finite number" in err or "levels deep" in err or "too large" in err), err
    if code == 2:
        assert all(ln.startswith("  ") and ": " in ln for ln in err.splitlines()[1:]), err


_SET_VALUES = st.one_of(st.sampled_from(["NaN", "Infinity", "-Infinity", "1e308", "1e999", "-0.0", "[NaN]",
                                         "[" * 3000 + "]" * 3000, "9" * 5000, "{}", "[]", "null", "\"x\"",
                                         "[1, \"a\", null]", "{\"a\": [1, 2]}"]),
                        st.text(max_size=8))
_SET_KEYS = st.sampled_from(["time.end", "grid.cell_size", "gravity.0", "gravity.5", "gravity.-1", "gravity.x",
                             "materials.soil.density", "bodies.0.geometry.min.1", "name", "name.x", "",
                             ".", "a..b", "time", "bodies.0", "outputs.0.interval", "nosuch.key"])


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                 HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(_SET_KEYS, _SET_VALUES), min_size=1, max_size=3))
def test_hostile_set_values_give_exit_0_or_2(tmp_path, sets):
    """--set with hostile keys (out-of-range and negative indexes, a key below a string, empty parts) and
    values (NaN, Infinity, 1e999, 3000-deep lists, 5000-digit integers, objects for numbers): exit 0 or
    2, and a non-finite value put on a real number key is refused."""
    items = [f"{k}={v}" for k, v in sets]
    code, err = _validate_exit(tmp_path, tiny_case(), items)
    assert code in (0, 2), err
    last = dict(sets)  # a later --set of the same key replaces an earlier one
    for k in ("time.end", "grid.cell_size", "gravity.0", "materials.soil.density"):
        if last.get(k) in ("NaN", "Infinity", "-Infinity", "1e999") and not any(
                other in ("time", "grid", "gravity", "materials") for other in last):
            assert code == 2


@pytest.mark.parametrize("name", MPI_SIZE_VARIABLES)
def test_a_launch_count_that_mpi_does_not_see_is_refused(tmp_path, capsys, monkeypatch, name):
    """A launcher variable that says 2 processes while mpi4py's MPI sees one (another MPI's mpiexec started
    geompm, or the variable is stale): each copy would run the whole case into the same run folder, so the
    run is refused with exit code 2 before any folder is made, naming the variable.  MPICH's launcher sets
    PMI_SIZE (checked with mpiexec of the mpich 5.0.2 wheel), Open MPI OMPI_COMM_WORLD_SIZE, MVAPICH
    MV2_COMM_WORLD_SIZE."""
    monkeypatch.setenv(name, "2")
    f = tmp_path / "case.json"
    f.write_text(json.dumps(tiny_case()))
    run = tmp_path / "run"
    assert main(["run", str(f), "--out", str(run), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "error: refused:" in err
    assert f"{name}: the launcher started 2 processes ({name}=2) but mpi4py's MPI sees 1" in err
    assert not run.exists()


def test_several_processes_without_mpi4py_are_refused(monkeypatch):
    """Started as 3 processes with mpi4py missing (the '[mpi]' extra not installed): refused, naming the
    variable and the extra to install."""
    monkeypatch.setitem(sys.modules, "mpi4py", None)
    with pytest.raises(CaseError) as exc:
        world({"PMI_SIZE": "3"})
    where, text = exc.value.problems[0]
    assert where == "PMI_SIZE" and "one of 3 MPI processes" in text and "pip install 'geompm[mpi]'" in text


def test_a_single_mpi_process_runs_alone():
    """A launcher's single process (N = 1), an empty or a non-numeric variable run in one process (no
    communicator); a count of 3 is read from whichever launcher set it."""
    for env in ({}, {"PMI_SIZE": "1"}, {"OMPI_COMM_WORLD_SIZE": ""}, {"MV2_COMM_WORLD_SIZE": "x"}):
        assert launched(env) == (1, "") and world(env) is None
    for name in MPI_SIZE_VARIABLES:
        assert launched({name: "3"}) == (3, name)
