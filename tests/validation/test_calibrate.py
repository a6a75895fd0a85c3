"""geompm calibrate: the source study's DP-Cross calibration (section 3.2), its search and its fit."""

from __future__ import annotations

import csv
import json
import math

import pytest

from geompm.cli import main
from geompm.study.calibrate import SOURCE_MU_INF, bracket, linear_fit, next_points

from tests.support.cases import CASES

SEED = CASES / "seed"


def test_linear_fit_of_the_source_values():
    """The source's mu_inf = 1.9, 1.2, 0.8, 0.6 Pa s at h = 0.02 ... 0.0025 m are linear in h with
    R^2 > 0.99 (source, section 3.2): least squares gives 0.4304 + 74.09 h, R^2 = 0.9988."""
    hs = sorted(SOURCE_MU_INF)
    a, b, r2 = linear_fit(hs, [SOURCE_MU_INF[h] for h in hs])
    assert a == pytest.approx(0.43043, rel=1e-4) and b == pytest.approx(74.087, rel=1e-4)
    assert 0.99 < r2 == pytest.approx(0.998767, abs=1e-6)


def test_search_narrows_to_the_neighbours_of_the_best_value():
    """Round 1 is log-spaced over the bounds; round 2 puts its points strictly between the best value's
    neighbours, so the bracket shrinks by (n + 1) / 2 in log each round."""
    first = next_points({}, 0.05, 0.8, 4)
    assert first == pytest.approx([0.05, 0.12599, 0.31748, 0.8], rel=1e-4)
    tried = dict(zip(first, [1.0, 0.5, 0.8, 2.0]))
    second = next_points(tried, 0.05, 0.8, 4)
    assert all(0.05 < x < 0.31748 for x in second) and len(second) == 4
    assert math.log(second[1] / second[0]) == pytest.approx(math.log(0.31748 / 0.05) / 5, rel=1e-6)
    assert bracket(tried) == (first[1], first[0], first[2])


@pytest.mark.slow
def test_calibrated_mu_inf_decreases_with_cell_size(tmp_path, capsys):
    """The source (section 3.2) finds the Cross mu_inf matching DP falls as the grid is refined
    (1.9 Pa s at h = 0.02 m, 1.2 at 0.01 m).  Calibrating the seed column at those two cell sizes
    (kept short: 0.4 s, i.e. T* = 4, when DP has come to rest; 4 points x 2 rounds on Dask) must
    give a smaller mu_inf at h = 0.01 than at 0.02, each with a finite misfit J below 1."""
    out = tmp_path / "cal"
    code = main(["calibrate", str(SEED / "dp_h0.02.json"), str(SEED / "dp_h0.01.json"),
                 "--fluid", str(SEED / "cross.json"), "--bounds", "0.05", "0.8", "--points", "4", "--rounds", "2",
                 "--set", "time.end=0.4", "--out", str(out), "--quiet"])
    assert code == 0
    with open(out / "calibration.csv", newline="") as fh:
        rows = {float(r["cell_size"]): r for r in csv.DictReader(fh)}
    mu02, mu01 = float(rows[0.02]["value"]), float(rows[0.01]["value"])
    assert mu01 < mu02
    for r in rows.values():
        assert float(r["bracket_low"]) <= float(r["value"]) <= float(r["bracket_high"])
        assert 0 < float(r["objective"]) < 1.0 and int(r["evaluations"]) == 8
    assert (out / "calibration.png").read_bytes()[:4] == b"\x89PNG"
    summary = json.loads((out / "calibration.json").read_text())
    assert summary["fit"] is None  # two cell sizes: no fit is claimed
    assert "h = 0.01 m: viscosity =" in capsys.readouterr().out


def test_calibrate_refuses_a_soil_case_without_normalised_series(tmp_path, capsys):
    """X* and K* need the series writer's normalise block: a case without it is refused (exit 2) before
    any run, naming the case and its outputs key."""
    code = main(["calibrate", str(CASES / "column_collapse.json"), "--fluid", str(SEED / "cross.json"),
                 "--out", str(tmp_path / "c")])
    assert code == 2
    assert "column_collapse.json: outputs" in capsys.readouterr().err
    assert not (tmp_path / "c").exists()
