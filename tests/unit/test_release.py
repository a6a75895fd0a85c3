"""Release bodies from GIS files (setup/release.py; issue 18, point 3) on a DEM of a 30 deg incline.

A vertical prism over a plane has the volume (plan area) x (vertical thickness) exactly, so the seeded
particle volume is checked against that at three lattice spacings (h = 0.1, 0.05, 0.025 m with 2
particles per cell): the error must stay within 5 % and shrink with h.  Every particle lies over the
polygon, above the DEM's surface and below it plus the thickness.  Per-feature thickness attributes,
a thickness raster and the mass between two DEMs give their volumes; bad input is refused with the
JSON path.
"""

import json
import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.errors import CaseError

from geompm.testing.verification.dem import write_dem

rasterio = pytest.importorskip("rasterio")
TAN = math.tan(math.radians(30.0))


def ground(x, y):
    return 1.6 - TAN * x


def _case(tmp_path, geometry, h=0.05):
    write_dem(tmp_path / "dem.tif", ground, -0.2, -0.2, 60, 60, 0.05)
    return {
        "name": "release", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [2.0, 2.0, 2.0], "cell_size": h},
        "time": {"end": 0.1}, "gravity": [0.0, 0.0, -9.81],
        "materials": {"soil": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1.0e7,
                               "poisson_ratio": 0.3}},
        "bodies": [{"material": "soil", "geometry": geometry, "particles_per_cell": 2}],
        "obstacles": [{"type": "terrain", "name": "ground", "dem": "dem.tif"}],
    }


def _geojson(path, polygons):
    """polygons: [(ring, properties)]"""
    feats = [{"type": "Feature", "properties": props,
              "geometry": {"type": "Polygon", "coordinates": [[list(map(float, v)) for v in ring]]}}
             for ring, props in polygons]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    return path.name


SQUARE = [(0.5, 0.5), (1.1, 0.5), (1.1, 1.1), (0.5, 1.1), (0.5, 0.5)]  # 0.36 m2


def test_release_polygon_volume_converges_to_area_times_thickness(tmp_path):
    _geojson(tmp_path / "area.geojson", [(SQUARE, {})])
    errors = []
    for h in (0.1, 0.05, 0.025):
        geom = {"type": "release_polygon", "file": "area.geojson", "dem": "dem.tif", "thickness": 0.12}
        st = scene_from_dict(_case(tmp_path, geom, h), base_dir=tmp_path).state
        volume = float(st.p_vol.sum())
        errors.append(abs(volume / (0.36 * 0.12) - 1.0))
        x, y, z = st.p_x.T
        assert (x > 0.5).all() and (x < 1.1).all() and (y > 0.5).all() and (y < 1.1).all()
        assert (z > ground(x, y)).all() and (z < ground(x, y) + 0.12).all()
    assert max(errors) < 0.05, errors
    assert errors[2] < errors[0], errors


def test_per_feature_thickness_raster_and_two_surfaces(tmp_path):
    left = [(0.3, 0.5), (0.7, 0.5), (0.7, 0.9), (0.3, 0.9), (0.3, 0.5)]  # 0.16 m2 each
    right = [(1.1, 0.5), (1.5, 0.5), (1.5, 0.9), (1.1, 0.9), (1.1, 0.5)]
    _geojson(tmp_path / "two.geojson", [(left, {"depth": 0.1}), (right, {"depth": 0.2})])
    geom = {"type": "release_polygon", "file": "two.geojson", "dem": "dem.tif", "thickness_attribute": "depth"}
    st = scene_from_dict(_case(tmp_path, geom, 0.025), base_dir=tmp_path).state
    left_vol = float(st.p_vol[st.p_x[:, 0] < 0.9].sum())
    right_vol = float(st.p_vol[st.p_x[:, 0] > 0.9].sum())
    assert left_vol == pytest.approx(0.016, rel=0.05) and right_vol == pytest.approx(0.032, rel=0.05)
    # a thickness raster: 0.1 m over the square 0.5..1.1 (pixel centres), NoData elsewhere
    def thickness(x, y):
        return np.where((x > 0.45) & (x < 1.15) & (y > 0.45) & (y < 1.15), 0.1, np.nan)
    from rasterio.transform import Affine

    xs = -0.2 + (np.arange(60) + 0.5) * 0.05
    X, Y = np.meshgrid(xs, xs[::-1])
    t = np.nan_to_num(thickness(X, Y), nan=-9999.0)
    with rasterio.open(tmp_path / "thick.tif", "w", driver="GTiff", height=60, width=60, count=1, dtype="float64",
                       crs="EPSG:2056", transform=Affine(0.05, 0, -0.2, 0, -0.05, 2.8), nodata=-9999.0) as dst:
        dst.write(t, 1)
    geom = {"type": "release_raster", "file": "thick.tif", "dem": "dem.tif"}
    st = scene_from_dict(_case(tmp_path, geom, 0.025), base_dir=tmp_path).state
    # bilinear between pixel centres: the 0.1 m plateau spans 0.475..1.125, ramps of one pixel around it
    assert float(st.p_vol.sum()) == pytest.approx(0.1 * 0.7 ** 2, rel=0.08)
    # the mass between the ground and a failure surface 0.15 m lower over the same square
    write_dem(tmp_path / "bed.tif", lambda x, y: ground(x, y) - 0.15 * ((x > 0.45) & (x < 1.15) & (y > 0.45)
                                                                        & (y < 1.15)), -0.2, -0.2, 60, 60, 0.05)
    geom = {"type": "between_surfaces", "surface": "dem.tif", "failure_surface": "bed.tif"}
    case = _case(tmp_path, geom, 0.025)
    case["obstacles"][0]["dem"] = "bed.tif"  # the failure surface is the sliding bed
    st = scene_from_dict(case, base_dir=tmp_path).state
    assert float(st.p_vol.sum()) == pytest.approx(0.15 * 0.7 ** 2, rel=0.08)


