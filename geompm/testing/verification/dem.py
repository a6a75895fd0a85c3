"""A GeoTIFF DEM written from a height function, for the terrain, release and hazard-map tests."""

import numpy as np


def write_dem(path, fn, west, south, nx, ny, dx, nodata_at=None, crs="EPSG:2056"):
    """A GeoTIFF of heights fn(x, y) at the pixel centres, north-up, pixel size dx."""
    import rasterio
    from rasterio.transform import Affine

    xs = west + (np.arange(nx) + 0.5) * dx
    ys = south + (np.arange(ny) + 0.5) * dx
    X, Y = np.meshgrid(xs, ys[::-1])  # rows run from north to south
    z = fn(X, Y).astype("float64")
    if nodata_at is not None:
        col = int((nodata_at[0] - west) / dx)
        row = ny - 1 - int((nodata_at[1] - south) / dx)
        z[row, col] = -9999.0
    with rasterio.open(path, "w", driver="GTiff", height=ny, width=nx, count=1, dtype="float64", crs=crs,
                       transform=Affine(dx, 0.0, west, 0.0, -dx, south + ny * dx), nodata=-9999.0) as dst:
        dst.write(z, 1)
    return path
