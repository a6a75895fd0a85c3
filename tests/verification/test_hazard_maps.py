"""Hazard maps (writers/hazard_maps.py; issue 18, point 4) from a block sliding down a DEM incline.

Checked on the maps a `geompm run` writes: the deposit raster integrated over the cell areas equals
the particles' volume (the depth is the binned reference volume over the cell area, so to the
block's elastic volume change while every particle is over the raster; the issue asks 3 %); the maximum-depth raster is >= the deposit
everywhere; the arrival time grows down the slope along the block's centre line; the GeoTIFFs carry
the DEM's CRS and transform exactly (read back with rasterio); the run's VTU points are the map
coordinates (eastings of 2.6e6 m, EPSG:2056): the same case in local coordinates gives the same
particles shifted by the map offset to 1e-6 m, at the start and after 0.3 s of sliding.
"""

import json
import math

import meshio
import numpy as np
import pytest

from geompm.cli import main

from geompm.testing.verification.dem import write_dem

from geompm.testing.verification.terrain_block import block_case

rasterio = pytest.importorskip("rasterio")
EAST, NORTH = 2_600_000.0, 1_200_000.0  # a Swiss LV95 site


def _site_case(tmp_path):
    """The 30 deg DEM incline of test_terrain, moved to map coordinates (E, N) = (2.6e6, 1.2e6) m."""
    case, down, height = block_case(tmp_path, 30.0, 0.0, 0.3, "terrain")
    write_dem(tmp_path / "site.tif", lambda x, y: height(x - EAST, y - NORTH), EAST - 0.2, NORTH - 0.2, 44, 44, 0.05)
    case["grid"]["origin"] = [EAST, NORTH, 0.0]
    case["obstacles"][0]["dem"] = "site.tif"
    case["bodies"][0]["geometry"]["translate"] = [EAST, NORTH, 0.0]
    case["time"]["end"] = 0.3
    case["crs"] = "EPSG:2056"
    case["outputs"] = [{"writer": "hazard_maps", "depth_threshold": 0.01},
                       {"writer": "vtu", "interval": 0.3}, {"writer": "hdf5", "interval": 0.3}]
    (tmp_path / "site.json").write_text(json.dumps(case))
    return tmp_path / "site.json", height


