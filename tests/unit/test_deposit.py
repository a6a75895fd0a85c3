"""The deposit measures of geompm/writers/deposit.py on deposits whose answer is known in closed form.

A rectangle L x H of particles on a regular lattice (any spacing): thickness H
everywhere, front at L (to the sampling step), height H; a wedge of slope
H/L (a triangle) has t(x) = H (1 - x/L), so its front at threshold f H is at
(1 - f) L; a lone particle far ahead of the deposit does not move the front
(the furthest particle would), as long as one particle layer is thinner than
the threshold.
"""

import numpy as np
import pytest

from geompm.writers.deposit import deposit_front, deposit_height, thickness_profile


def _lattice(L, H, s):
    xs, ys = np.meshgrid(np.arange(0.5 * s, L, s), np.arange(0.5 * s, H, s), indexing="ij")
    pts = np.stack([xs.ravel(), ys.ravel()], axis=1)
    return pts, np.full(len(pts), s * s)


@pytest.mark.parametrize("s", [0.01, 0.005, 0.0025])
def test_rectangle_front_and_height_at_any_spacing(s):
    x, a = _lattice(0.3, 0.1, s)
    assert deposit_height(x, a, 0.0005, 0.005) == pytest.approx(0.1, rel=1e-9)
    assert deposit_front(x, a, 0.005, 0.0005) == pytest.approx(0.3, abs=0.0005)
    _, t = thickness_profile(x, a, 0.0005)
    assert np.median(t) == pytest.approx(0.1, rel=1e-9)


def test_wedge_front_follows_the_threshold():
    s = 0.0025
    x, a = _lattice(0.4, 0.1, s)
    keep = x[:, 1] <= 0.1 * (1.0 - x[:, 0] / 0.4)
    for f in (0.05, 0.25, 0.5):
        assert deposit_front(x[keep], a[keep], f * 0.1, 0.0005) == pytest.approx((1 - f) * 0.4, abs=3 * s)


def test_an_outlier_does_not_move_the_front():
    """Valid while one particle layer is thinner than the threshold (here 2.5 mm against 5 mm)."""
    x, a = _lattice(0.3, 0.1, 0.0025)
    x = np.vstack([x, [[0.6, 0.00125]]])
    a = np.append(a, 0.0025 ** 2)
    assert deposit_front(x, a, 0.005, 0.0005) == pytest.approx(0.3, abs=0.0005)
    assert x[:, 0].max() == pytest.approx(0.6)


def test_series_writes_the_deposit_front_and_study_takes_it_as_runout(tmp_path):
    """A run with the series writer's deposit_threshold writes deposit_front; a particle that a --set puts
    far ahead moves front_x but not deposit_front, and scalar_metrics reports deposit_front as runout."""
    import json

    from geompm.cli import main
    from geompm.study import metrics as M

    from tests.support.cases import tiny_case

    case = tiny_case(outputs=[{"writer": "series", "interval": 0.0, "deposit_threshold": 0.15}])
    case["time"]["end"] = 0.01
    case["bodies"].append({"material": "soil", "geometry": {"type": "box", "min": [0.8, 0.0], "max": [0.9, 0.1]},
                           "particles_per_cell": 1})
    f = tmp_path / "c.json"
    f.write_text(json.dumps(case))
    assert main(["run", str(f), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    series, status = M.read_run(tmp_path / "run")
    assert series["front_x"][-1] > 0.8  # the lone particle: 0.1 m thick alone, below the 0.15 m threshold
    assert series["deposit_front"][-1] == pytest.approx(0.6, abs=0.02)  # the 0.2-0.6 m block, 0.4 m thick
    assert M.scalar_metrics(series, status)["runout"] == series["deposit_front"][-1]


def test_deposit_threshold_is_refused_in_3d(tmp_path, capsys):
    import json

    from geompm.cli import main

    from tests.support.cases import CASES

    case = json.loads((CASES / "debris_obstacle.json").read_text())
    case["outputs"] = [{"writer": "series", "deposit_threshold": 0.01}]
    f = tmp_path / "c.json"
    f.write_text(json.dumps(case))
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "check_dam.stl").write_bytes((CASES / "meshes" / "check_dam.stl").read_bytes())
    assert main(["validate", str(f)]) == 2
    assert "outputs.0.deposit_threshold: the deposit front is defined for 2D" in capsys.readouterr().err


def test_front_of_a_profile_shorter_than_the_window():
    """A column narrower than the 5-threshold window (0.1 m wide, window 0.25 m) still has its front at its
    edge, within one sample."""
    s = 0.0025
    g = (np.arange(40) + 0.5) * s
    x = np.array([(a, b) for a in g if a < 0.1 for b in (np.arange(200) + 0.5) * s])
    a = np.full(len(x), s * s)
    assert deposit_front(x, a, 0.05, 0.01) == pytest.approx(0.1, abs=0.01)
