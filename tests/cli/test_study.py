"""geompm study: variant plans, metrics, convergence orders, and the command end to end on Dask."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from geompm.cli import main
from geompm.study import metrics as M
from geompm.study.plan import build_plan, parse_sample, parse_vary
from geompm.study.report import pareto

from tests.support.cases import CASES


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_plan_is_the_product_of_varied_values_times_draws():
    """--vary lists combine as a Cartesian product; each --sample draw multiplies it (2 x 3 x 4 = 24 variants)."""
    vary = parse_vary(["grid.cell_size=0.02,0.01", "solver.transfer=apic,flip,pic"])
    plan = build_plan(vary, parse_sample(["materials.soil.friction_angle=uniform(28,34)"]), 4, seed=3)
    assert len(plan) == 24
    assert plan[0].values["grid.cell_size"] == 0.02 and plan[0].values["solver.transfer"] == "apic"
    assert {v.values["solver.transfer"] for v in plan} == {"apic", "flip", "pic"}
    assert all(28 <= v.values["materials.soil.friction_angle"] <= 34 for v in plan)
    assert plan[5].sets[0] == "grid.cell_size=0.02"


def test_sampled_values_follow_the_distribution_and_the_seed():
    """normal(31, 2) with 4000 draws: sample mean within 0.1 deg of 31 and sd within 0.1 of 2 (standard
    errors 0.03 and 0.02); the same seed gives the same draws, another seed different ones."""
    spec = parse_sample(["materials.soil.friction_angle=normal(31,2)"])
    x = np.array([v.values["materials.soil.friction_angle"] for v in build_plan({}, spec, 4000, seed=1)])
    assert abs(x.mean() - 31) < 0.1 and abs(x.std() - 2) < 0.1
    again = [v.values["materials.soil.friction_angle"] for v in build_plan({}, spec, 5, seed=1)]
    other = [v.values["materials.soil.friction_angle"] for v in build_plan({}, spec, 5, seed=2)]
    assert again == list(x[:5]) and again != other


def test_richardson_order_recovers_a_known_order():
    """Celik et al. (2008) J. Fluids Eng. 130:078001: f = 1 + 0.5 h^2 gives p = 2 with ratio 2, and
    f = 2 + h^1.5 gives p = 1.5 with the non-constant ratios 1.5 and 1.6 (iterated eq. 4)."""
    assert M.richardson_order([0.04, 0.02, 0.01], [1 + 0.5 * h ** 2 for h in (0.04, 0.02, 0.01)]) == \
        pytest.approx(2.0, abs=1e-9)
    hs = [0.032, 0.02, 0.0125]
    assert M.richardson_order(hs, [2 + h ** 1.5 for h in hs]) == pytest.approx(1.5, abs=1e-6)
    assert math.isnan(M.richardson_order([0.04, 0.02, 0.01], [1.0, 1.1, 1.05]))  # oscillating: no order
    assert M.fitted_order([0.04, 0.02], [3e-3 * 16, 3e-3 * 4]) == pytest.approx(2.0)


def test_series_error_and_obstacle_metrics():
    """Relative L2 error of a run 10% above the reference is 0.10 whatever its sampling; the impulse of a
    triangular force pulse (peak 6 N, base 0.5 s) is 1.5 N s and its peak 6 N."""
    t_ref = np.linspace(0, 1, 101)
    ref = {"time": t_ref, "front_x": 1 + t_ref ** 2}
    t = np.linspace(0, 1, 1001)
    run = {"time": t, "front_x": 1.1 * (1 + t ** 2)}
    assert M.series_error(run, ref, "front_x") == pytest.approx(0.1, rel=1e-4)
    f = np.interp(t, [0, 0.25, 0.5, 1], [0, 6, 0, 0])
    series = {"time": t, "front_x": t, "wall_fx": 0.6 * f, "wall_fy": -0.8 * f}
    out = M.scalar_metrics(series)
    assert out["peak_force:wall"] == pytest.approx(6.0)
    assert out["impulse:wall"] == pytest.approx(1.5, rel=1e-6)
    assert out["runout"] == 1.0
    assert pareto([(1, 0.5), (2, 0.6), (3, 0.1), (0.5, 0.9)]) == [3, 0, 2]


def test_one_obstacles_metric_is_reported_with_its_error():
    """`--metric peak_force:dam` (the documented per-obstacle form) gives that scalar, so study.csv carries its
    error and the summary its order; before, only the bare `peak_force` did, and the labelled form was
    dropped without a word (found measuring the check dam for issue 15)."""
    from geompm.study.command import _metric_names

    series = [{"time": np.zeros(2), "dam_fx": np.zeros(2), "dam_fy": np.zeros(2), "dam_fz": np.zeros(2)}]
    assert _metric_names(["runout", "peak_force:dam", "impulse:dam"], series)[0] == [
        "runout", "peak_force:dam", "impulse:dam"]
    assert _metric_names(["peak_force"], series)[0] == ["peak_force:dam"]
    assert _metric_names(["peak_force:wall"], series)[0] == []


def _study(tmp_path, *extra, name="st"):
    out = tmp_path / name
    code = main(["study", str(CASES / "column_collapse.json"), "--out", str(out), "--quiet",
                 "--set", "time.end=0.4", *extra])
    return code, out


@pytest.mark.slow
def test_refinement_study_end_to_end_and_resume(tmp_path, capsys):
    """Column collapse at h = 0.04, 0.02, 0.01 m on a Dask LocalCluster: three finished run folders, the
    finest is the reference (errors 0), the runout error falls with h, particle-steps/s is particles x
    steps / wall, an observed order is printed, study.png is a PNG.  --resume reruns nothing; a run folder
    as --reference gives the same errors as 'finest'."""
    code, out = _study(tmp_path, "--vary", "grid.cell_size=0.04,0.02,0.01")
    assert code == 0
    rows = _rows(out / "study.csv")
    assert [r["status"] for r in rows] == ["finished"] * 3
    assert [int(r["particles"]) for r in rows] == [50, 200, 800]
    err = [float(r["runout_error"]) for r in rows]
    assert err[2] == 0.0 and err[0] > err[1] > 0.01
    assert float(rows[2]["front_x_l2_error"]) == 0.0 and float(rows[0]["kinetic_energy_l2_error"]) > 0.05
    for r in rows:
        rate = int(r["particles"]) * int(r["steps"]) / float(r["wall_seconds"])
        assert float(r["particle_steps_per_second"]) == pytest.approx(rate, rel=1e-6)
        assert float(r["peak_memory_mib"]) > 20
    summary = json.loads((out / "study_summary.json").read_text())
    assert summary["reference"] == "v002" and summary["orders"][0]["cell_sizes"] == [0.01, 0.02, 0.04]
    assert "observed order of convergence" in capsys.readouterr().out
    assert (out / "study.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    stamp = (out / "runs" / "v001" / "status.json").stat().st_mtime_ns
    code, _ = _study(tmp_path, "--vary", "grid.cell_size=0.04,0.02,0.01", "--resume",
                     "--reference", str(out / "runs" / "v002"))
    assert code == 0 and "3 of 3 variants already finished" in capsys.readouterr().out
    assert (out / "runs" / "v001" / "status.json").stat().st_mtime_ns == stamp
    again = _rows(out / "study.csv")
    assert [float(r["runout_error"]) for r in again] == pytest.approx(err, abs=1e-12)


def test_failed_variant_is_reported_and_retried_with_resume(tmp_path, capsys):
    """A variant at a fixed dt 5x the Courant limit (h / c_p = 0.04 / 20.6 = 1.9 ms) blows up: it is
    reported as failed (exit 3) in study.csv while the stable one finishes; --resume then runs only the
    failed variant again.  An invalid variant (output interval below its fixed dt) is refused first."""
    code, _ = _study(tmp_path, "--vary", "time.dt=0.0005,0.01", "--set", "grid.cell_size=0.04",
                     "--set", "time.end=0.1", name="refused")
    assert code == 2 and "variant v001" in capsys.readouterr().err and not (tmp_path / "refused").exists()
    args = ("--vary", "time.dt=0.0005,0.01", "--set", "grid.cell_size=0.04", "--set", "time.end=0.1",
            "--set", "outputs.0.interval=0.01")
    code, out = _study(tmp_path, *args)
    assert code == 3
    rows = _rows(out / "study.csv")
    assert rows[0]["status"] == "finished"
    assert rows[1]["status"].startswith("failed (exit 3)") and rows[1]["runout"] == ""
    capsys.readouterr()
    code, _ = _study(tmp_path, *args, "--resume")
    assert code == 3 and "1 of 2 variants already finished" in capsys.readouterr().out


@pytest.mark.slow
def test_monte_carlo_friction_angle_gives_runout_distribution(tmp_path):
    """Four draws of phi ~ uniform(24, 40) deg at h = 0.02 m: study_summary.json gives n = 4 and the mean
    and quantiles of the runout; the steepest friction angle gives a shorter runout than the lowest
    (Lube et al. 2005: runout falls as friction rises)."""
    code, out = _study(tmp_path, "--sample", "materials.soil.friction_angle=uniform(24,40)", "--samples", "4",
                       "--seed", "1", "--set", "grid.cell_size=0.02")
    assert code == 0
    rows = _rows(out / "study.csv")
    phi = np.array([float(r["materials.soil.friction_angle"]) for r in rows])
    runout = np.array([float(r["runout"]) for r in rows])
    assert runout[phi.argmax()] < runout[phi.argmin()]
    dist = json.loads((out / "study_summary.json").read_text())["distribution"]["runout"]
    assert dist["n"] == 4 and dist["mean"] == pytest.approx(runout.mean())
    assert dist["p05"] <= dist["p50"] <= dist["p95"]
    assert "runout_error" not in rows[0]  # no reference in a sampled study


@pytest.mark.parametrize("args, needle", [
    (["--vary", "grid.cell_sise=0.02,0.01"], "grid.cell_sise"),
    (["--vary", "grid.cell_size=0.02,-1"], "variant v001"),
    (["--sample", "materials.soil.friction_angle=gauss(31,2)"], "distributions: normal"),
    (["--sample", "materials.soil.friction_angle=normal(31)"], "normal takes 2 numbers"),
    (["--vary", "grid.cell_size"], "dotted.key=v1,v2"),
    (["--reference", "/nonexistent/run"], "--reference"),
    (["--set", "outputs=abc", "--vary", "grid.cell_size=0.04,0.02"], "outputs: must be a list"),
])
def test_bad_study_arguments_are_refused_before_any_run(tmp_path, capsys, args, needle):
    """Bad --vary/--sample/--reference: exit 2 naming the problem, and no study folder is made."""
    out = tmp_path / "refused"
    code = main(["study", str(CASES / "column_collapse.json"), "--out", str(out), *args])
    assert code == 2
    assert needle in capsys.readouterr().err
    assert not out.exists()


def test_study_runs_on_an_existing_dask_scheduler(tmp_path):
    """--scheduler tcp://HOST:PORT sends the variants to a cluster started elsewhere (here a separate
    LocalCluster with 2 worker threads): both variants finish there and h = 0.04 m has 50 particles."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, protocol="tcp",
                      dashboard_address=":0") as cluster:
        assert cluster.scheduler_address.startswith("tcp://")
        code, out = _study(tmp_path, "--vary", "grid.cell_size=0.04,0.02", "--set", "time.end=0.1",
                           "--scheduler", cluster.scheduler_address)
    assert code == 0
    rows = _rows(out / "study.csv")
    assert [r["status"] for r in rows] == ["finished", "finished"]
    assert [int(r["particles"]) for r in rows] == [50, 200]