def test_hazard_maps_of_a_sliding_block(tmp_path, capsys):
    path, height = _site_case(tmp_path)
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    maps = {}
    with rasterio.open(tmp_path / "site.tif") as dem:
        crs, transform = dem.crs, dem.transform
    for name in ("depth_max", "deposit", "source", "arrival", "speed_max", "pressure_max"):
        with rasterio.open(out / "maps" / f"{name}.tif") as src:
            assert src.crs == crs and src.transform == transform, name  # the DEM's georeferencing, exactly
            maps[name] = src.read(1, masked=True)
    area = abs(transform.a * transform.e)
    mesh = meshio.read(sorted((out / "particles").glob("particles_*.vtu"))[-1])
    volume = float(np.sum(mesh.point_data["volume"]))
    assert float(maps["deposit"].sum()) * area == pytest.approx(volume, rel=0.03)
    assert float(maps["source"].sum()) * area == pytest.approx(float(maps["deposit"].sum()) * area, rel=0.03)
    assert (maps["depth_max"] >= maps["deposit"] - 1e-12).all()
    # arrival along the centre line (the block slides along +x, rows run north to south)
    row = maps["arrival"].shape[0] // 2
    line = maps["arrival"][row]
    reached = np.nonzero(~line.mask)[0]
    later = reached[line[reached] > 0]
    assert len(later) >= 2, "the block reached no new cell"
    assert (np.diff(line[later]) >= 0).all(), line[later]
    assert float(maps["speed_max"].max()) > 0.5 and float(maps["pressure_max"].max()) > 0.0
    summary = json.loads((out / "maps" / "summary.json").read_text())
    assert summary["deposit_volume_m3"] == pytest.approx(volume, rel=0.03) and summary["crs"] == "EPSG:2056"
    # travel on a plane: the drop between two ground points over their distance is tan 30 deg, plus the
    # release depth at the top cell (at most the block's vertical 0.17 m) over the runout (~0.4 m)
    L = summary["runout_length_m"]
    assert 0.3 < L < 0.6
    most = math.degrees(math.atan(math.tan(math.radians(30)) + 0.15 / math.cos(math.radians(30)) / L))
    assert 30.0 < summary["travel_angle_deg"] <= most
    import h5py

    with h5py.File(out / "results.h5") as f:
        assert f.attrs["crs"] == "EPSG:2056"
    assert main(["info", str(out)]) == 0
    assert "travel angle" in capsys.readouterr().out
    assert main(["plot", str(out)]) == 0  # the maps over the DEM's hillshade (plots/maps.py)
    for name in ("depth_max", "speed_max", "pressure_max", "arrival", "deposit"):
        png = (out / "plots" / f"map_{name}.png").read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000, name
    # VTU points are the map coordinates: the same case in local coordinates (origin 0) gives the same
    # particles shifted by (E, N), to 1e-6 m, at t = 0 and after 0.3 s of sliding
    (tmp_path / "local").mkdir()
    local_case, _, _ = block_case(tmp_path / "local", 30.0, 0.0, 0.3, "terrain")
    local_case["time"]["end"] = 0.3
    local_case["outputs"] = [{"writer": "vtu", "interval": 0.3}]
    (tmp_path / "local" / "local.json").write_text(json.dumps(local_case))
    assert main(["run", str(tmp_path / "local" / "local.json"), "--out", str(tmp_path / "run_local"), "--quiet"]) == 0
    for k in (0, -1):
        site = meshio.read(sorted((out / "particles").glob("particles_*.vtu"))[k])
        local = meshio.read(sorted((tmp_path / "run_local" / "particles").glob("particles_*.vtu"))[k])
        shift = site.points - local.points
        assert site.points[:, 0].min() > EAST
        assert bytes(site.field_data["crs"]).decode() == "EPSG:2056" and "crs" not in local.field_data
        np.testing.assert_allclose(shift[:, 0], EAST, rtol=0, atol=1e-6)
        np.testing.assert_allclose(shift[:, 1], NORTH, rtol=0, atol=1e-6)
        np.testing.assert_allclose(shift[:, 2], 0.0, rtol=0, atol=1e-6)


def test_hazard_maps_resume_from_a_checkpoint_state(tmp_path):
    """At a checkpoint the writer writes its GeoTIFFs and maps/state.npz; a resumed writer reloads the
    maxima and the arrival times exactly and carries on accumulating."""
    from geompm.api import scene_from_file
    from geompm.engine.scheduler import Simulation
    from geompm.writers.hazard_maps import MAPS, HazardMapParams, HazardMapWriter

    path, _ = _site_case(tmp_path)
    sim = Simulation(scene_from_file(path))
    run = tmp_path / "run"
    run.mkdir()
    first = HazardMapWriter(HazardMapParams(), 0.0)
    first.open(run, sim)
    for _ in range(200):
        sim.step(sim.stable_dt())
        first.write(sim)
    state = first.state()
    assert (run / "maps" / "depth_max.tif").is_file() and (run / "maps" / "state.npz").is_file()
    second = HazardMapWriter(HazardMapParams(), 0.0)
    second.resume(run, sim, state)
    for name in MAPS:
        np.testing.assert_array_equal(second.maps[name], first.maps[name], err_msg=name)
    assert (second.maps["arrival"] > 0).any()  # the block had moved onto new cells
    for _ in range(50):
        sim.step(sim.stable_dt())
        first.write(sim)
        second.write(sim)
    for name in MAPS:
        np.testing.assert_array_equal(second.maps[name], first.maps[name], err_msg=name)


def test_hazard_maps_without_a_raster_are_refused_before_the_run(tmp_path):
    from geompm.api import scene_from_dict
    from geompm.errors import CaseError

    case, _, _ = block_case(tmp_path, 30.0, 0.0, 0.3, "plane")
    case["outputs"] = [{"writer": "hazard_maps"}]
    with pytest.raises(CaseError, match=r"outputs\.0\.dem.*terrain obstacle"):
        scene_from_dict(case, base_dir=tmp_path)


