"""geompm's packages form layers: no circle between files or packages, no import from a lower layer into a
higher one (tests/support/import_graph.py declares the order and reads the imports with ``ast``).
"""

from pathlib import Path

import pytest

from tests.support import import_graph as G

PACKAGE = Path(__file__).resolve().parents[2] / "geompm"


@pytest.fixture(scope="module")
def graph():
    return G.read_graph(PACKAGE)


def test_no_circles_between_files(graph):
    modules, edges = graph
    assert G.circles(edges) == []


def test_no_circles_between_packages(graph):
    modules, edges = graph
    assert G.circles(G.package_edges(modules, edges)) == []


def test_every_package_has_a_layer(graph):
    modules, _ = graph
    assert {G.package_of(m, modules) for m in modules} <= set(G.LAYER_OF)


def test_no_upward_imports(graph):
    """A law never imports the backend, the backend never imports the engine, set-up compiles nothing
    from the engine; in general, no package imports one of a higher layer."""
    modules, edges = graph
    assert G.upward_imports(modules, edges) == []


def test_the_checker_sees_a_circle_and_an_upward_import(tmp_path):
    """The checks can fail: a law importing the backend, which imports the law back, is two faults."""
    pkg = tmp_path / "geompm"
    for d in ("materials", "backend"):
        (pkg / d).mkdir(parents=True)
        (pkg / d / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "materials" / "law.py").write_text("from geompm.backend.loops import run\n")
    (pkg / "backend" / "loops.py").write_text("def run():\n    from geompm.materials import law\n")
    modules, edges = G.read_graph(pkg)
    assert G.circles(edges) == [["geompm.backend.loops", "geompm.materials.law"]]
    assert G.upward_imports(modules, edges) == [("geompm.materials.law", "geompm.backend.loops")]


def test_every_package_says_what_it_owns():
    """Each package's __init__ opens with a docstring (what the package owns)."""
    import ast

    missing = [str(p.relative_to(PACKAGE.parent)) for p in PACKAGE.rglob("__init__.py")
               if "__pycache__" not in p.parts and not ast.get_docstring(ast.parse(p.read_text()))]
    assert not missing


def test_no_import_path_is_kept_for_old_callers():
    """The package is 0.1.0 and keeps no forwarding module: geompm.stages, geompm.plugin, geompm.layout and
    geompm.registry are gone (their homes are in geompm.contract), and importing one fails."""
    import importlib

    for old in ("geompm.stages", "geompm.plugin", "geompm.layout", "geompm.registry", "geompm._moved"):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(old)


def test_assembling_a_scene_compiles_no_law(monkeypatch):
    """Building a Scene seeds particles and checks the case; it runs no law's loop (the first step's checks,
    engine/first_step.py, do that before the run).  With the law loops' factory made to fail, a DP scene
    still assembles."""
    from geompm.api import scene_from_dict
    from geompm.backend import cpu_loops
    from tests.support.cases import tiny_case

    def refuse(law):
        raise AssertionError(f"assembly compiled the loops of {law.name}")

    monkeypatch.setattr(cpu_loops, "block_loops", refuse)
    case = tiny_case()
    case["materials"]["soil"] = {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 1e6,
                                 "poisson_ratio": 0.3, "friction_angle": 30.0}
    scene = scene_from_dict(case)
    assert scene.state.n > 0


def test_benchmarks_stand_on_the_package_not_on_the_tests():
    """No benchmark script imports tests/ (nor puts the repository on sys.path to do so): the harnesses they
    share with the tests live in geompm.testing.verification."""
    import ast

    root = PACKAGE.parent
    found = []
    for path in sorted((root / "benchmarks").rglob("*.py")):
        if "results" in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            found += [f"{path.relative_to(root)}: {n}" for n in names if n == "tests" or n.startswith("tests.")]
    assert not found, found
