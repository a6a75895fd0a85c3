"""Repository invariants: the generated schema is in sync, CI runs the README's test command."""

import json
import re

from geompm.schema.export import case_json_schema

from tests.support.cases import ROOT


def test_schema_file_matches_the_models():
    """schemas/case.schema.json must equal what `geompm schema` generates now (geompm's own plugins), whatever
    third-party plugins are installed (the mu_i plugin of plugins/ is, in the README's test command)."""
    on_disk = json.loads((ROOT / "schemas" / "case.schema.json").read_text())
    assert on_disk == case_json_schema(built_in_only=True), \
        "regenerate with: geompm schema -o schemas/case.schema.json"
    assert not [k for k in on_disk["$defs"] if k.startswith("material.mu_i")]
    assert set(on_disk["properties"]) >= {"name", "dimension", "grid", "time", "gravity", "solver", "materials",
                                          "bodies", "boundaries", "obstacles", "damping", "outputs"}


def test_ci_runs_the_readme_test_command_verbatim():
    readme = (ROOT / "README.md").read_text()
    commands = re.findall(r"```(?:bash|sh)\n(.*?)\n```", readme, flags=re.S)
    test_cmd = [c for c in commands if "pytest" in c]
    assert len(test_cmd) == 1, "the README must hold exactly one test command"
    assert test_cmd[0].strip() in (ROOT / ".ci" / "run").read_text()


def test_shipped_cases_validate():
    from geompm.schema import load_case

    for case in sorted((ROOT / "cases").glob("*.json")):
        loaded = load_case(case)
        assert loaded.case.name == case.stem


def test_a_clone_with_nothing_beside_it_collects_every_test(tmp_path):
    """The repository stands alone: a git clone of the committed tree, in a folder with nothing beside it,
    collects the same tests as this checkout's committed files, with no collection error (what the tests
    read is in the repository: tests/refdata with its README)."""
    import shutil
    import subprocess
    import sys

    import pytest

    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    clone = tmp_path / "alone" / "repo"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
    assert not (clone.parent / "shared").exists()

    def collect(where):
        out = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
                              "tests"], cwd=where, capture_output=True, text=True, timeout=600)
        ids = sorted(line for line in out.stdout.splitlines() if "::" in line)
        return out.returncode, ids, out.stdout[-2000:] + out.stderr[-2000:]

    code, ids, tail = collect(clone)
    assert code == 0, tail
    assert len(ids) > 500
    committed = subprocess.run(["git", "ls-files", "tests"], cwd=ROOT, capture_output=True, text=True).stdout.split()
    files = {i.split("::")[0] for i in ids}
    test_files = {f for f in committed if f.split("/")[-1].startswith("test_") and f.endswith(".py")}
    assert files == test_files