def test_basal_pore_pressure_ratio_map_of_a_saturated_block(tmp_path):
    """A saturated block (grains 2650 kg/m3, n = 0.4, so rho_sat = 1990 kg/m3) resting on a flat DEM,
    hydrostatic below its top, 5 ms after release (K_w = 2e7 Pa: a tenth of water's, for a longer step): the median over the covered cells of the map
    pore_pressure_ratio_max equals the hydrostatic basal ratio rho_w (D - s/2) / (rho_sat D) = 0.4606
    (D = 0.15 m thick, its lowest particles s/2 = 0.0125 m above the base) within 3 %. A ratio over the solids'
    weight only would give 0.77, one without the water's pressure 0 (docs/pore-water.md)."""
    case, _, _ = block_case(tmp_path, 0.0, 0.0, 0.3, "terrain")
    case["materials"]["block"]["density"] = 2650.0
    case["materials"]["block"]["pore_water"] = {"porosity": 0.4, "hydraulic_conductivity": 1e-6,
                                                "fluid": {"bulk_modulus": 2.0e7}}
    case["time"]["end"] = 0.005
    case["outputs"] = [{"writer": "hazard_maps", "depth_threshold": 0.05}]
    (tmp_path / "wet.json").write_text(json.dumps(case))
    out = tmp_path / "run"
    assert main(["run", str(tmp_path / "wet.json"), "--out", str(out), "--quiet"]) == 0
    with rasterio.open(out / "maps" / "pore_pressure_ratio_max.tif") as src:
        ratio = src.read(1)
    with rasterio.open(out / "maps" / "depth_max.tif") as src:
        depth = src.read(1)
    full = depth > 0.14  # columns the block covers whole
    assert full.sum() >= 16
    expected = 1000.0 * (0.15 - 0.0125) / (1990.0 * 0.15)
    assert float(np.median(ratio[full])) == pytest.approx(expected, rel=0.03)
    summary = json.loads((out / "maps" / "summary.json").read_text())
    assert summary["peak_pore_pressure_ratio"] >= float(np.median(ratio[full]))


def test_maps_are_nodata_outside_the_flow_and_timed_maps_pair_depth_and_speed(tmp_path):
    """Every map is NoData where its quantity is undefined (outside the flow, the deposit, the source) and
    names its unit in the band description; the timed maps at 0.1 and 0.2 s hold the block's volume (to
    3 %) and its speed, a t along the slope with a = g (sin 30 - 0.3 cos 30) = 2.36 m/s2 (to 10 %: the
    terrain's velocity-form friction, tests/verification/test_terrain.py)."""
    path, _ = _site_case(tmp_path)
    case = json.loads(path.read_text())
    case["outputs"] = [{"writer": "hazard_maps", "depth_threshold": 0.01, "times": [0.1, 0.2]}]
    path.write_text(json.dumps(case))
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    with rasterio.open(out / "maps" / "depth_max.tif") as src:
        depth_max = src.read(1, masked=True)
        assert src.descriptions == ("depth_max [m]",)
        area = abs(src.transform.a * src.transform.e)
    assert depth_max.mask.any() and (depth_max.compressed() >= 0.01).all()  # NoData where the flow never was
    for name in ("speed_max", "pressure_max", "energy_max"):
        with rasterio.open(out / "maps" / f"{name}.tif") as src:
            assert (src.read(1, masked=True).mask == depth_max.mask).all(), name
    with rasterio.open(out / "maps" / "deposit.tif") as src:
        deposit = src.read(1, masked=True)
    assert (deposit.compressed() >= 0.01).all() and deposit.mask.sum() > depth_max.mask.sum()
    summary = json.loads((out / "maps" / "summary.json").read_text())
    volume = summary["source_volume_m3"]
    a = 9.81 * (math.sin(math.radians(30)) - 0.3 * math.cos(math.radians(30)))
    for t in (0.1, 0.2):
        at = summary["timed_maps"][f"{t:g}"]
        assert t <= at < t + 0.01
        with rasterio.open(out / "maps" / f"depth_t{t:g}.tif") as src:
            assert float(src.read(1, masked=True).sum()) * area == pytest.approx(volume, rel=0.03)
            assert src.descriptions == ("depth_t%g [m]" % t,)
        with rasterio.open(out / "maps" / f"speed_t{t:g}.tif") as src:
            speed = src.read(1, masked=True)
        assert float(np.ma.median(speed)) == pytest.approx(a * at, rel=0.10)


