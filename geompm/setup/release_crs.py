"""The coordinate reference system of a release GeoJSON, and its polygons brought into the case's.

- A ``crs`` member (GeoJSON 2008: ``{"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2056"}}``,
  as QGIS writes it) names the file's CRS: its coordinates are reprojected to the case's ``crs``
  (rasterio.warp.transform, PROJ), or refused when the case states none.
- Without one, RFC 7946 says WGS 84 longitude and latitude: in a case that states its ``crs``, coordinates
  that fall outside the DEM as they are but within +-180 / +-90 are read as degrees (QGIS's default
  export) and reprojected the same way; coordinates that fall on the DEM, and every coordinate of a case
  without a ``crs`` (a local frame), are taken as the case's own.
Every refusal names both CRSs.
"""

from __future__ import annotations

import numpy as np

from geompm.errors import CaseError

WGS84 = "EPSG:4326"


def member_crs(data: dict) -> str | None:
    """The CRS text of a GeoJSON's ``crs`` member ("EPSG:2056"), or None without one."""
    member = data.get("crs") if isinstance(data, dict) else None
    if not isinstance(member, dict):
        return None
    name = (member.get("properties") or {}).get("name")
    if not isinstance(name, str):
        return None
    if name.startswith("urn:ogc:def:crs:"):
        parts = name.split(":")
        if parts[4:5] == ["EPSG"] or "EPSG" in parts:
            return f"EPSG:{parts[-1]}"
        if parts[-1] in ("CRS84", "CRS83"):
            return WGS84 if parts[-1] == "CRS84" else "EPSG:4269"
    return name


def _reproject(polys, src: str, dst: str, where: str):
    from rasterio.crs import CRS
    from rasterio.errors import CRSError
    from rasterio.warp import transform

    try:
        src_crs, dst_crs = CRS.from_user_input(src), CRS.from_user_input(dst)
    except CRSError as exc:
        raise CaseError([(where, f"the GeoJSON's CRS '{src}' is not one GDAL knows ({exc})")]) from None
    out = []
    for rings, t in polys:
        moved = []
        for ring in rings:
            xs, ys = transform(src_crs, dst_crs, ring[:, 0].tolist(), ring[:, 1].tolist())
            moved.append(np.column_stack([xs, ys]))
        out.append((moved, t))
    return out


def in_case_crs(polys, data: dict, case_crs: str | None, dem, name: str, where: str):
    """``polys`` ([(rings, thickness)]) in the case's CRS, and a note of where they came from ('' when taken
    as they are)."""
    allv = np.concatenate([r for rings, _ in polys for r in rings])
    src = member_crs(data)
    if src is None:
        lo, hi = allv.min(axis=0), allv.max(axis=0)
        on_dem = lo[0] >= dem.x0 and lo[1] >= dem.y0 and hi[0] <= dem.upper[0] and hi[1] <= dem.upper[1]
        degrees = np.all(np.abs(allv[:, 0]) <= 180.0) and np.all(np.abs(allv[:, 1]) <= 90.0)
        if on_dem or not degrees or case_crs is None:  # without a case CRS, the case's own local frame
            return polys, ""
        src = WGS84
        why = "has no 'crs' member and its coordinates look like longitude and latitude (RFC 7946: WGS 84)"
    else:
        why = f"states its CRS as {src}"
    if case_crs is None:
        raise CaseError([(where, f"'{name}' {why}, but the case states no \"crs\" to bring it into: set the case's "
                                 "\"crs\" (the DEM's, e.g. \"EPSG:2056\")")])
    from rasterio.crs import CRS

    if CRS.from_user_input(src) == CRS.from_user_input(case_crs):
        return polys, ""
    return _reproject(polys, src, case_crs, where), f" (reprojected from {src} to the case's {case_crs})"
