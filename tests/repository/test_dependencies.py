"""Every import in geompm/ and plugins/ is the standard library or a declared requirement (issue 14).

An AST scan of every module collects the top-level name of each absolute
import.  A name from the standard library (``sys.stdlib_module_names``) or
the package itself passes; any other must map, through
``importlib.metadata.packages_distributions()``, to a distribution that the
installed package's metadata (``importlib.metadata.requires``) declares.  An
import at module level must be a core dependency; one inside a function (a
lazy import for an optional feature) may come from an extra as well.  The
check that CI runs the suite in a fresh virtual environment (.ci/run) makes
an undeclared import fail there even if this machine happens to have it.
"""

import ast
import importlib.metadata as md
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _declared(dist: str) -> tuple[set[str], set[str]]:
    """(core requirement names, requirement names of any extra) of an installed distribution, normalised."""
    core, extra = set(), set()
    for req in md.requires(dist) or []:
        name = re.split(r"[\s\[<>=!~;(]", req, maxsplit=1)[0]
        (extra if "extra ==" in req else core).add(_norm(name))
    return core, extra


def _norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _imports(src: Path) -> list[tuple[str, bool, int]]:
    """(top-level module, at module level?, line) of every absolute import in a file."""
    tree = ast.parse(src.read_text())
    lazy = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
            for n in ast.walk(f)}
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name.split(".")[0], id(node) not in lazy, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.append((node.module.split(".")[0], id(node) not in lazy, node.lineno))
    return out


PACKAGES = [("geompm", ROOT / "geompm", "geompm"),
            ("geompm-mu-i", ROOT / "plugins" / "geompm-mu-i" / "geompm_mu_i", "geompm_mu_i")]


def undeclared(files, root: Path, dist: str, own: str) -> list[str]:
    """What the scan refuses in ``files``: imports that are neither stdlib nor declared by ``dist``."""
    core, extra = _declared(dist)
    provides = md.packages_distributions()
    problems = []
    for src in files:
        for mod, top, line in _imports(src):
            if mod in sys.stdlib_module_names or mod in (own, "__future__"):
                continue
            dists = {_norm(d) for d in provides.get(mod, [])}
            allowed = core if top else core | extra
            if not dists:
                problems.append(f"{src.relative_to(root)}:{line}: '{mod}' is not installed by any distribution")
            elif not dists & allowed:
                kind = "a core dependency" if top else "a dependency or an extra"
                problems.append(f"{src.relative_to(root)}:{line}: '{mod}' ({', '.join(sorted(dists))}) is not "
                                f"declared as {kind} of {dist}")
    return problems


@pytest.mark.parametrize("dist,folder,own", PACKAGES, ids=[p[0] for p in PACKAGES])
def test_every_import_is_stdlib_or_declared(dist, folder, own):
    problems = undeclared(sorted(folder.rglob("*.py")), ROOT, dist, own)
    assert not problems, "\n".join(problems)


def test_the_scan_refuses_what_is_not_declared(tmp_path):
    """The check can fail: hypothesis (only in the 'test' extra) is refused at module level and allowed in a
    function; a module that no installed distribution provides is refused anywhere; scipy is declared
    (trimesh's proximity queries need it)."""
    src = tmp_path / "mod.py"
    src.write_text("import hypothesis\nimport numpy\n\ndef f():\n    import hypothesis\n    import no_such_xyz\n")
    problems = undeclared([src], tmp_path, "geompm", "geompm")
    assert len(problems) == 2
    assert "mod.py:1: 'hypothesis'" in problems[0] and "core dependency" in problems[0]
    assert "mod.py:6: 'no_such_xyz' is not installed" in problems[1]
    assert "scipy" in _declared("geompm")[0]
