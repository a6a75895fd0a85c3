"""The documentation points only at files in the repository, and every file it names exists.

A clone with nothing beside it must be readable: every relative markdown link in README.md and docs/
resolves to a file or folder of the repository, every path written in backticks that starts with one of
the repository's top folders (``docs/``, ``tests/``, ``cases/``, ...) exists, and no page sends the reader
to the project's ``shared/`` folder outside the repository.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
TOP = ("docs", "tests", "cases", "benchmarks", "geompm", "schemas", "plugins", "examples")
#: folders a script fills and git ignores (named by the pages that tell how to fill them)
GENERATED = {"benchmarks/device/wheels"}
LINK = re.compile(r"\]\(([^)\s]+)\)")
TICKED = re.compile(r"`((?:%s)/[A-Za-z0-9_./-]+)`" % "|".join(TOP))


def _ids(pages):
    return [str(p.relative_to(ROOT)) for p in pages]


@pytest.mark.parametrize("page", PAGES, ids=_ids(PAGES))
def test_relative_links_resolve(page):
    """Each [text](target) that is not a URL or an anchor names an existing file, relative to the page."""
    missing = []
    for target in LINK.findall(page.read_text()):
        if re.match(r"^[a-z]+:", target) or target.startswith("#"):
            continue
        path = (page.parent / target.split("#")[0]).resolve()
        if not path.exists() or ROOT not in path.parents and path != ROOT:
            missing.append(target)
    assert not missing, f"{page.relative_to(ROOT)} links to {missing}"


@pytest.mark.parametrize("page", PAGES, ids=_ids(PAGES))
def test_named_repository_paths_exist(page):
    """A path in backticks such as `tests/refdata/x.csv` exists in the repository (globs and
    placeholders like <name> are skipped), and no page names the project's shared/ folder."""
    text = page.read_text()
    missing = [p for p in TICKED.findall(text)
               if not any(c in p for c in "*<>") and p.rstrip("/.") not in GENERATED
               and not (ROOT / p.rstrip("/.")).exists()]
    assert not missing, f"{page.relative_to(ROOT)} names missing paths {missing}"
    outside = re.findall(r"(?<![\w/])(?:\.\./)?shared/(?:design|refdata|hooks)\S*", text)
    assert not outside, f"{page.relative_to(ROOT)} points outside the repository: {outside}"


#: a path a comment or docstring names: folders, then a file with a known suffix (kernels/shape.py,
#: docs/pore-water.md, cases/dam_break.json)
CODE_PATH = re.compile(r"(?<![\w./$-])((?:[A-Za-z_][\w-]*/)+[\w-]+\.(?:py|md|json|csv|stl|sh|toml))\b")
#: a module or folder of the package named without its suffix (engine/scheduler, schemes/saturated)
PACKAGE_PATH = re.compile(r"(?<![\w./$-])((?:%s)/[a-z_]+)(?![\w/.-])" % "|".join(
    p.name for p in (ROOT / "geompm").iterdir() if p.is_dir() and p.name != "__pycache__"))
#: paths the sources write (a script's output folder, a test's own files), not references to the repository
WRITTEN = ("OUT/", "maps/", "runs/", "mypkg/", "record/", "meshes/m.stl", "meshes/none.stl", "meshes/x.stl",
           "benchmarks/x.py", "tests/refdata/x.csv")
SOURCES = sorted(p for top in ("geompm", "tests", "benchmarks", "plugins") for p in (ROOT / top).rglob("*.py")
                 if "__pycache__" not in p.parts)


def _comment_text(path: Path) -> str:
    """The comments and string literals of a Python file (docstrings among them)."""
    import io
    import tokenize

    parts = []
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if tok.type in (tokenize.COMMENT, tokenize.STRING):
            parts.append(tok.string)
    return "\n".join(parts)


def test_paths_named_in_code_comments_exist():
    """Every file path a comment or docstring of geompm, tests, benchmarks or plugins names (such as
    ``backend/cpu_loops.py`` or ``docs/pore-water.md``) exists: relative to the repository, to the package
    (``geompm/``), to the plugin's package or to the file's own folder; and every module or folder of the
    package named without its suffix (``engine/scheduler``) exists.  Paths with placeholders and paths a
    test or script writes (WRITTEN) are not references and are skipped."""
    bases = [ROOT, ROOT / "geompm", ROOT / "plugins" / "geompm-mu-i"]
    missing = []
    for src in SOURCES:
        text = _comment_text(src)
        for ref in set(CODE_PATH.findall(text)):
            if any(c in ref for c in "*<>{}") or ref.startswith(WRITTEN):
                continue
            if not any((b / ref).exists() for b in (*bases, src.parent)):
                missing.append(f"{src.relative_to(ROOT)}: {ref}")
        for ref in set(PACKAGE_PATH.findall(text)):
            here = ROOT / "geompm" / ref
            if not (here.is_dir() or here.with_suffix(".py").is_file()):
                missing.append(f"{src.relative_to(ROOT)}: {ref}")
    assert not missing, "paths named in comments that do not exist:\n" + "\n".join(sorted(missing))


@pytest.mark.parametrize("page", PAGES, ids=_ids(PAGES))
def test_paths_named_in_prose_exist(page):
    """A file path a page names outside backticks (``kernels/shape.py`` in a sentence) exists, relative to the
    repository or the package, and so does a module or folder of the package named without its suffix."""
    text = page.read_text()
    missing = [ref for ref in set(CODE_PATH.findall(text)) if not any(c in ref for c in "*<>{}")
               and not ref.startswith(WRITTEN)
               and not any((b / ref).exists() for b in (ROOT, ROOT / "geompm", page.parent))]
    missing += [ref for ref in set(PACKAGE_PATH.findall(text))
                if not ((ROOT / "geompm" / ref).is_dir() or (ROOT / "geompm" / ref).with_suffix(".py").is_file())]
    assert not missing, f"{page.relative_to(ROOT)} names missing paths {sorted(missing)}"
