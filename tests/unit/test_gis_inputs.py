"""GIS inputs that cannot go wrong silently (setup/release_crs.py, setup/release_checks.py, files/dem.py): a
GeoJSON's CRS read and reprojected, RFC 7946 longitude/latitude recognised, untagged DEM voids and a
geographic DEM refused with the cell or the UTM zone, a release the grid would cut refused with the volumes, a
depth that looks like centimetres or a release under four cells deep warned about."""

import json

import numpy as np
import pytest

from geompm.errors import CaseError
from geompm.schema.load import parse_case
from geompm.setup.assemble import assemble
from geompm.testing.verification.dem import write_dem

rasterio = pytest.importorskip("rasterio")
W, S = 2_600_000.0, 1_200_000.0  # the site's south-west corner in EPSG:2056 [m]
SQUARE = [(W + 10, S + 10), (W + 20, S + 10), (W + 20, S + 20), (W + 10, S + 20), (W + 10, S + 10)]  # 100 m2


def ground(x, y):
    return 500.0 + 0.3 * (x - W)


def _case(tmp_path, geojson, thickness=2.0, top=30.0, crs="EPSG:2056", dem="dem.tif"):
    if dem == "dem.tif":
        write_dem(tmp_path / "dem.tif", ground, W, S, 40, 40, 1.0)
    return {
        "name": "gis", "dimension": 3, **({"crs": crs} if crs else {}),
        "grid": {"origin": [W, S, 495.0], "extent": [40.0, 40.0, top], "cell_size": 1.0},
        "time": {"end": 0.1}, "gravity": [0.0, 0.0, -9.81],
        "materials": {"soil": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1.0e7,
                               "poisson_ratio": 0.3}},
        "bodies": [{"material": "soil", "particles_per_cell": 2,
                    "geometry": {"type": "release_polygon", "file": geojson, "dem": dem, "thickness": thickness}}],
        "obstacles": [{"type": "terrain", "name": "ground", "dem": dem}],
    }


def _write(tmp_path, name, ring, crs_member=None):
    data = {"type": "FeatureCollection",
            "features": [{"type": "Feature", "properties": {},
                          "geometry": {"type": "Polygon", "coordinates": [[list(map(float, v)) for v in ring]]}}]}
    if crs_member:
        data["crs"] = {"type": "name", "properties": {"name": crs_member}}
    (tmp_path / name).write_text(json.dumps(data))
    return name


def _to(crs, ring):
    from rasterio.warp import transform

    xs, ys = transform("EPSG:2056", crs, [p[0] for p in ring], [p[1] for p in ring])
    return list(zip(xs, ys))


def _assembled(tmp_path, case):
    loaded = parse_case(case, tmp_path)
    return assemble(loaded), loaded.warnings


def _released(scene):
    st = scene.state
    x, y = st.p_x[:, 0], st.p_x[:, 1]
    return float(st.p_vol.sum()), x, y


@pytest.mark.parametrize("crs, member", [("EPSG:2056", "urn:ogc:def:crs:EPSG::2056"),
                                         ("EPSG:32632", "urn:ogc:def:crs:EPSG::32632"),
                                         ("EPSG:4326", None)])
def test_a_polygon_in_any_crs_lands_where_it_is(tmp_path, crs, member):
    """The 10 x 10 m square, written in EPSG:2056 with a crs member, in UTM 32N with one, or in RFC 7946
    longitude/latitude without one: 100 m2 x 2 m = 200 m3 released over the same square (to 1 % and 0.1 m)."""
    ring = SQUARE if crs == "EPSG:2056" else _to(crs, SQUARE)
    scene, _ = _assembled(tmp_path, _case(tmp_path, _write(tmp_path, "a.geojson", ring, member)))
    vol, x, y = _released(scene)
    assert vol == pytest.approx(200.0, rel=0.01)
    assert x.min() > W + 9.9 and x.max() < W + 20.1 and y.min() > S + 9.9 and y.max() < S + 20.1


def test_utm_coordinates_labelled_2056_are_refused_naming_both_crs(tmp_path):
    name = _write(tmp_path, "b.geojson", _to("EPSG:32632", SQUARE), "urn:ogc:def:crs:EPSG::2056")
    with pytest.raises(CaseError) as err:
        _assembled(tmp_path, _case(tmp_path, name))
    (path, text), = err.value.problems
    assert path == "bodies.0.geometry.file" and "outside the DEM" in text and "EPSG:2056" in text


def test_a_crs_the_case_does_not_state_is_refused(tmp_path):
    name = _write(tmp_path, "c.geojson", _to("EPSG:32632", SQUARE), "urn:ogc:def:crs:EPSG::32632")
    with pytest.raises(CaseError) as err:
        _assembled(tmp_path, _case(tmp_path, name, crs=None))
    assert "EPSG:32632" in err.value.problems[0][1] and "\"crs\"" in err.value.problems[0][1]