def test_a_creeping_column_does_not_arrive():
    """accumulate (writers/hazard_maps.py): a column 0.2 m deep moving at 0.05 m/s (creep, below the 0.1 m/s
    arrival speed) gets no arrival time but its depth and speed maxima; at 0.2 m/s it arrives."""
    from geompm.writers.hazard_maps import accumulate

    sums = np.zeros((2, 1, 6))
    for i, u in enumerate((0.05, 0.2)):
        sums[i, 0, :2] = 0.2, 400.0  # 0.2 m3 over 1 m2, 2000 kg/m3
        sums[i, 0, 2] = 400.0 * u
    depth, speed, dmax, smax, pmax, emax = (np.zeros((2, 1)) for _ in range(6))
    arrival = np.full((2, 1), -1.0)
    accumulate(sums, 1.0, 0.01, 0.1, 59.0, depth, speed, dmax, smax, pmax, emax, arrival)
    assert arrival[0, 0] == -1.0 and arrival[1, 0] == 59.0
    assert dmax[0, 0] == pytest.approx(0.2) and smax[0, 0] == pytest.approx(0.05) and speed[1, 0] == pytest.approx(0.2)


@pytest.mark.slow
def test_a_study_writes_ensemble_maps_and_map_metrics(tmp_path, capsys):
    """`geompm study` over three friction coefficients of the site case: maps/probability_of_reach.tif is the
    fraction of runs whose depth_max reached the threshold (k/3, NoData where none did), depth_max_p50.tif the
    median of the runs' depth_max with 0 where a run did not reach, on the DEM's raster; study.csv carries each
    run's impact area and runouts from maps/summary.json (the thalweg runout no shorter than the cell's size and
    no longer than the straight runout allows); the terrain's force is not a metric; eastings print in full."""
    path, _ = _site_case(tmp_path)
    out = tmp_path / "study"
    assert main(["study", str(path), "--vary", "obstacles.0.friction=0.2,0.4,0.6", "--out", str(out), "--quiet",
                 "--workers", "1"]) == 0
    printed = capsys.readouterr().out
    runs = sorted((out / "runs").iterdir())
    depth = []
    for d in runs:
        with rasterio.open(d / "maps" / "depth_max.tif") as src:
            depth.append(src.read(1))
            transform = src.transform
    depth = np.stack(depth)
    with rasterio.open(out / "maps" / "probability_of_reach.tif") as src:
        assert src.transform == transform and src.descriptions[0] == "probability_of_reach [-]"
        prob = src.read(1)
    with rasterio.open(out / "maps" / "depth_max_p50.tif") as src:
        p50 = src.read(1)
    reached = depth != -9999.0
    count = reached.sum(axis=0)
    assert (prob[count == 0] == -9999.0).all() and prob[count > 0] == pytest.approx(count[count > 0] / 3)
    assert (count == 3).any() and (count < 3).any()  # friction changes where the block goes
    median = np.median(np.where(reached, depth, 0.0), axis=0)
    assert p50[count > 0] == pytest.approx(median[count > 0], abs=1e-12)
    summary = json.loads((out / "study_summary.json").read_text())
    assert summary["maps"]["runs"] == 3 and "maps/pressure_max_p90.tif" in summary["maps"]["files"]
    header = (out / "study.csv").read_text().splitlines()[0].split(",")
    assert "impact_area" in header and "runout_thalweg" in header and "runout_length" in header
    assert not any(h.startswith("peak_force:") for h in header)  # the terrain is the ground, not a barrier
    rows = [dict(zip(header, line.split(","))) for line in (out / "study.csv").read_text().splitlines()[1:]]
    for r in rows:
        assert 0.0 < float(r["runout_thalweg"]) and float(r["impact_area"]) > 0.0
    assert "e+06" not in printed and "ensemble maps of 3 runs" in printed
