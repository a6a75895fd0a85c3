"""Release bodies from GIS files: the mass of a mapped landslide or debris-flow source (3D, set-up only).

Each gives a bounding box and a membership test for the particle lattice (setup/bodies.py):

- ``release_polygon``: points over the area of a GeoJSON polygon (Polygon or
  MultiPolygon features; holes by the even-odd rule) and between the DEM
  surface H(x, y) and H + t, t the uniform ``thickness`` or each feature's
  ``thickness_attribute``.  The thickness is measured vertically (the usual
  mapped "release depth" of practice tools is slope-normal; divide it by
  cos(slope) to give it here);
- ``release_raster``: H < z < H + T(x, y), T the thickness raster
  (bilinear between its pixel centres; NoData and values <= 0: no release);
- ``between_surfaces``: H_f(x, y) < z < H(x, y), the failure surface H_f and
  the pre-event ground H, two DEMs (the set-up of D-Claw's Oso 2014 case);
  use the failure surface as the terrain so that it becomes the sliding bed.

H is the terrain's bilinear height (files/dem.py), so particles fill
from exactly the surface the contact uses.
"""

from __future__ import annotations

import json

import numpy as np

from geompm.errors import CaseError
from geompm.files.atomic import case_relative, unreadable_file
from geompm.setup.polygon import points_in_polygon
from geompm.setup.release_crs import in_case_crs


def _raster(base_dir, name, where, nodata_as=None):
    from geompm.files.dem import read_dem

    path = case_relative(base_dir, name)
    problem = unreadable_file(path, name)
    if problem:
        raise CaseError([(where, f"raster {problem}")])
    return read_dem(path, where, nodata_as=nodata_as)


def _polygons(path, thickness, attribute, where):
    """([(rings, thickness)], the GeoJSON's data) of a GeoJSON file: each polygon as a list of (k, 2) rings."""
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise CaseError([(where, f"cannot read the GeoJSON '{path.name}': {exc}")]) from None
    features = data.get("features", [data]) if isinstance(data, dict) else []
    out = []
    for k, feat in enumerate(features):
        geom = feat.get("geometry", feat) if isinstance(feat, dict) else None
        kind = geom.get("type") if isinstance(geom, dict) else None
        if kind not in ("Polygon", "MultiPolygon"):
            continue
        t = thickness
        if attribute is not None:
            t = (feat.get("properties") or {}).get(attribute)
            if not isinstance(t, (int, float)) or not t > 0:
                raise CaseError([(where, f"feature {k} of '{path.name}': property '{attribute}' = {t!r} must be a "
                                         "thickness > 0 [m]")])
        polys = geom["coordinates"] if kind == "MultiPolygon" else [geom["coordinates"]]
        for poly in polys:
            out.append(([np.asarray(ring, float)[:, :2] for ring in poly], float(t)))
    if not out:
        raise CaseError([(where, f"'{path.name}' holds no Polygon or MultiPolygon feature")])
    return out, data


class Release:
    """A release's membership test, ``contains(pts)``, from its columns: bottom(x, y) < z < top(x, y), with
    top = -inf where nothing is released (set-up's checks read the columns: release_checks.py)."""

    def __init__(self, bottom, top, lo, hi):
        self.bottom, self.top = bottom, top
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)  # its bounding box [m]

    def region(self):
        """(lo, hi, contains), as body_region gives it."""
        return self.lo, self.hi, self

    def columns(self, x, y):
        """(bottom, top) heights [m] of the release's columns at (x, y); top = -inf outside it."""
        return self.bottom(x, y), self.top(x, y)

    def __call__(self, pts):
        bottom, top = self.columns(pts[:, 0], pts[:, 1])
        return (pts[:, 2] > bottom) & (pts[:, 2] < top)


def release_region(geom, base_dir, json_path: str, crs: str | None = None):
    """(lo, hi, contains) of a release geometry, ``contains`` a Release; ``crs`` the case's (a GeoJSON in
    another is reprojected)."""
    if geom.type == "between_surfaces":
        top = _raster(base_dir, geom.surface, f"{json_path}.surface")
        bed = _raster(base_dir, geom.failure_surface, f"{json_path}.failure_surface")
        return Release(bed.height, top.height, [bed.x0, bed.y0, bed.z.min()], [*bed.upper, top.z.max()]).region()
    dem = _raster(base_dir, geom.dem, f"{json_path}.dem")
    if geom.type == "release_raster":
        t = _raster(base_dir, geom.file, f"{json_path}.file", nodata_as=0.0)

        def top_of(x, y):
            thick = t.height(x, y)
            return np.where(thick > 0.0, dem.height(x, y) + thick, -np.inf)
        thick_max = float(t.z.max())
        if thick_max <= 0.0:
            raise CaseError([(f"{json_path}.file", "the thickness raster has no value > 0: nothing to release")])
        return Release(dem.height, top_of, [t.x0, t.y0, dem.z.min()], [*t.upper, dem.z.max() + thick_max]).region()
    path = case_relative(base_dir, geom.file)
    where = f"{json_path}.file"
    problem = unreadable_file(path, geom.file)
    if problem:
        raise CaseError([(where, f"GeoJSON {problem}")])
    if (geom.thickness is None) == (geom.thickness_attribute is None):
        raise CaseError([(json_path, "give exactly one of 'thickness' [m] and 'thickness_attribute'")])
    polys, data = _polygons(path, geom.thickness, geom.thickness_attribute, where)
    polys, moved = in_case_crs(polys, data, crs, dem, geom.file, where)
    allv = np.concatenate([r for rings, _ in polys for r in rings])
    lo_xy, hi_xy = allv.min(axis=0), allv.max(axis=0)
    if lo_xy[0] < dem.x0 or lo_xy[1] < dem.y0 or hi_xy[0] > dem.upper[0] or hi_xy[1] > dem.upper[1]:
        frame = moved or f" (in the case's {crs})" if crs else moved
        raise CaseError([(where, f"the release area (x {lo_xy[0]:.12g}..{hi_xy[0]:.12g}, y {lo_xy[1]:.12g}.."
                                 f"{hi_xy[1]:.12g} m){frame} reaches outside the DEM (x {dem.x0:.12g}..{dem.upper[0]:.12g}, "
                                 f"y {dem.y0:.12g}..{dem.upper[1]:.12g} m, {dem.crs or 'no CRS'}): check the "
                                 "GeoJSON's CRS and the DEM's")])

    def top_of(x, y):
        xy = np.column_stack([x, y])
        ground = dem.height(x, y)
        top = np.full(len(xy), -np.inf)
        for rings, t in polys:
            inside = np.zeros(len(xy), dtype=bool)
            for ring in rings:
                inside ^= points_in_polygon(xy, ring)
            top = np.where(inside, np.maximum(top, ground + t), top)
        return top
    t_max = max(t for _, t in polys)
    return Release(dem.height, top_of, np.r_[lo_xy, dem.z.min()], np.r_[hi_xy, dem.z.max() + t_max]).region()
