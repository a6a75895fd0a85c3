"""The README's three figures: what geompm computes, drawn from runs of three shipped cases.

    python benchmarks/front_door/make.py record RUNS     # run the cases into RUNS and keep what the figures need
    python benchmarks/front_door/make.py draw [OUT]      # draw the figures (default docs/figures) and their manifest

``record`` runs cases/debris_obstacle.json (the main job: debris against the STL check dam),
cases/terrain_debris_flow.json (a debris flow down a DEM catchment, with hazard maps) and cases/dam_break.json
(a water column released against Martin & Moyce's 1952 experiment) with the shipped settings, and writes the
little the figures need into benchmarks/front_door/data/: the dam's faces with the normal pressure at the
peak force, the largest flow depth on the DEM's raster, and the dam break's surge front against time.
``draw`` reads only those files and tests/refdata, so the figures are redrawn in seconds; it writes
docs/figures/front.json, the sha256 of this script and of every file the figures read, which
tests/repository/test_front_door.py compares with the files as they are: a figure whose script or data
changed without being redrawn fails the test.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"
FIGURES = ROOT / "docs" / "figures"
REFDATA = ROOT / "tests" / "refdata"
#: the figures, in the README's order, and the files each reads
FIGURE_INPUTS = {
    "front_dam_pressure.png": ["dam_faces.npz", "dam_status.json"],
    "front_hazard_map.png": ["terrain_depth_max.npz"],
    "front_dam_break.png": ["dam_break_front.csv", "refdata:dambreak_martin_moyce1952_n2_2_a2.25in.csv",
                            "refdata:dambreak_martin_moyce1952_n2_2_a1.125in.csv"],
}
#: the dam break's column width a [m] and gravity [m/s2] (cases/dam_break.json; docs/validation/dam-break.md)
DAM_BREAK_A, G = 0.1, 9.81


def input_path(name: str) -> Path:
    return REFDATA / name.split(":", 1)[1] if name.startswith("refdata:") else DATA / name


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def manifest() -> dict:
    """{figure: {input name: sha256}} and the script's own sha256: what the figures were drawn from."""
    return {"script": sha256(Path(__file__)),
            "figures": {fig: {name: sha256(input_path(name)) for name in names}
                        for fig, names in FIGURE_INPUTS.items()}}


# -- record -------------------------------------------------------------------------------------------------
class Finished:
    def __init__(self, folder: Path):
        self.folder = folder
        self.status = json.loads((folder / "status.json").read_text())


def finished_run(case: str, runs: Path) -> Finished:
    """The run of cases/<case>.json in runs/<case>: the one there if it finished, else a new one."""
    from geompm.api import run

    folder = runs / case
    status = folder / "status.json"
    if not (status.is_file() and json.loads(status.read_text()).get("finished")):
        run(ROOT / "cases" / f"{case}.json", out=folder, quiet=True, overwrite=folder.exists())
    return Finished(folder)


def record(runs: Path) -> None:
    import meshio

    from geompm.plots.pressure import last_surfaces

    DATA.mkdir(exist_ok=True)
    dam = finished_run("debris_obstacle", runs)
    faces = [f for f in last_surfaces(dam.folder) if f.stem.startswith("dam")]
    m = meshio.read(faces[0])
    np.savez_compressed(DATA / "dam_faces.npz", points=m.points, triangles=m.cells[0].data,
                        pressure=m.cell_data["pressure_at_peak_force"][0], normal=m.cell_data["normal"][0])
    keep = {k: dam.status["obstacles"]["dam"][k] for k in ("peak_force", "peak_time", "peak_pressure",
                                                           "peak_pressure_at", "peak_pressure_time")}
    (DATA / "dam_status.json").write_text(json.dumps(keep, indent=1) + "\n")

    terrain = finished_run("terrain_debris_flow", runs)
    import rasterio

    with rasterio.open(terrain.folder / "maps" / "depth_max.tif") as src:
        depth, bounds = src.read(1), src.bounds
    with rasterio.open(ROOT / "cases" / "terrain" / "site.tif") as src:
        ground = src.read(1)
    np.savez_compressed(DATA / "terrain_depth_max.npz", depth_max=depth.astype(np.float32),
                        ground=ground.astype(np.float32),
                        bounds=np.array([bounds.left, bounds.bottom, bounds.right, bounds.top]))

    dam_break = finished_run("dam_break", runs)
    rows = np.genfromtxt(dam_break.folder / "series.csv", delimiter=",", names=True)
    with open(DATA / "dam_break_front.csv", "w") as fh:
        fh.write("# cases/dam_break.json as shipped (h = 5 mm): the surge front x [m] against time t [s]\n")
        fh.write("time_s,front_x_m\n")
        for t, x in zip(rows["time"], rows["front_x"]):
            fh.write(f"{t:.6g},{x:.6g}\n")


