"""Every command shown in README.md and docs/ works as written, so that an example cannot rot.

Commands are the lines of the ``console``/``bash``/``sh`` code blocks that start with ``geompm`` or
``python benchmarks/...`` (a trailing ``# comment`` and ``\\`` continuations are handled; the README's
install lines are tests/repository/test_repository.py's).  Each is checked as far as a CI budget allows:

- every ``geompm`` line is parsed by geompm's own argument parser (a removed or misspelt option fails);
- ``validate``, ``plugins`` and ``schema`` (into a temporary file) run to completion with exit 0;
- the README's ``run`` -> ``info`` -> ``plot`` sequence on the elastic bar runs for real (in a temporary
  folder, so ``runs/bar_fine`` lands there);
- ``run --resume``, ``study``, ``stability``, ``calibrate`` and ``cuda-check`` (minutes to hours) are not run; their case
  files are loaded with every ``--set``, each ``--vary`` value and each ``--sample`` path applied
  (geompm.schema.load_case: an example that varies a material the case does not have fails here, as
  the landslide's ``materials.soil`` did);
- ``bench`` scene names must be scenes of benchmarks/scenes.json; a ``python benchmarks/x.py`` script
  must exist.
"""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest

from geompm.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))


def doc_commands() -> list[tuple[str, str]]:
    """(file, command) for every geompm / benchmark-script line of the docs' shell code blocks."""
    out = []
    for f in DOCS:
        for block in re.findall(r"```(?:console|bash|sh|shell)\n(.*?)```", f.read_text(), re.S):
            joined = re.sub(r"\\\n\s*", " ", block)
            for line in joined.splitlines():
                line = line.strip().removeprefix("$ ").strip()
                if line.startswith("geompm ") or line.startswith("python benchmarks/"):
                    out.append((str(f.relative_to(ROOT)), line))
    return out


COMMANDS = doc_commands()


def _argv(line: str) -> list[str]:
    return shlex.split(line, comments=True)


def test_the_docs_show_commands():
    """The extraction finds the docs' examples (26 when this test was written): a regex that silently
    matched nothing would make every other test here vacuous."""
    assert len(COMMANDS) >= 20
    assert {c.split()[1] for _, c in COMMANDS if c.startswith("geompm")} >= {
        "validate", "run", "info", "plot", "study", "calibrate", "bench", "plugins", "cuda-check", "schema"}


@pytest.mark.parametrize("where, line", COMMANDS, ids=[f"{w}:{c[:50]}" for w, c in COMMANDS])
def test_command_parses_and_its_case_loads(where, line, monkeypatch):
    """Parsed by the real parser; a case-taking command's case loads with its --set / --vary / --sample."""
    monkeypatch.chdir(ROOT)
    argv = _argv(line)
    if argv[0] == "python":
        assert (ROOT / argv[1]).is_file(), f"{where}: {argv[1]} does not exist"
        return
    args = build_parser().parse_args(argv[1:])
    cmd = argv[1]
    if cmd == "bench":
        scenes = json.loads((ROOT / "benchmarks" / "scenes.json").read_text())
        assert all(s in scenes for s in (args.scene or [])), f"{where}: unknown scene in {args.scene}"
        return
    if cmd in ("run", "study", "stability", "cuda-check"):
        cases = [args.case]
    elif cmd == "calibrate":
        cases = list(args.soil_cases) + [args.fluid]
    else:
        return
    from geompm.schema import load_case

    sets = list(getattr(args, "set", None) or [])
    variants = [[]]
    if cmd == "study":
        from geompm.study.plan import build_plan, parse_sample, parse_vary

        plan = build_plan(parse_vary(args.vary or []), parse_sample(args.sample or []), 2, seed=1)
        variants = [v.sets for v in plan[:2]] or [[]]
    for case in cases:
        for extra in variants:
            load_case(ROOT / case, sets + list(extra))


def test_quick_commands_run(tmp_path, monkeypatch, capsys):
    """validate, plugins and schema run to exit 0 as the docs show them (schema into a temporary file, not
    over the committed one); then the README's run -> info -> plot sequence on the elastic bar runs in a
    temporary folder and info reports it finished."""
    quick = [_argv(c) for _, c in COMMANDS if c.split()[1] in ("validate", "plugins", "schema")]
    assert quick
    monkeypatch.chdir(ROOT)
    for argv in quick:
        if argv[1] == "schema":
            argv = ["geompm", "schema", "-o", str(tmp_path / "case.schema.json")]
        assert main(argv[1:]) == 0, " ".join(argv)
    seq = [_argv(c) for w, c in COMMANDS if w == "README.md" and "bar_fine" in c]
    assert [a[1] for a in seq] == ["run", "info", "plot"]
    monkeypatch.chdir(tmp_path)
    for argv in seq:
        argv = [str(ROOT / a) if a.startswith("cases/") else a for a in argv]
        if argv[1] == "run":
            argv.append("--quiet")
        assert main(argv[1:]) == 0, " ".join(argv)
    out = capsys.readouterr().out
    assert "status       finished" in out and (tmp_path / "runs" / "bar_fine" / "plots" / "series.png").is_file()