@pytest.mark.parametrize("change, path, message", [
    ({"thickness": -0.1}, "bodies.0.geometry.thickness", "must be > 0"),
    ({"thickness_attribute": "depth"}, "bodies.0.geometry", "exactly one of"),
    ({"file": "far.geojson"}, "bodies.0.geometry.file", "outside the DEM"),
    ({"dem": "nowhere.tif"}, "bodies.0.geometry.dem", "not found"),
])
def test_bad_release_input_is_refused_with_the_json_path(tmp_path, change, path, message):
    _geojson(tmp_path / "area.geojson", [(SQUARE, {})])
    _geojson(tmp_path / "far.geojson", [([(5, 5), (6, 5), (6, 6), (5, 6), (5, 5)], {})])
    geom = {"type": "release_polygon", "file": "area.geojson", "dem": "dem.tif", "thickness": 0.12, **change}
    with pytest.raises(CaseError) as err:
        scene_from_dict(_case(tmp_path, geom), base_dir=tmp_path)
    text = str(err.value)
    assert path in text and message in text, text


def test_geostatic_stress_of_a_release_polygon_converges_to_the_infinite_slope_solution(tmp_path):
    """Geostatic initial stress on a release_polygon body (issue 18, point 3) with the slope's
    ``surface_normal``: the slope-normal stress of the particles inside the square (0.1 m from its
    edges) against the infinite-slope value sigma_nn = -rho g d cos theta (d the slope-normal depth
    below the body's top; Duncan, Wright & Brandon 2014, Soil Strength and Slope Stability, ch. 6).
    RMS error, out of rho g T cos^2 theta = 1 766 Pa at the base (T = 0.12 m vertical): measured 198 and
    74 Pa at h = 0.05 and 0.025 m (48 Pa at 0.0125 m, docs/terrain.md); asserted below 15 % and 6 % and
    shrinking by more than 1.5x.  The top particles, where the lattice meets a slope-parallel surface in
    steps, carry the largest single errors (0.72 and 0.31 kPa): not asserted."""
    _geojson(tmp_path / "area.geojson", [(SQUARE, {})])
    theta = math.radians(30.0)
    n = np.array([math.sin(theta), 0.0, math.cos(theta)])
    base = 2000.0 * 9.81 * 0.12 * math.cos(theta) ** 2
    rms = []
    for h in (0.05, 0.025):
        geom = {"type": "release_polygon", "file": "area.geojson", "dem": "dem.tif", "thickness": 0.12}
        case = _case(tmp_path, geom, h)
        case["bodies"][0].update(initial_stress="geostatic", surface_normal=list(n))
        st = scene_from_dict(case, base_dir=tmp_path).state
        x, v = st.p_x, st.p_stress
        sig = np.empty((st.n, 3, 3))
        sig[:, 0, 0], sig[:, 1, 1], sig[:, 2, 2] = v[:, 0], v[:, 1], v[:, 2]
        sig[:, 0, 1] = sig[:, 1, 0] = v[:, 3]
        sig[:, 1, 2] = sig[:, 2, 1] = v[:, 4]
        sig[:, 0, 2] = sig[:, 2, 0] = v[:, 5]
        above = (x[:, 2] - ground(x[:, 0], x[:, 1])) * math.cos(theta)  # slope-normal height above the DEM
        depth = 0.12 * math.cos(theta) - above
        inner = (np.abs(x[:, 0] - 0.8) < 0.2) & (np.abs(x[:, 1] - 0.8) < 0.2)
        s_nn = np.einsum("i,pij,j->p", n, sig[inner], n)
        rms.append(float(np.sqrt(np.mean((s_nn + 2000.0 * 9.81 * depth[inner] * math.cos(theta)) ** 2))))
    assert rms[0] < 0.15 * base and rms[1] < 0.06 * base, rms
    assert rms[0] > 1.5 * rms[1], rms