# -- draw ---------------------------------------------------------------------------------------------------
def draw_dam_pressure(png: Path, plt) -> None:
    d = np.load(DATA / "dam_faces.npz")
    status = json.loads((DATA / "dam_status.json").read_text())
    pts, tri, p = d["points"], d["triangles"], d["pressure"] / 1e3
    fig = plt.figure(figsize=(6.4, 4.2), dpi=110)
    ax = fig.add_subplot(1, 1, 1)
    # the upstream face seen from upstream: y across the flume, z up
    loaded = d["normal"][:, 0] < -0.5
    from matplotlib.collections import PolyCollection

    polys = PolyCollection([pts[t][:, 1:3] for t in tri[loaded]], array=p[loaded], cmap="viridis",
                           edgecolors="face")
    ax.add_collection(polys)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_xlabel("y across the flume [m]")
    ax.set_ylabel("z [m]")
    fig.colorbar(polys, ax=ax, label="normal pressure at the peak force [kPa]", shrink=0.8)
    ax.set_title(f"Debris on an STL check dam: face pressures at the peak force\n"
                 f"(t = {status['peak_time']:.2f} s, |F| = {status['peak_force']:.0f} N; "
                 f"hot spot {status['peak_pressure'] / 1e3:.1f} kPa)", fontsize=10)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


def draw_hazard_map(png: Path, plt) -> None:
    d = np.load(DATA / "terrain_depth_max.npz")
    left, bottom, right, top = d["bounds"]
    depth = np.ma.masked_less_equal(d["depth_max"], 0.0)
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    extent = (left - left, right - left, bottom - bottom, top - bottom)
    levels = np.arange(np.floor(d["ground"].min() / 6.0) * 6.0, d["ground"].max() + 6.0, 6.0)
    cs = ax.contour(d["ground"], levels=levels, colors="0.6", linewidths=0.5, extent=extent, origin="upper")
    ax.clabel(cs, fontsize=6, fmt="%.0f")
    im = ax.imshow(depth, extent=extent, origin="upper", cmap="magma_r")
    fig.colorbar(im, ax=ax, label="largest flow depth [m]", shrink=0.8)
    ax.set_xlabel(f"easting - {left:.0f} [m]")
    ax.set_ylabel(f"northing - {bottom:.0f} [m]")
    ax.set_title("A debris flow down a DEM catchment: the depth hazard map\n(a GeoTIFF on the DEM's raster; "
                 "ground contours every 6 m)", fontsize=10)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


def draw_dam_break(png: Path, plt) -> None:
    sim = np.genfromtxt(DATA / "dam_break_front.csv", delimiter=",", skip_header=2)
    T = sim[:, 0] * math.sqrt(2 * G / DAM_BREAK_A)
    Z = sim[:, 1] / DAM_BREAK_A
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    ax.plot(T, Z, "-", color="C0", label="geompm, h = 5 mm (cases/dam_break.json)")
    for name, mark in (("a2.25in", "o"), ("a1.125in", "s")):
        ref = np.genfromtxt(REFDATA / f"dambreak_martin_moyce1952_n2_2_{name}.csv", delimiter=",", skip_header=3)
        ax.plot(ref[:, 0], ref[:, 1], mark, mfc="none", color="k",
                label=f"Martin & Moyce (1952), a = {name[1:].replace('in', ' in')}")
    ax.set_xlim(0, 3.5)
    ax.set_ylim(1, 4.5)
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("surge front Z = z/a")
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title("Dam break against Martin & Moyce (1952): the front leads by 9-17 %,\n"
                 "within 2.5 % after one time offset (docs/validation/dam-break.md)", fontsize=10)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


DRAW = {"front_dam_pressure.png": draw_dam_pressure, "front_hazard_map.png": draw_hazard_map,
        "front_dam_break.png": draw_dam_break}


def draw(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    for name, fn in DRAW.items():
        fn(out / name, plt)
    (out / "front.json").write_text(json.dumps(manifest(), indent=1) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("record", help="run the three cases and keep the figures' data")
    r.add_argument("runs", type=Path, help="folder for the three run folders")
    d = sub.add_parser("draw", help="draw the figures from the kept data")
    d.add_argument("out", type=Path, nargs="?", default=FIGURES)
    args = parser.parse_args(argv)
    if args.cmd == "record":
        record(args.runs)
    else:
        draw(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
