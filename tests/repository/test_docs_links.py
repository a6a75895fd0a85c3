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
               if not any(c in p for c in "*<>") and p.rstrip("/.") not in GENERATED and not (ROOT / p.rstrip("/.")).exists()]
    assert not missing, f"{page.relative_to(ROOT)} names missing paths {missing}"
    outside = re.findall(r"(?<![\w/])(?:\.\./)?shared/(?:design|refdata|hooks)\S*", text)
    assert not outside, f"{page.relative_to(ROOT)} points outside the repository: {outside}"
