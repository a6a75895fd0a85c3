"""Generate the synthetic catchment of cases/terrain_debris_flow.json (deterministic; run from anywhere).

    python cases/terrain/make_site.py

Writes, next to this script:
- ``site.tif``: a 1 m DEM (GeoTIFF, EPSG:2056 Swiss LV95, float64) of a 240 m x 100 m catchment whose
  lower-left corner is at E 2 650 000, N 1 150 000 m: a channel running east, 25 deg steep in its upper
  half and easing to 6 deg on a fan (tanh transition around x = 130 m), V-shaped valley sides at about
  19 deg with a 5 m rounded bottom, and smoothed random relief of 0.3 m;
- ``release.geojson``: the release area in the upper channel (a hexagon of about 480 m2) with a
  vertical ``depth`` property of 2.2 m (about 1 000 m3 of debris);
- ``check_dam.stl``: a 2.5 m x 44 m x 6 m concrete check dam (a box, local coordinates centred on the
  origin), placed across the channel at x = 170 m by the case's ``translate``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
E0, N0 = 2_650_000.0, 1_150_000.0
NX, NY, PIXEL = 240, 100, 1.0
S_HI, S_LO = math.tan(math.radians(25.0)), math.tan(math.radians(6.0))
DAM_X = 170.0


def thalweg(x):
    """Channel-bed height [m] at distance x [m] east of the west edge (120 m at x = 0)."""
    # integral of slope(x) = S_LO + (S_HI - S_LO) (1 - tanh((x - 130) / 15)) / 2
    w = 15.0
    return 120.0 - S_LO * x - (S_HI - S_LO) * 0.5 * (x - w * (np.log(np.cosh((x - 130.0) / w))
                                                         - np.log(np.cosh(-130.0 / w))))


def height(x, y, rng=None):
    z = thalweg(x) + 0.35 * (np.sqrt((y - 50.0) ** 2 + 25.0) - 5.0)
    if rng is not None:
        noise = rng.normal(size=z.shape)
        for _ in range(6):  # smooth: the relief of a real slope, not pixel noise
            noise = (noise + np.roll(noise, 1, 0) + np.roll(noise, -1, 0) + np.roll(noise, 1, 1)
                     + np.roll(noise, -1, 1)) / 5.0
        z = z + 0.3 * noise / noise.std()
    return z


def main():
    import rasterio
    import trimesh
    from rasterio.transform import Affine

    xs = (np.arange(NX) + 0.5) * PIXEL
    ys = (np.arange(NY) + 0.5) * PIXEL
    X, Y = np.meshgrid(xs, ys[::-1])  # rows from north to south
    z = height(X, Y, np.random.default_rng(2026))
    with rasterio.open(HERE / "site.tif", "w", driver="GTiff", height=NY, width=NX, count=1, dtype="float64",
                       crs="EPSG:2056", transform=Affine(PIXEL, 0.0, E0, 0.0, -PIXEL, N0 + NY * PIXEL)) as dst:
        dst.write(z, 1)
    hexagon = [(20.0, 50.0), (27.0, 38.0), (41.0, 38.0), (48.0, 50.0), (41.0, 62.0), (27.0, 62.0), (20.0, 50.0)]
    feature = {"type": "Feature", "properties": {"name": "release", "depth": 2.2},
               "geometry": {"type": "Polygon", "coordinates": [[[E0 + x, N0 + y] for x, y in hexagon]]}}
    (HERE / "release.geojson").write_text(json.dumps({"type": "FeatureCollection", "name": "release",
                                                      "crs": {"type": "name",
                                                              "properties": {"name": "urn:ogc:def:crs:EPSG::2056"}},
                                                      "features": [feature]}, indent=1) + "\n")
    trimesh.creation.box(extents=[2.5, 44.0, 6.0]).export(HERE / "check_dam.stl")
    print(f"site.tif: {NX} x {NY} px of {PIXEL} m, z {z.min():.2f}..{z.max():.2f} m; dam base at "
          f"z = {float(thalweg(DAM_X)):.3f} m (thalweg at x = {DAM_X} m)")


if __name__ == "__main__":
    main()
