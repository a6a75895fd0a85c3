"""Stages are read by declared capability, never by the case section or class they come from.

A test-only distribution registers ``piston`` in the ``geompm.boundaries`` group: a third-party moving
boundary (a rigid box driven at 0.5 m/s into a block, built on geompm's box obstacle) that declares
``records_force`` and ``supplies_energy``.  Nothing in geompm names it, yet:

- the health check's energy budget counts its supplied speed (E_v = 2 M v^2, engine/health.py);
- status.json, ``Run.peak_forces``, ``geompm info`` and the study metrics ``peak_force:piston`` and
  ``impulse:piston`` report its force;
- series.csv carries its force columns, and the peak force in status.json (taken every step) is at
  least the largest |F| of the rows (taken at output times).
"""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest

import geompm
from geompm.contract import registry

from tests.support.cases import tiny_case
from tests.support import fake_dist

SPEED = 0.5  # [m/s]


PISTON = textwrap.dedent("""\
    from geompm.obstacles.analytic import BoxObstacle

    class Piston(BoxObstacle):
        '''A rigid box pushed at a prescribed velocity (test plugin, a boundary).'''
        name = "piston"
        description = "test plugin: a moving rigid box, as a boundary"
        records_force = True
        supplies_energy = True
    """)


@pytest.fixture
def piston_plugin(tmp_path, monkeypatch):
    fake_dist.install(tmp_path, monkeypatch, "piston-plugin",
                      {"geompm.boundaries": {"piston": "piston_plugin:Piston"}}, {"piston_plugin": PISTON})
    yield
    registry.clear_cache()


def _case(speed):
    case = tiny_case()
    case["time"]["end"] = 0.05
    case["outputs"] = [{"writer": "series", "interval": 0.01}]
    case["boundaries"].append({"type": "piston", "name": "piston", "min": [0.0, 0.0], "max": [0.18, 0.6],
                               "velocity": [speed, 0.0], "condition": "slip"})
    return case


def test_a_third_party_moving_boundary_is_read_by_its_capabilities(piston_plugin, tmp_path, capsys):
    from geompm.api import scene_from_dict
    from geompm.cli import main
    from geompm.engine.health import HealthCheck
    from geompm.study.metrics import read_run, scalar_metrics

    moving, still = scene_from_dict(_case(SPEED)), scene_from_dict(_case(0.0))
    (piston,) = [s for s in moving.stages if s.label == "piston"]
    assert piston in moving.boundaries and piston.records_force and piston.supplies_energy
    mass = float(moving.state.p_mass.sum())
    assert HealthCheck(moving).budget0 - HealthCheck(still).budget0 == pytest.approx(2.0 * mass * SPEED ** 2)

    run = geompm.run(_case(SPEED), out=tmp_path / "run", quiet=True)
    assert run.exit_code == 0
    peak, when = run.peak_forces["piston"]
    series, status = read_run(run.folder)
    f_rows = np.hypot(series["piston_fx"], series["piston_fy"])
    assert peak > 0.0 and 0.0 < when <= 0.05 and peak >= f_rows.max() * (1 - 1e-12)
    metrics = scalar_metrics(series, status)
    assert metrics["peak_force:piston"] == peak
    # the impulse is summed over every step by the stage (contact/impact.py), not over the series rows
    entry = status["obstacles"]["piston"]
    assert metrics["impulse:piston"] == entry["impulse"] >= np.linalg.norm(entry["impulse_vector"]) > 0.0
    capsys.readouterr()
    assert main(["info", str(run.folder)]) == 0
    assert "piston" in capsys.readouterr().out
    assert json.loads((run.folder / "status.json").read_text())["obstacles"]["piston"]["peak_force"] == peak
