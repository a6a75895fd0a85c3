"""A barrier's design numbers reach the user: status.json, `geompm info`, `geompm plot`, `geompm study
--metric impact`, and bad probe input is refused with its JSON path before any work."""

from __future__ import annotations

import json

import pytest

from geompm.cli import main
from geompm.errors import CaseError
from geompm.schema.load import parse_case
from geompm.study.command import _metric_names, validate_all
from geompm.study.plan import build_plan, parse_vary

from tests.support.cases import CASES


def _surge(**over):
    """A 0.4 x 0.1 m elastic block sliding at 3 m/s on a slip floor into a 0.3 m wall; a probe 0.15 m upstream."""
    case = {
        "name": "surge", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.6, 0.6], "cell_size": 0.05},
        "time": {"end": 0.3, "cfl": 0.4}, "gravity": [0.0, -9.81],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"debris": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 2e6,
                                 "poisson_ratio": 0.3}},
        "bodies": [{"material": "debris", "geometry": {"type": "box", "min": [0.2, 0.0], "max": [0.6, 0.1]},
                    "velocity": [3.0, 0.0], "particles_per_cell": 2}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"}],
        "obstacles": [{"type": "box", "name": "wall", "min": [1.0, 0.0], "max": [1.1, 0.3], "condition": "slip",
                       "probe": "gauge"}],
        "probes": [{"name": "gauge", "point": [0.85, 0.0], "half_width": 0.05}],
        "outputs": [{"writer": "series", "interval": 0.005}, {"writer": "surfaces", "interval": 0.1}],
    }
    case.update(over)
    return case


@pytest.fixture(scope="module")
def surge_run(tmp_path_factory):
    d = tmp_path_factory.mktemp("surge")
    (d / "surge.json").write_text(json.dumps(_surge()))
    assert main(["run", str(d / "surge.json"), "--out", str(d / "run"), "--quiet"]) == 0
    return d / "run"


def test_status_holds_the_design_numbers(surge_run):
    """The filtered peak is at most the raw one; the probe read the block's 0.1 m depth and about 3 m/s; alpha
    and k are the filtered peak over rho v^2 h w and rho g h^2 w / 2 with those readings; the window is a
    tenth of the first contact time."""
    o = json.loads((surge_run / "status.json").read_text())["obstacles"]["wall"]
    assert 0 < o["filtered_peak_force"] <= o["peak_force"]
    assert o["force_window"] == pytest.approx(0.1 * o["first_contact"])
    assert o["first_contact"] == pytest.approx((1.0 - 0.6) / 3.0, abs=0.03)
    assert o["probe_depth"] == pytest.approx(0.1, rel=0.05) and o["probe_speed"] == pytest.approx(3.0, rel=0.05)
    rho, v, h = o["probe_density"], o["probe_speed"], o["probe_depth"]
    assert o["alpha"] == pytest.approx(o["filtered_peak_force"] / (rho * v * v * h * 1.0), rel=1e-12)
    assert o["hydrostatic_ratio"] == pytest.approx(o["filtered_peak_force"] / (0.5 * rho * 9.81 * h * h), rel=1e-12)
    assert o["impulse"] >= o["impulse_vector"][0] > 0
    assert o["pressure_profile"] and all(p >= 0 for _, p in o["pressure_profile"])
    assert 0.0 < o["pressure_centre_height"] < 0.1  # the 0.1 m block loads the wall's lowest tenth of a metre


def test_info_and_plot_show_them(surge_run, capsys):
    o = json.loads((surge_run / "status.json").read_text())["obstacles"]["wall"]
    assert main(["info", str(surge_run)]) == 0
    out = capsys.readouterr().out
    assert f"filtered     wall: peak {o['filtered_peak_force']:.4g} N/m" in out
    assert f"alpha = F / (rho v^2 h w) = {o['alpha']:.3g}" in out and "approach     wall: probe 'gauge'" in out
    assert main(["plot", str(surge_run)]) == 0
    assert (surge_run / "plots" / "impact.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    head = (surge_run / "series.csv").read_text().splitlines()[0].split(",")
    assert {"wall_f_filtered", "gauge_depth", "gauge_speed", "gauge_q"} <= set(head)


@pytest.mark.parametrize("change, path", [
    ({"obstacles": [{"type": "box", "name": "wall", "min": [1.0, 0.0], "max": [1.1, 0.3], "probe": "nowhere"}]},
     "obstacles.0.probe"),
    ({"probes": [{"name": "gauge", "point": [0.85, 0.0, 0.0], "half_width": 0.05}]}, "probes.0.point"),
    ({"probes": [{"name": "wall", "point": [0.85, 0.0], "half_width": 0.05}]}, "probes.0.name"),
    ({"solver": {"backend": "cuda"}}, "probes"),
])
def test_bad_probes_are_refused_with_their_path(change, path):
    with pytest.raises(CaseError) as err:
        parse_case(_surge(**change), ".")
    assert path in [p for p, _ in err.value.problems]


def test_a_study_names_every_impact_metric_and_warns_of_a_damping_tied_to_h():
    """`--metric impact` asks for the six obstacle numbers; a study over cell sizes of the main job's old
    damping (no reference_cell_size) is warned about, the flume's (reference_cell_size set) is not."""
    series = [{"time": [0.0], "dam_fx": [0.0]}]
    assert _metric_names(["impact"], series)[0] == [f"{k}:dam" for k in (
        "peak_force", "filtered_peak_force", "impulse", "final_force", "alpha", "hydrostatic_ratio")]
    plan = build_plan(parse_vary(["grid.cell_size=0.1,0.05"]), {}, 1, 0)
    assert validate_all(str(CASES / "flume_impact_2d.json"), plan, []) == []
    warned = validate_all(str(CASES / "flume_impact_2d.json"), plan, ["damping.0.reference_cell_size=null"])
    assert len(warned) == 1 and "reference_cell_size" in warned[0]
