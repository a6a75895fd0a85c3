"""Case settings that would silently do nothing, and stage labels that would collide (issue 17, point 5).

Two stages with one label write the same series.csv columns and checkpoint state: refused, naming
the second one's JSON path.  A setting that has no effect in its context is warned about, naming
its path, by `geompm validate` (and `geompm run`): flip_ratio without FLIP, cfl with a fixed dt, a
2D polygon's extrude, a 2D cylinder's axis/length,
and the CUDA backend's P2G choice on the CPU.
"""

import json

import pytest

from geompm.cli import main
from geompm.errors import CaseError
from geompm.schema import parse_case

from tests.support.cases import tiny_case

OBSTACLE = {"type": "box", "name": "dam", "min": [0.7, 0.0], "max": [0.8, 0.3]}


def test_two_stages_with_one_label_are_refused():
    case = tiny_case(obstacles=[OBSTACLE, {**OBSTACLE, "min": [0.85, 0.0], "max": [0.9, 0.3]}])
    with pytest.raises(CaseError) as err:
        parse_case(case)
    (path, msg), = err.value.problems
    assert path == "obstacles.1.name" and "'dam' is already used by obstacles.0" in msg
    parse_case(tiny_case(obstacles=[OBSTACLE, {**OBSTACLE, "name": "dam2", "min": [0.85, 0.0],
                                                "max": [0.9, 0.3]}]))


def _flip_ratio(c):
    c["solver"]["flip_ratio"] = 0.95


def _cfl_with_dt(c):
    c["time"]["dt"] = 1e-4


def _extrude_2d(c):
    c["bodies"][0]["geometry"] = {"type": "polygon", "vertices": [[0.2, 0.0], [0.6, 0.0], [0.2, 0.4]],
                                  "extrude": [0.0, 1.0]}


def _cylinder_axis_2d(c):
    c["obstacles"] = [{"type": "cylinder", "center": [0.8, 0.1], "radius": 0.05, "axis": "x"}]


def _tiled_p2g_on_cpu(c):
    c["solver"]["p2g"] = "tiled"


def _particle_pass_on_cpu(c):
    c["solver"]["particle_pass"] = "separate"


@pytest.mark.parametrize("mutate,path", [
    (_flip_ratio, "solver.flip_ratio"),
    (_tiled_p2g_on_cpu, "solver.p2g"),
    (_particle_pass_on_cpu, "solver.particle_pass"),
    (_cfl_with_dt, "time.cfl"),
    (_extrude_2d, "bodies.0.geometry.extrude"),
    (_cylinder_axis_2d, "obstacles.0.axis"),
])
def test_a_setting_that_does_nothing_is_warned_with_its_path(tmp_path, capsys, mutate, path):
    case = tiny_case()
    mutate(case)
    f = tmp_path / "case.json"
    f.write_text(json.dumps(case))
    assert main(["validate", str(f)]) == 0
    out = capsys.readouterr().out
    warned = [line for line in out.splitlines() if line.startswith("warning:") and path in line]
    assert len(warned) == 1 and ("no effect" in warned[0] or "applies to" in warned[0]), out


def test_the_valid_tiny_case_has_no_such_warning(tmp_path, capsys):
    f = tmp_path / "case.json"
    f.write_text(json.dumps(tiny_case()))
    assert main(["validate", str(f)]) == 0
    assert "warning:" not in capsys.readouterr().out
