"""The writer of docs/how-to/write-an-output-writer.md, run exactly as the page prints it.

The page's python block is saved as a module of a test-only distribution that registers it in the
``geompm.writers`` group (what ``pip install`` of a plugin package makes).  A block in free fall (no floor,
no initial stress) has one velocity, g t downward, at every particle; the writer's rows must give
peak_speed = g t at each output time (to 1e-9 relative: only round-off), the particle count above its
threshold, and ``geompm.run`` must list its file.  A negative threshold is refused with its JSON path.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import geompm
from geompm.contract import registry
from geompm.errors import CaseError

from tests.support.cases import tiny_case
from tests.support import fake_dist

PAGE = Path(__file__).resolve().parents[2] / "docs" / "how-to" / "write-an-output-writer.md"
G = 9.81


@pytest.fixture
def peak_speed_plugin(tmp_path, monkeypatch):
    code = re.findall(r"```python\n(.*?)```", PAGE.read_text(), flags=re.S)[0]
    fake_dist.install(tmp_path, monkeypatch, "peak-speed-plugin",
                      {"geompm.writers": {"peak_speed": "peak_speed_plugin:PeakSpeedWriter"}},
                      {"peak_speed_plugin": code})
    yield
    registry.clear_cache()


def _free_fall(threshold):
    case = tiny_case()
    case["bodies"][0]["geometry"] = {"type": "box", "min": [0.3, 0.5], "max": [0.6, 0.8]}
    case["boundaries"] = []
    case["time"]["end"] = 0.04
    case["outputs"] = [{"writer": "series", "interval": 0.01},
                       {"writer": "peak_speed", "interval": 0.01, "threshold": threshold}]
    return case


def test_the_pages_writer_records_a_free_fall(peak_speed_plugin, tmp_path):
    run = geompm.run(_free_fall(0.2), out=tmp_path / "run", quiet=True)
    assert run.exit_code == 0
    assert run.outputs["peak_speed"] == [tmp_path / "run" / "peak_speed.csv"]
    lines = run.outputs["peak_speed"][0].read_text().splitlines()
    assert lines[0] == "time,peak_speed,at_x,at_y,n_fast"
    rows = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    np.testing.assert_allclose(rows[:, 0], [0.0, 0.01, 0.02, 0.03, 0.04], atol=1e-12)
    np.testing.assert_allclose(rows[:, 1], G * rows[:, 0], rtol=1e-9, atol=1e-12)
    n = int(run.status["particles"])
    np.testing.assert_array_equal(rows[:, 4], np.where(G * rows[:, 0] > 0.2, n, 0))


def test_the_pages_writer_refuses_a_negative_threshold(peak_speed_plugin, tmp_path):
    with pytest.raises(CaseError) as info:
        geompm.run(_free_fall(-1.0), out=tmp_path / "run", quiet=True)
    assert any(path == "outputs.1.threshold" for path, _ in info.value.problems)
    assert not (tmp_path / "run").exists()
