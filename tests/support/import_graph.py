"""geompm's import graph, read from the source with ``ast`` (nothing is imported), and its layer order.

    python -m tests.support.import_graph [PACKAGE_DIR]    # the figures: modules, packages, circles, upward imports

Every ``import`` and ``from ... import`` of a geompm module counts, at module level or inside a function
(a lazy import is still a dependency).  A "package" is the first name under ``geompm`` (``geompm.contact``,
or a top-level module such as ``geompm.errors``).  The layer order below is the one declaration of which
package may import which: a package may import packages of its own layer or of a lower one, never of a
higher one, and no two files or two packages may import each other through any chain (a circle).
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

#: geompm's layers, lowest first (docs/architecture.md draws them)
LAYERS: tuple[tuple[str, ...], ...] = (
    ("version", "errors"),
    ("contract",),
    ("kernels",),
    ("mpm",),
    ("files",),
    ("parallel",),
    ("materials", "damping", "contact"),
    ("boundaries", "obstacles", "probes", "sources"),
    ("backend",),
    ("schemes",),
    ("writers",),
    ("schema",),
    ("setup",),
    ("engine",),
    ("api", "testing", "study", "stability", "bench", "plots"),
    ("cli",),
    # the package's own __init__
    ("__init__",),
)
LAYER_OF = {pkg: k for k, names in enumerate(LAYERS) for pkg in names}


def module_name(path: Path, package_dir: Path) -> str:
    parts = list(path.relative_to(package_dir.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def package_of(module: str, modules: dict[str, Path]) -> str:
    """``geompm.contact.rules`` -> ``contact``; ``geompm.errors`` -> ``errors``; ``geompm`` -> ``__init__``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def read_graph(package_dir: Path) -> tuple[dict[str, Path], dict[str, set[str]]]:
    """(module -> file, module -> the geompm modules it imports)."""
    root = package_dir.name
    modules = {module_name(p, package_dir): p for p in sorted(package_dir.rglob("*.py"))
               if "__pycache__" not in p.parts}
    edges: dict[str, set[str]] = {}
    for mod, path in modules.items():
        pkg = mod if path.name == "__init__.py" else mod.rsplit(".", 1)[0]
        found = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                found |= {a.name for a in node.names if a.name.split(".")[0] == root}
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if target.split(".")[0] != root:
                    continue
                for a in node.names:  # `from geompm.x import y` imports the module geompm.x.y if it is one
                    found.add(f"{target}.{a.name}" if f"{target}.{a.name}" in modules else target)
        edges[mod] = {t for t in found if t in modules and t != mod}
    return modules, edges


def circles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one member (Tarjan), each sorted."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))
    for v in sorted(edges):
        if v not in index:
            visit(v)
    return sorted(out)


def package_edges(modules, edges) -> dict[str, set[str]]:
    out: dict[str, set[str]] = {}
    for m, targets in edges.items():
        a = package_of(m, modules)
        out.setdefault(a, set())
        for t in targets:
            b = package_of(t, modules)
            if a != b:
                out[a].add(b)
    return out


def upward_imports(modules, edges) -> list[tuple[str, str]]:
    """(importer, imported) pairs where the imported module's package sits in a higher layer; a package
    missing from LAYERS counts as upward everywhere (it must be placed)."""
    bad = []
    for m, targets in sorted(edges.items()):
        a = LAYER_OF.get(package_of(m, modules), -1)
        for t in sorted(targets):
            b = LAYER_OF.get(package_of(t, modules), len(LAYERS))
            if a < b:
                bad.append((m, t))
    return bad


def figures(package_dir: Path) -> dict:
    modules, edges = read_graph(package_dir)
    pe = package_edges(modules, edges)
    return {"modules": len(modules), "packages": len(pe),
            "top_level_modules": sum(1 for m, p in modules.items() if m.count(".") == 1 and p.name != "__init__.py"),
            "module_circles": circles(edges), "package_circles": circles(pe),
            "upward_imports": upward_imports(modules, edges)}


if __name__ == "__main__":
    here = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "geompm"
    f = figures(here)
    print(f"{f['modules']} modules in {f['packages']} packages ({f['top_level_modules']} loose modules in geompm/)")
    print(f"circles between files: {len(f['module_circles'])}: {f['module_circles']}")
    print(f"circles between packages: {len(f['package_circles'])}: {f['package_circles']}")
    print(f"imports from a lower layer into a higher one: {len(f['upward_imports'])}")
    for a, b in f["upward_imports"]:
        print(f"  {a} -> {b}")
