"""`geompm bench` works: its measurements are self-consistent and its scenes are the issue's scenes.

No timing is asserted here (speed figures live in `geompm bench` and
docs/performance.md, measured on a stated machine); these tests check the
machinery: the per-scene JSON numbers agree with each other and with the
case, the variant checks compute the right ratios, the cold start uses an
empty numba cache, and benchmarks/scenes.json defines the scenes of issue 7
(particle counts, the 25k-1.6M scaling ladder, the 8x domain).
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from geompm.api import scene_from_file
from geompm.bench.command import check_lines, measurements, roofline
from geompm.bench.peak import fma_rates
from geompm.cli import main

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "benchmarks"


def _tiny(tmp_path: Path) -> Path:
    """dp3d at h = 1/16 (2 964 particles), and a scenes.json with a plain scene, a size ladder and a domain pair."""
    case = json.loads((BENCH / "dp3d.json").read_text())
    case["grid"]["cell_size"] = 1 / 16
    (tmp_path / "tiny.json").write_text(json.dumps(case))
    big = dict(case, grid=dict(case["grid"], extent=[2.0, 2.0, 2.0]))
    (tmp_path / "tiny_big.json").write_text(json.dumps(big))
    scenes = {
        "tiny": {"case": "tiny.json", "steps": 3},
        "ladder": {"case": "tiny.json", "steps": 2, "check": "spread",
                   "variants": {"coarse": ["grid.cell_size=0.125"], "fine": ["grid.cell_size=0.0625"]}},
        "domain": {"steps": 2, "check": "domain",
                   "variants": {"unit": {"case": "tiny.json"}, "big": {"case": "tiny_big.json"}}},
    }
    (tmp_path / "scenes.json").write_text(json.dumps(scenes))
    return tmp_path


def test_bench_json_is_self_consistent(tmp_path, capsys):
    folder = _tiny(tmp_path)
    assert main(["bench", "--dir", str(folder), "--json", "--no-cold", "--no-bandwidth"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line.startswith("{")]
    assert [r["scene"] for r in rows] == ["tiny", "ladder:coarse", "ladder:fine", "domain:unit", "domain:big"]
    scene = scene_from_file(folder / "tiny.json")
    r = rows[0]
    # sub-cell centres (k + 1/2) h/2 inside the block: 13 x 19 x 12
    assert r["particles"] == scene.state.n == 13 * 19 * 12
    assert r["steps"] == 3 and r["dimension"] == 3 and r["threads"] >= 1
    assert r["particle_steps_per_s"] == pytest.approx(r["particles"] * r["steps"] / r["wall_s"], rel=1e-9)
    assert r["ns_per_particle_step"] * r["particle_steps_per_s"] == pytest.approx(1e9, rel=1e-9)
    # the model bytes hold at least the particle state; the window holds every node with mass
    assert r["bytes_per_particle"] >= scene.state.nbytes() / scene.state.n
    assert 0 < r["active_nodes"] <= r["window_nodes"] < r["grid_cells"] * 1.2
    assert r["peak_rss_bytes"] > r["model_bytes"]
    assert r["sim_time"] > 0 and r["startup_s"] > 0
    # the ladder refines h by 2 (6 x 9 x 6 sub-cell centres at h = 0.125 m); the big domain has 8x the
    # cells and the same particles
    assert rows[1]["particles"] == 6 * 9 * 6 and rows[2]["particles"] == 13 * 19 * 12
    assert rows[4]["grid_cells"] == 8 * rows[3]["grid_cells"] and rows[4]["particles"] == rows[3]["particles"]


def test_variant_checks_compute_ratios():
    """The spread and domain lines divide the right figures (synthetic results)."""
    spec = {"check": "spread"}
    res = [("s:a", {"particles": 10, "ns_per_particle_step": 100.0}),
           ("s:b", {"particles": 1000, "ns_per_particle_step": 130.0})]
    (line,) = check_lines("s", spec, res)
    assert "= 1.300" in line and "OUTSIDE" in line
    res[1][1]["ns_per_particle_step"] = 120.0
    assert "within" in check_lines("s", spec, res)[0]
    dom = [("d:tight", {"wall_s": 2.0, "grid_cells": 100}), ("d:wide", {"wall_s": 2.3, "grid_cells": 800})]
    (line,) = check_lines("d", {"check": "domain"}, dom)
    assert "8x the grid cells" in line and "1.150x" in line and "within" in line
    ratio = [("r:dp3d", {"wall_s": 1.0, "ns_per_particle_step": 150.0}),
             ("r:si", {"wall_s": 10.0, "ns_per_particle_step": 3000.0,
                       "scheme_timings": {"solve_s": 3.5, "solves": 20.0, "solve_iterations": 160.0,
                                          "hierarchy_builds": 1.0}})]
    first, second = check_lines("r", {"check": "ratio"}, ratio)
    assert first == "r: r:dp3d 150 ns per particle-step"
    assert "20.00x r:dp3d's" in second and "35 % of its time" in second and "8.0 CG iterations" in second


def test_roofline_divides_the_right_figures():
    """The roofline line (synthetic figures): 1e7 particle-steps/s of 2000 flops and 800 bytes are 20 GFLOP/s
    and 8 GB/s, against a 40 GFLOP/s scalar rate, 80 vectorised and a 16 GB/s triad."""
    r = {"particle_steps_per_s": 1e7, "roofline_flops": 2000, "roofline_bytes": 800}
    line = roofline(r, 16e9, {"scalar_flops_per_s": 40e9, "vector_flops_per_s": 80e9})
    assert line["flops_per_s"] == pytest.approx(2e10) and line["bytes_per_s"] == pytest.approx(8e9)
    assert line["of_scalar_fma"] == pytest.approx(0.5) and line["of_vector_fma"] == pytest.approx(0.25)
    assert line["of_triad"] == pytest.approx(0.5)
    assert "20.0 GFLOP/s = 50% of the scalar" in line["text"] and "8.0 GB/s = 50% of the triad" in line["text"]


def test_multiply_add_rates_compute_what_they_count():
    """The micro-benchmark's chains end where a x + b converges from 1 + t (x -> 2 for a = 0.5, b = 1): its own
    check passes, so the flops it counts were done; the vectorised update is not slower than the scalar chains
    by more than its noise (it runs 4-8 lanes per instruction)."""
    rates = fma_rates(iters=200_000, repeats=2)
    assert rates["scalar_flops_per_s"] > 1e8 and rates["vector_flops_per_s"] > 0.5 * rates["scalar_flops_per_s"]


def test_shipped_scenes_are_the_issue_scenes():
    """benchmarks/scenes.json: fluid3d/dp3d/obstacle3d about 198k particles on 64^3 cells, dp2d about 200k
    in 2D, scaling from 25k to 1.6M (factor 4 per level, within 15 %), a domain 8x or more the tight one."""
    scenes = json.loads((BENCH / "scenes.json").read_text())
    assert {"fluid3d", "dp3d", "dp2d", "obstacle3d", "scaling", "domain"} <= set(scenes)
    for name in ("fluid3d", "dp3d", "obstacle3d"):
        sc = scene_from_file(BENCH / scenes[name]["case"])
        assert sc.dim == 3 and list(sc.grid.ncells) == [64, 64, 64]
        assert 190_000 < sc.state.n < 210_000
        assert scenes[name]["steps"] == 100
    assert len(scene_from_file(BENCH / "obstacle3d.json").obstacles) == 1
    d2 = scene_from_file(BENCH / scenes["dp2d"]["case"])
    assert d2.dim == 2 and 190_000 < d2.state.n < 210_000 and scenes["dp2d"]["steps"] == 200
    ladder = measurements("scaling", scenes["scaling"], BENCH, None)
    h = np.array([float(s[0].split("=")[1]) for _, _, s, _, _ in ladder])
    counts = 204204 * (0.015625 / h) ** 3  # particles scale with h^-3 at 2 per cell per direction
    np.testing.assert_allclose(counts, [25e3, 100e3, 400e3, 1.6e6], rtol=0.15)
    cells = [int(scene_from_file(case, sets).grid.ncells.prod())
             for _, case, sets, _, _ in measurements("domain", scenes["domain"], BENCH, None)]
    assert cells[1] / cells[0] >= 6 and cells[2] / cells[1] == 8


def test_unknown_scene_is_refused(tmp_path, capsys):
    folder = _tiny(tmp_path)
    assert main(["bench", "--dir", str(folder), "--scene", "nope"]) == 2
    assert "unknown scene nope" in capsys.readouterr().err


@pytest.mark.slow
def test_cold_start_uses_an_empty_cache(tmp_path):
    """The cold start compiles (empty NUMBA_CACHE_DIR) and is slower than the warm start from that cache.  The
    2D DP scene at h = 0.02 m (measured 20.6 s cold, 0.9 s warm) rather than the 3D tiny scene (about 35 s of the
    suite): the mechanism is the same, and geompm bench measures the 3D scenes' cold starts
    (docs/performance.md)."""
    from geompm.bench.command import cold_and_warm

    cold, warm = cold_and_warm(str(BENCH / "dp2d.json"), ["grid.cell_size=0.02"])
    assert cold > 2.0 * warm > 0


def test_worker_runs_as_a_module(tmp_path):
    folder = _tiny(tmp_path)
    out = subprocess.run([sys.executable, "-m", "geompm.bench.worker", str(folder / "tiny.json"), "--steps", "1",
                          "--set", "grid.cell_size=0.125"], capture_output=True, text=True, check=True).stdout
    r = json.loads(out)
    assert r["steps"] == 1 and r["particles"] == 6 * 9 * 6


def test_triad_bandwidth_is_plausible():
    """The STREAM triad moves 24 bytes per element: a figure between 0.5 GB/s and 2 TB/s on any machine."""
    from geompm.bench.stream import triad_bandwidth

    assert 5e8 < triad_bandwidth(n=2_000_000, repeats=2) < 2e12