def _raw_dem(path, z, crs="EPSG:2056", west=W, south=S, nodata=None):
    from rasterio.transform import Affine

    with rasterio.open(path, "w", driver="GTiff", height=z.shape[0], width=z.shape[1], count=1, dtype="float64",
                       crs=crs, transform=Affine(1.0 if crs != "EPSG:4326" else 1e-4, 0.0, west, 0.0,
                                                 -1.0 if crs != "EPSG:4326" else -1e-4,
                                                 south + z.shape[0] * (1.0 if crs != "EPSG:4326" else 1e-4)),
                       nodata=nodata) as dst:
        dst.write(z, 1)


@pytest.mark.parametrize("void", [-32768.0, -9999.0, 0.0])
def test_untagged_voids_are_refused_with_the_cell(tmp_path, void):
    """-32768 and -9999 without a NoData tag, and a 0 in a DEM whose heights are 500-512 m (more than ten
    reliefs below its 1 % height): refused with the cell's map coordinates and the gdal_edit fix."""
    X, Y = np.meshgrid(W + np.arange(40) + 0.5, S + np.arange(40)[::-1] + 0.5)
    z = ground(X, Y)
    z[5, 30] = void  # row 5 from the north: y = S + 34.5; column 30: x = W + 30.5
    _raw_dem(tmp_path / "void.tif", z)
    with pytest.raises(CaseError) as err:
        _assembled(tmp_path, _case(tmp_path, _write(tmp_path, "a.geojson", SQUARE), dem="void.tif"))
    text = err.value.problems[0][1]
    assert "void" in text and "gdal_edit.py -a_nodata" in text and f"x = {W + 30.5:.3f}, y = {S + 34.5:.3f}" in text


def test_a_geographic_dem_is_refused_as_geographic_first(tmp_path):
    _raw_dem(tmp_path / "geo.tif", np.full((40, 40), 500.0), crs="EPSG:4326", west=7.5, south=46.9)
    with pytest.raises(CaseError) as err:
        _assembled(tmp_path, _case(tmp_path, _write(tmp_path, "a.geojson", SQUARE), dem="geo.tif"))
    text = err.value.problems[0][1]
    assert "geographic" in text and "EPSG:32632" in text  # 7.5 E: UTM zone 32 north


def test_a_release_the_grid_would_cut_is_refused_with_the_volumes(tmp_path):
    """220.7 (centimetres given as metres) over 100 m2 in a grid 30 m tall: 22 070 m3 asked, most of it above the
    grid's top; refused with both volumes before any step."""
    with pytest.raises(CaseError) as err:
        _assembled(tmp_path, _case(tmp_path, _write(tmp_path, "a.geojson", SQUARE), thickness=220.7))
    path, text = err.value.problems[0]
    assert path == "bodies.0.geometry" and "22070" in text.replace(" ", "") and "cut off" in text


def test_deep_and_shallow_releases_are_warned_about(tmp_path):
    """60 m in a grid tall enough: warned as a possible unit slip; 2 m at h = 1 m: warned with h = 0.5 m."""
    _, warnings = _assembled(tmp_path, _case(tmp_path, _write(tmp_path, "a.geojson", SQUARE), thickness=60.0,
                                             top=80.0))
    assert any("up to 60 m deep" in t for _, t in warnings)
    _, warnings = _assembled(tmp_path, _case(tmp_path, _write(tmp_path, "a.geojson", SQUARE)))
    shallow = [t for p, t in warnings if "cells at h = 1 m" in t]
    assert shallow and "grid.cell_size = 0.5 m" in shallow[0]


def test_column_seeding_makes_the_box_lattice_particles(tmp_path):
    """The release seeded column by column (setup/release_seed.py) is the box lattice's points inside the
    release, the same points in the same order, for a polygon whose box spans the DEM's relief (12 m) and a
    release 2 m deep: the columns make the 1 600 points of 200 m3 at 8 per m3, the box over five times as many."""
    from geompm.setup.bodies import body_region, lattice
    from geompm.setup.release_seed import seed_release

    case = _case(tmp_path, _write(tmp_path, "a.geojson", SQUARE))
    loaded = parse_case(case, tmp_path)
    geom = loaded.case.bodies[0].geometry
    origin, h = np.array(case["grid"]["origin"]), 1.0
    lo, hi, contains = body_region(geom, 3, tmp_path, "b", None, "EPSG:2056")
    lo, hi = np.maximum(lo, origin), np.minimum(hi, origin + np.array(case["grid"]["extent"]))
    box = lattice(lo, hi, origin, h, 2)
    columns = seed_release(contains, lo, hi, origin, h, 2, "b")
    assert np.array_equal(box[contains(box)], columns) and len(columns) == 1600 and len(box) > 5 * 1600
