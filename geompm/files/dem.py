"""A digital elevation model (DEM) read with rasterio: heights on a regular lattice, with its georeferencing.

GeoTIFF and ESRI ASCII grids (any raster GDAL reads) with a north-up affine
transform (no rotation terms).  Heights are taken at the pixel centres
(GDAL's pixel-is-area convention) and re-ordered so that ``z[i, j]`` is the
height [m] at x = x0 + i dx, y = y0 + j dy, x east and y north, whatever the
file's row order.  The DEM's CRS (as WKT/EPSG text) and affine transform are
kept for the outputs.  NoData cells inside the region the case uses are
refused with the JSON path and the cell's map coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from geompm.errors import CaseError
from geompm.kernels.lattice import bilinear, heights  # noqa: F401 (bilinear: the terrain's import)

#: heights [m] at or below this are a void value, whatever the raster's tags say
VOID_BELOW = -1000.0
#: a height this many reliefs below the region's 1 % height (and 100 m below it at least) is a void value
VOID_RELIEF = 10.0


@dataclass
class Dem:
    z: np.ndarray  # (nx, ny) heights [m] at the pixel centres, x east, y north
    x0: float  # centre of the first pixel [m, map coordinates]
    y0: float
    dx: float  # pixel size [m], > 0
    dy: float
    crs: str | None  # the raster's CRS as text ("EPSG:2056"), None if it has none
    transform: tuple  # the file's affine transform (a, b, c, d, e, f)

    @property
    def upper(self) -> tuple[float, float]:
        return self.x0 + (self.z.shape[0] - 1) * self.dx, self.y0 + (self.z.shape[1] - 1) * self.dy

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Bilinear heights [m] at points (x, y), as the terrain uses them."""
        return heights(self.z, self.x0, self.y0, self.dx, self.dy, np.ascontiguousarray(x, float),
                       np.ascontiguousarray(y, float))


def read_dem(path, where: str, region=None, nodata_as: float | None = None) -> Dem:
    """The DEM of ``path``, cropped to the pixels whose centres lie in ``region`` ((xmin, ymin),
    (xmax, ymax)) plus one pixel; CaseError at ``where`` for a rotated raster or NoData in the crop
    (unless ``nodata_as`` gives the value NoData cells take, e.g. 0 for a thickness raster)."""
    import rasterio

    try:
        src = rasterio.open(path)
    except rasterio.errors.RasterioIOError as exc:
        raise CaseError([(where, f"cannot read the DEM '{path}' ({exc}); give a GeoTIFF or ESRI ASCII grid")]) from None
    with src:
        t = src.transform
        if t.b != 0.0 or t.d != 0.0:
            raise CaseError([(where, f"the DEM '{path}' is rotated (affine terms b = {t.b}, d = {t.d}); "
                                     "warp it north-up first (gdalwarp)")])
        if src.crs is not None and src.crs.is_geographic:
            raise CaseError([(where, geographic_problem(path, src))])
        band = src.read(1, masked=True).astype(float)
        crs = src.crs.to_string() if src.crs else None
        transform = tuple(t)[:6]
    # pixel centres: x = c + (col + 0.5) a, y = f + (row + 0.5) e
    nrow, ncol = band.shape
    xs = t.c + (np.arange(ncol) + 0.5) * t.a
    ys = t.f + (np.arange(nrow) + 0.5) * t.e
    z = np.ma.filled(band, np.nan).T  # (ncol, nrow): [col, row]
    if t.a < 0:
        xs, z = xs[::-1], z[::-1]
    if t.e < 0:  # north-up rasters: rows run south; make y increase with the index
        ys, z = ys[::-1], z[:, ::-1]
    if region is not None:
        (xmin, ymin), (xmax, ymax) = region
        dx, dy = abs(t.a), abs(t.e)
        ix = np.nonzero((xs >= xmin - dx) & (xs <= xmax + dx))[0]
        iy = np.nonzero((ys >= ymin - dy) & (ys <= ymax + dy))[0]
        if len(ix) < 2 or len(iy) < 2:
            raise CaseError([(where, f"the DEM '{path}' covers x {xs.min():.6g}..{xs.max():.6g}, y {ys.min():.6g}.."
                                     f"{ys.max():.6g} m, which does not reach the region x {xmin:.6g}..{xmax:.6g}, "
                                     f"y {ymin:.6g}..{ymax:.6g} m")])
        xs, ys, z = xs[ix[0]:ix[-1] + 1], ys[iy[0]:iy[-1] + 1], z[ix[0]:ix[-1] + 1, iy[0]:iy[-1] + 1]
    if nodata_as is not None:
        z = np.where(np.isfinite(z), z, nodata_as)
    if nodata_as is None:
        void = untagged_voids(z)
        if void is not None:
            i, j = void[0]
            raise CaseError([(where, f"the DEM '{path}' has {len(void)} cell(s) whose height can only be a void value "
                                     f"that the file does not tag as NoData, the first at x = {xs[i]:.3f}, y = "
                                     f"{ys[j]:.3f} (map coordinates) with {z[i, j]:.6g} m: tag it (gdal_edit.py "
                                     f"-a_nodata {z[i, j]:.6g} FILE) and fill the voids (gdal_fillnodata), or clip them "
                                     "away")])
    bad = np.argwhere(~np.isfinite(z))
    if len(bad):
        i, j = bad[0]
        raise CaseError([(where, f"the DEM '{path}' has {len(bad)} NoData cell(s) in the region the case uses, the "
                                 f"first at x = {xs[i]:.3f}, y = {ys[j]:.3f} (map coordinates): fill them (gdal_fillnodata) "
                                 "or shrink the grid / 'clip' to avoid them")])
    return Dem(np.ascontiguousarray(z), float(xs[0]), float(ys[0]), float(abs(t.a)), float(abs(t.e)), crs, transform)


def untagged_voids(z: np.ndarray):
    """Indices (k, 2) of the finite heights that can only be void values (VOID_BELOW, VOID_RELIEF), or None."""
    finite = np.isfinite(z)
    if not finite.any():
        return None
    low, high = np.percentile(z[finite], [1.0, 99.0])
    far_below = low - max(VOID_RELIEF * (high - low), 100.0)
    bad = np.argwhere(finite & ((z <= VOID_BELOW) | (z < far_below)))
    return bad if len(bad) else None


def geographic_problem(path, src) -> str:
    """The message for a DEM in degrees, with the UTM zone of its centre to warp it to."""
    b = src.bounds
    lon, lat = 0.5 * (b.left + b.right), 0.5 * (b.bottom + b.top)
    zone = int(math.floor((lon + 180.0) / 6.0)) % 60 + 1
    epsg = (32600 if lat >= 0 else 32700) + zone
    return (f"the DEM '{path}' is in a geographic CRS ({src.crs.to_string()}: degrees of longitude and latitude), "
            f"but geompm works in metres: warp it to a projected CRS first, e.g. the UTM zone of its centre "
            f"(gdalwarp -t_srs EPSG:{epsg} {path} dem_utm.tif), and give the case's coordinates in it")
