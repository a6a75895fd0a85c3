"""Repository invariants: the generated schema is in sync, CI runs the README's test command."""

import json
import re

from geompm.schema.export import case_json_schema

from .conftest import ROOT


def test_schema_file_matches_the_models():
    """schemas/case.schema.json must equal what `geompm schema --built-in` generates now, whatever
    third-party plugins are installed (the mu_i plugin of plugins/ is, in the README's test command)."""
    on_disk = json.loads((ROOT / "schemas" / "case.schema.json").read_text())
    assert on_disk == case_json_schema(built_in_only=True), \
        "regenerate with: geompm schema --built-in -o schemas/case.schema.json"
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