def test_threads_follow_the_option_then_numba_num_threads(tmp_path, monkeypatch):
    """Each variant's status.json records the numba threads it ran with: --threads 1 gives 1 even on a
    2-core machine where the default would share 2 cores among fewer runs; an exported NUMBA_NUM_THREADS=1
    is honoured the same way (numba's meaning: threads per process), and --threads 0 is refused (exit 2).
    Two workers of one 2-thread run each would oversubscribe the cores (a variant took 135 s against 12 s
    alone in a user's trial)."""
    from geompm.study.execute import threads_per_run

    args = ("--vary", "grid.cell_size=0.04", "--set", "time.end=0.02", "--workers", "1")
    code, out = _study(tmp_path, *args, "--threads", "1", name="opt")
    assert code == 0
    assert json.loads((out / "runs" / "v000" / "status.json").read_text())["threads"] == 1
    assert main(["study", str(CASES / "column_collapse.json"), "--out", str(tmp_path / "bad"), "--threads",
                 "0", "--vary", "grid.cell_size=0.04"]) == 2
    monkeypatch.setenv("NUMBA_NUM_THREADS", "1")
    assert threads_per_run(1, 1) == 1 and threads_per_run(1, 1, 3) == 3
    monkeypatch.delenv("NUMBA_NUM_THREADS")
    import os

    assert threads_per_run(1, 1) == (os.cpu_count() or 1)
    assert threads_per_run(os.cpu_count() or 1, 8) == 1


def test_map_coordinates_are_printed_in_full():
    """A runout given as an easting (612 345.67 m) prints to the centimetre, not as 6.123e+05; a small
    value keeps its significant digits."""
    from geompm.study.command import shown

    assert shown(612345.6789) == "612345.68" and shown(2.34567) == "2.346" and shown(-1.2e6) == "-1200000.00"
