"""Ensemble hazard maps of a study: where and how hard a flow reaches, over the finished variants.

Each variant of a case with a ``hazard_maps`` writer leaves maps/depth_max.tif, speed_max.tif and
pressure_max.tif on the DEM's raster (writers/hazard_maps.py; NoData where its flow never reached
``depth_threshold``).  Over the n finished variants, cell by cell:

    probability_of_reach = (variants whose flow reached the cell) / n                       [-]
    <map>_p<q>           = the q-th percentile of the variants' values, 0 where one did not reach

(linear interpolation between order statistics, numpy's default: with 12 runs, p90 lies between the 10th
and 11th largest).  Both are NoData where no variant reached.  The files go to ``<study>/maps/`` with the
variants' CRS and transform, each band described with its quantity and unit; variants whose rasters differ
(a varied DEM, coarsen) are refused rather than resampled.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geompm.files.atomic import atomic_path
from geompm.writers.hazard_maps import NODATA, UNITS

#: the maps a study combines and the percentiles it writes of each
QUANTITIES = ("depth_max", "speed_max", "pressure_max")
PERCENTILES = (50, 90)


def _read(path: Path):
    import rasterio

    with rasterio.open(path) as src:
        return src.read(1), src.profile.copy()


def ensemble_maps(out: Path, run_dirs: list[Path]) -> dict | None:
    """Write the ensemble maps of the runs in ``run_dirs`` that have maps to ``out/maps``; a summary of them
    (files, runs, areas [m2]) or None when no run has maps."""
    runs = [Path(d) for d in run_dirs if (Path(d) / "maps" / "depth_max.tif").is_file()]
    if not runs:
        return None
    stacks, profile = {}, None
    for q in QUANTITIES:
        layers = []
        for d in runs:
            data, prof = _read(d / "maps" / f"{q}.tif")
            if profile is None:
                profile = prof
            elif (prof["transform"], prof["crs"], prof["width"], prof["height"]) != \
                    (profile["transform"], profile["crs"], profile["width"], profile["height"]):
                raise ValueError(f"the hazard maps of {d.name} lie on another raster than those of {runs[0].name} "
                                 "(a varied DEM or coarsen): ensemble maps need one raster")
            layers.append(data)
        stacks[q] = np.stack(layers)
    reached = stacks["depth_max"] != NODATA
    count = reached.sum(axis=0)
    never = count == 0
    folder = Path(out) / "maps"
    folder.mkdir(exist_ok=True)
    written = []

    def write(name, data, unit):
        band = np.where(never, NODATA, data)
        with atomic_path(folder / f"{name}.tif") as tmp:
            import rasterio

            with rasterio.open(tmp, "w", **{**profile, "dtype": "float64", "nodata": NODATA, "count": 1}) as dst:
                dst.write(band, 1)
                dst.set_band_description(1, f"{name} [{unit}]")
                dst.update_tags(1, quantity=name, units=unit, runs=str(len(runs)))
        written.append(f"maps/{name}.tif")

    probability = count / len(runs)
    write("probability_of_reach", probability, "-")
    for q in QUANTITIES:
        values = np.where(stacks[q] == NODATA, 0.0, stacks[q])
        for p in PERCENTILES:
            write(f"{q}_p{p}", np.percentile(values, p, axis=0), UNITS[q])
    t = profile["transform"]
    cell = abs(t.a * t.e)
    return {"runs": len(runs), "files": written,
            "area_reached_by_any_m2": float((count > 0).sum() * cell),
            "area_reached_by_half_m2": float((probability >= 0.5).sum() * cell),
            "area_reached_by_all_m2": float((count == len(runs)).sum() * cell)}
