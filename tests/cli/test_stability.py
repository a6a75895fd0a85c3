"""geompm stability end to end on a small infinite slope: the JSON it prints, the files it writes, what
`geompm info` says of the folder, a slope that fails as it stands, and the refusals.

The slope (geompm/testing/verification/slopes.py) is cohesionless with phi = 30 deg on beta = 20 deg, associated, so its
limit-equilibrium factor of safety is tan(phi) / tan(beta) = 1.586 (Taylor 1948); at h = 0.2 m and a
tolerance of 0.1 the search must bracket it within that tolerance plus the coarse grid's few per cent."""

from __future__ import annotations

import json

import pytest

from geompm.cli import main
from geompm.testing.verification.slopes import infinite_slope_case, limit_equilibrium

pytestmark = pytest.mark.slow


def _case(tmp_path, **kw):
    path = tmp_path / "slope.json"
    path.write_text(json.dumps(infinite_slope_case(0.2, end=1.0, **kw)))
    return path


def test_stability_json_files_and_info(tmp_path, capsys):
    case = _case(tmp_path)
    out = tmp_path / "stab"
    assert main(["stability", str(case), "--out", str(out), "--json", "--tolerance", "0.1", "--workers", "2",
                 "--threads", "1"]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    lo, hi = summary["bracket"]
    assert hi - lo <= 0.1 + 1e-9 and summary["factor_of_safety"] == pytest.approx(0.5 * (lo + hi))
    assert summary["factor_of_safety"] == pytest.approx(limit_equilibrium(20.0, 30.0, 0.0), rel=0.06)
    trials = summary["trials"]
    assert len(trials) >= 4 and all({"factor", "failed", "ratio", "last_increment", "run_dir"} <= set(t) for t in trials)
    assert [t["factor"] for t in trials] == sorted(t["factor"] for t in trials)
    assert any(t["factor"] == hi and t["failed"] for t in trials) and any(t["factor"] == lo and not t["failed"]
                                                                          for t in trials)
    assert (out / "mechanism.vtu").stat().st_size > 1000 and (out / "mechanism.png").stat().st_size > 1000
    assert json.loads((out / "stability.json").read_text())["bracket"] == [lo, hi]
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"F = {summary['factor_of_safety']:.3f}" in text and f"{len(trials)}" in text


def test_a_slope_failing_as_it_stands_is_reported_not_refused(tmp_path, capsys):
    """phi = 15 deg on beta = 20 deg: F = tan 15 / tan 20 = 0.736 < 1, reported with its bracket."""
    case = _case(tmp_path, friction=15.0, dilation=15.0)
    assert main(["stability", str(case), "--out", str(tmp_path / "s"), "--json", "--tolerance", "0.1",
                 "--workers", "2", "--threads", "1"]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary["bracket"][1] < 1.0
    assert summary["factor_of_safety"] == pytest.approx(limit_equilibrium(20.0, 15.0, 0.0), rel=0.08)


def test_slip_surface_of_a_cohesive_slope_lies_at_its_base(tmp_path, capsys):
    """c = 2 kPa: the infinite slope's strength over its stress is least at the base (Taylor 1948: the
    cohesion's share falls with depth), so the failed trial's band of largest plastic strain rate, written as
    slip_surface.csv, lies within a cell of the base (h = 0.2 m) along the whole strip; the mechanism figure is
    drawn with a given circle; stability.json records the trials' viscoplastic time (T/800) and the circle."""
    case = _case(tmp_path, cohesion=2000.0)
    out = tmp_path / "stab"
    assert main(["stability", str(case), "--out", str(out), "--json", "--tolerance", "0.1", "--workers", "2",
                 "--threads", "1", "--bishop-circle", "0.8", "30.0", "29.5"]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert "slip_surface.csv" in summary["mechanism"]
    rows = (out / "slip_surface.csv").read_text().splitlines()
    assert rows[0] == "x_m,y_m"
    pts = [tuple(map(float, r.split(","))) for r in rows[1:]]
    assert len(pts) >= 6  # eight cells along the strip
    assert all(0.0 <= y <= 0.2 for _, y in pts), pts
    saved = json.loads((out / "stability.json").read_text())
    assert saved["criterion"]["viscoplastic_time_s"] == pytest.approx(1.0 / 800.0)
    assert saved["bishop_circle"] == [0.8, 30.0, 29.5]
    assert (out / "mechanism.png").stat().st_size > 1000


@pytest.mark.parametrize("args, path", [(["--tolerance", "0"], "--tolerance"), (["--local-damping", "1.0"], "--local-damping"),
                                        (["--ratio", "-1"], "--ratio"), (["--duration", "0"], "--duration"),
                                        (["--damping-rate", "0"], "--damping-rate"),
                                        (["--viscoplastic-time", "-1"], "--viscoplastic-time"),
                                        (["--bishop-circle", "1", "1", "0"], "--bishop-circle")])
def test_bad_options_are_refused_before_any_trial(tmp_path, capsys, args, path):
    case = _case(tmp_path)
    assert main(["stability", str(case), "--out", str(tmp_path / "s"), *args]) == 2
    assert f"  {path}:" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


def test_a_case_without_soil_is_refused(tmp_path, capsys):
    raw = infinite_slope_case(0.2)
    raw["materials"]["soil"] = {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1e6,
                                "poisson_ratio": 0.3}
    case = tmp_path / "elastic.json"
    case.write_text(json.dumps(raw))
    assert main(["stability", str(case), "--out", str(tmp_path / "s")]) == 2
    err = capsys.readouterr().err
    assert "  materials:" in err and "linear_elastic" in err
    assert not (tmp_path / "s").exists()
