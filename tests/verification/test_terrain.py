"""Terrain from a DEM (obstacles/terrain.py, files/dem.py; issue 18, point 1).

- Signed distance from the height field against the exact distance to a paraboloid
  z = (x^2 + y^2) / (2 R) (closest point by dense search on the analytic surface): within 0.05 h.
- A block sliding on a DEM of a 30 deg incline with mu = 0.3 moves as the closed form
  s = g (sin theta - mu cos theta) t^2 / 2 (rigid-body dynamics; tests/refdata/analytic_block_on_incline.csv)
  and as the same block on the analytic ``plane`` boundary, within 3 %; the same with the slope turned
  37 deg about the vertical, so that the DEM's axes and the slope do not line up.
- The terrain's force history: its time-mean normal force once the block has landed is the weight's
  component normal to the slope, F_n = M g cos theta, within 3 %; no particle ends a step deeper than h / 4.
- Bad input: a missing DEM, NoData inside the grid, a DEM that does not cover the grid, a DEM in
  another CRS than the case's ``crs``, a 2D case: refused with the JSON path (and the NoData cell's map
  coordinates).
"""

import math

import numpy as np
import pytest

from geompm.api import scene_from_dict
from geompm.errors import CaseError

from geompm.testing.verification.dem import write_dem
from geompm.testing.verification.terrain_block import block_case, slide

rasterio = pytest.importorskip("rasterio")
G = 9.81


def test_signed_distance_to_a_paraboloid_is_within_five_hundredths_of_a_cell(tmp_path):
    """terrain_phi against the exact distance to z = (x^2 + y^2) / (2 R), R = 2 m, for points within
    two cells of the surface on slopes up to 56 deg (|grad H| = 1.5 at r = 3 m); DEM pixel h / 2."""
    from geompm.obstacles.terrain import TERRAIN, terrain_phi

    h, R = 0.1, 2.0
    dx = h / 2
    n = int(7.0 / dx)
    west = -3.5
    xs = west + (np.arange(n) + 0.5) * dx
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    z = (X ** 2 + Y ** 2) / (2 * R)
    prm = np.zeros(len(TERRAIN))
    prm[TERRAIN.dem_x0] = prm[TERRAIN.dem_y0] = xs[0]
    prm[TERRAIN.dem_dx] = prm[TERRAIN.dem_dy] = dx
    prm[TERRAIN.dem_nx] = prm[TERRAIN.dem_ny] = n
    rng = np.random.default_rng(4)
    # exact distance: by symmetry the closest point lies in the vertical plane through the axis and p,
    # at a radius r solving d/dr [(r - rho)^2 + (r^2 / 2R - z)^2] = 0:  r^3 / (2 R^2) + r (1 - z / R) - rho = 0
    errors, slopes = [], []
    w = np.zeros(12)
    for _ in range(300):
        rad, ang = rng.uniform(0.0, 3.0), rng.uniform(0, 2 * np.pi)
        foot = np.array([rad * np.cos(ang), rad * np.sin(ang), rad ** 2 / (2 * R)])
        normal = np.array([-foot[0] / R, -foot[1] / R, 1.0])
        normal /= np.linalg.norm(normal)
        p = foot + rng.uniform(-2 * h, 2 * h) * normal
        rho = math.hypot(p[0], p[1])
        roots = np.roots([1 / (2 * R ** 2), 0.0, 1.0 - p[2] / R, -rho])
        roots = roots[np.abs(roots.imag) < 1e-9].real
        exact = min(math.hypot(r - rho, r * r / (2 * R) - p[2]) for r in roots)
        exact *= 1.0 if p[2] > rho ** 2 / (2 * R) else -1.0
        errors.append(abs(terrain_phi(z, prm, p[0], p[1], p[2], w, 3) - exact))
        slopes.append(math.degrees(math.atan(rad / R)))
    errors = np.array(errors)
    assert max(slopes) > 55.0
    assert errors.max() < 0.05 * h, f"largest error {errors.max() / h:.3f} h"


@pytest.mark.parametrize("turn", [0.0, 37.0])
def test_block_on_a_dem_incline_slides_as_on_the_plane_and_the_closed_form(tmp_path, turn):
    th, mu, end = math.radians(30.0), 0.3, 0.4
    exact = G * (math.sin(th) - mu * math.cos(th)) * end ** 2 / 2
    s_dem, sim, lowest, fn = slide(tmp_path, turn, "terrain", mu=mu, end=end)
    s_plane, _, _, _ = slide(tmp_path, turn, "plane", mu=mu, end=end)
    assert s_dem == pytest.approx(exact, rel=0.03), f"terrain {s_dem:.4f} m, exact {exact:.4f} m"
    assert s_dem == pytest.approx(s_plane, rel=0.03), f"terrain {s_dem:.4f} m, plane {s_plane:.4f} m"
    assert lowest > -0.25 * 0.05  # the contact guarantee: no particle deeper than h / 4
    mass = float(sim.state.p_mass.sum())
    # the time-mean normal force from 0.1 s on (the elastic block rings at its contact frequency)
    assert fn == pytest.approx(mass * G * math.cos(th), rel=0.03), (fn, mass * G * math.cos(th))


def test_dem_problems_are_refused_with_the_json_path(tmp_path):
    case, _, height = block_case(tmp_path, 30.0, 0.0, 0.3, "terrain")
    case["obstacles"][0]["dem"] = "missing.tif"
    with pytest.raises(CaseError, match=r"obstacles\.0\.dem.*not found"):
        scene_from_dict(case, base_dir=tmp_path)
    write_dem(tmp_path / "hole.tif", height, -0.2, -0.2, 44, 44, 0.05, nodata_at=(1.0125, 0.5125))
    case["obstacles"][0]["dem"] = "hole.tif"
    with pytest.raises(CaseError, match=r"obstacles\.0\.dem.*NoData.*x = 1\.025, y = 0\.525"):
        scene_from_dict(case, base_dir=tmp_path)
    write_dem(tmp_path / "small.tif", height, 0.2, 0.2, 20, 20, 0.05)
    case["obstacles"][0]["dem"] = "small.tif"
    with pytest.raises(CaseError, match=r"obstacles\.0\.dem.*(does not reach|pixels cover)"):
        scene_from_dict(case, base_dir=tmp_path)
    case["obstacles"][0]["dem"] = "slope.tif"  # written by block_case, in EPSG:2056
    case["crs"] = "EPSG:32632"  # UTM 32N
    with pytest.raises(CaseError, match=r"obstacles\.0\.dem.*EPSG:2056.*EPSG:32632.*gdalwarp"):
        scene_from_dict(case, base_dir=tmp_path)
    case["crs"] = "EPSG:99999999"
    with pytest.raises(CaseError, match=r"crs.*not a coordinate reference system"):
        scene_from_dict(case, base_dir=tmp_path)
    case["crs"] = "EPSG:2056"
    scene_from_dict(case, base_dir=tmp_path)  # the same CRS: accepted
    flat = {"name": "t2", "dimension": 2, "grid": {"origin": [0.0, 0.0], "extent": [1.0, 1.0], "cell_size": 0.1},
            "time": {"end": 0.1}, "gravity": [0.0, -G], "materials": case["materials"],
            "bodies": [{"material": "block", "geometry": {"type": "box", "min": [0.2, 0.2], "max": [0.4, 0.4]}}],
            "obstacles": [{"type": "terrain", "dem": "slope.tif"}]}
    with pytest.raises(CaseError, match=r"obstacles\.0.*3D"):
        scene_from_dict(flat, base_dir=tmp_path)
