"""PNGs of a run's hazard maps (writers/hazard_maps.py) over a hillshade of the DEM, for `geompm plot`.

Each map is drawn in map coordinates [m] over the DEM's hillshade (illumination from azimuth 315 deg,
altitude 45 deg, the cartographic convention; Horn's gradient by central differences), masked where
the flow never reached the map's threshold, with a colour bar in the map's unit and a scale bar.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

#: the maps drawn, with their colour-bar labels
DRAWN = {"depth_max": "maximum flow depth [m]", "speed_max": "maximum speed [m/s]",
         "pressure_max": "maximum dynamic pressure rho v^2 [kPa]", "arrival": "arrival time [s]",
         "deposit": "deposit depth [m]"}


def hillshade(z: np.ndarray, dx: float, dy: float, azimuth: float = 315.0, altitude: float = 45.0) -> np.ndarray:
    """Shade in [0, 1] of a north-up raster z (rows from north to south)."""
    gy, gx = np.gradient(z, dy, dx)
    gy = -gy  # rows run south: d/dnorth = -d/drow
    slope = np.arctan(np.hypot(gx, gy))
    aspect = np.arctan2(-gx, gy)
    az, alt = math.radians(azimuth), math.radians(altitude)
    shade = np.sin(alt) * np.cos(slope) + np.cos(alt) * np.sin(slope) * np.cos(az - aspect)
    return np.clip(shade, 0.0, 1.0)


def plot_maps(run_dir: str | Path, out: Path) -> list[Path]:
    import rasterio
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    from geompm.plots.figure import pyplot, save

    plt = pyplot()
    maps = Path(run_dir) / "maps"
    summary = json.loads((maps / "summary.json").read_text())
    threshold = summary.get("depth_threshold", 0.0)
    shade = None
    dem = summary.get("dem")
    if dem and Path(dem).is_file():
        with rasterio.open(dem) as src:
            t = src.transform
            shade = hillshade(src.read(1).astype(float), abs(t.a), abs(t.e))
            shade_extent = (t.c, t.c + src.width * t.a, t.f + src.height * t.e, t.f)
    made = []
    for name, label in DRAWN.items():
        with rasterio.open(maps / f"{name}.tif") as src:
            data = src.read(1, masked=True).astype(float)
            depth = rasterio.open(maps / "depth_max.tif").read(1)
            t = src.transform
            extent = (t.c, t.c + src.width * t.a, t.f + src.height * t.e, t.f)
        data = np.ma.masked_where(np.ma.getmaskarray(data) | (depth < max(threshold, 1e-12)), data)
        if name == "pressure_max":
            data = data / 1e3
        fig, ax = plt.subplots(figsize=(9, 4.6))
        if shade is not None:
            ax.imshow(shade, cmap="gray", extent=shade_extent, vmin=0, vmax=1)
        im = ax.imshow(data, cmap="viridis" if name == "arrival" else "magma_r", extent=extent, alpha=0.85)
        fig.colorbar(im, ax=ax, label=label, shrink=0.85)
        width = extent[1] - extent[0]
        bar = 10 ** math.floor(math.log10(width / 4))
        ax.add_artist(AnchoredSizeBar(ax.transData, bar, f"{bar:g} m", "lower right", frameon=True))
        ax.set_xlabel(f"easting [m] ({summary.get('crs') or 'no CRS'})")
        ax.set_ylabel("northing [m]")
        ax.ticklabel_format(useOffset=False, style="plain")
        ax.set_title(f"{Path(run_dir).name}: {label}")
        made.append(save(fig, out / f"map_{name}.png"))
    return made
