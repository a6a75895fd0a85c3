"""geompm.run, the library call that runs a case as `geompm run` does, and geompm.stability (docs/python-api.md).

The page's examples are run as written (from the repository root, coarsened only by their own overrides),
and what the Run reports is checked against the files the run wrote: its step count and time against
status.json, its series against series.csv, each writer's outputs against the writer's declared patterns,
the obstacle's peak force against status.json.  A bad case raises CaseError before any folder exists.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

import geompm
from geompm.errors import CaseError

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "python-api.md"


def _examples() -> list[str]:
    return re.findall(r"```python\n(.*?)```", PAGE.read_text(), flags=re.S)


@pytest.fixture
def in_tmp_copy(tmp_path, monkeypatch):
    """The repository's cases/ visible from a scratch folder, so the examples' relative paths work and
    their runs/ lands in tmp_path."""
    os.symlink(ROOT / "cases", tmp_path / "cases")
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.slow
def test_the_pages_examples_run_as_written(in_tmp_copy, capsys):
    """Each python block of docs/python-api.md runs without an error, in order, in one namespace."""
    namespace: dict = {}
    blocks = _examples()
    assert len(blocks) == 4
    for code in blocks:
        exec(compile(code, str(PAGE), "exec"), namespace)
    run = namespace["run"]
    assert run.exit_code == 0 and run.finished
    assert (in_tmp_copy / "runs" / "debris_coarse" / "status.json").is_file()
    out = capsys.readouterr().out
    assert "dam" in out and "particles.pvd" in out
    result = namespace["result"]  # geompm.stability: a bracket no wider than its tolerance, its trials
    lo, hi = result["bracket"]
    assert hi - lo <= 0.1 + 1e-9 and result["message"] == "" and len(result["trials"]) >= 3


def test_run_reports_what_the_folder_holds(tmp_path):
    """A short 2D run: Run's steps, time, series, outputs and peak forces equal what status.json,
    series.csv and the writers' files say."""
    from tests.support.cases import tiny_case

    case = tiny_case()
    case["time"]["end"] = 0.02
    case["outputs"] = [{"writer": "series", "interval": 0.005}, {"writer": "vtu", "interval": 0.01}]
    case["obstacles"] = [{"type": "box", "name": "block", "min": [0.6, 0.0], "max": [0.8, 0.3]}]
    run = geompm.run(case, out=tmp_path / "run", quiet=True)
    status = json.loads((tmp_path / "run" / "status.json").read_text())
    assert run.exit_code == 0 and run.finished
    assert run.steps == status["steps"] > 0 and run.time == pytest.approx(0.02)
    rows = (tmp_path / "run" / "series.csv").read_text().splitlines()
    assert len(run.series["time"]) == len(rows) - 1 == 5  # t = 0, 0.005, ..., 0.02
    np.testing.assert_allclose(run.series["time"], [0.0, 0.005, 0.01, 0.015, 0.02], atol=1e-12)
    assert [p.name for p in run.outputs["vtu"]] == ["particles.pvd", "particles_000000.vtu",
                                                   "particles_000001.vtu", "particles_000002.vtu"]
    assert run.outputs["series"] == [tmp_path / "run" / "series.csv"]
    assert run.peak_forces == {k: (v["peak_force"], v["peak_time"]) for k, v in status["obstacles"].items()}
    assert set(run.peak_forces) == {"block"}


def test_a_bad_case_raises_before_any_folder(tmp_path):
    """A case with a negative density raises CaseError naming materials.<name>.density; nothing is made."""
    from tests.support.cases import tiny_case

    case = tiny_case()
    name = next(iter(case["materials"]))
    case["materials"][name]["density"] = -1.0
    with pytest.raises(CaseError) as info:
        geompm.run(case, out=tmp_path / "run", quiet=True)
    assert any(path == f"materials.{name}.density" for path, _ in info.value.problems)
    assert not (tmp_path / "run").exists()
