"""``geompm plot``'s picture of the face pressures: each obstacle at the step of its peak force.

The last entry of ``surfaces.pvd`` (writers/surfaces.py) holds, per face, the
normal pressure at the step of the largest |F| so far (``pressure_at_peak_force``)
and the running maximum (``max_normal_pressure``).  One panel per obstacle:
in 3D its faces coloured by the pressure at the peak force, upright as gravity
stands (the axis gravity acts along drawn vertical) and seen from the side the
load comes from (the camera along the pressure-weighted mean normal); in
2D its outline coloured the same way.  The title names the peak force's time
and the hot spot (status.json).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

PNG_NAME = "pressure.png"


def last_surfaces(run_dir: Path) -> list[Path]:
    """The files of the last time in surfaces.pvd (one per stage), or [] without one."""
    pvd = run_dir / "surfaces.pvd"
    if not pvd.is_file():
        return []
    rows = re.findall(r'timestep="([^"]+)" group="" part="\d+" file="([^"]+)"', pvd.read_text())
    if not rows:
        return []
    last = max(float(t) for t, _ in rows)
    return [run_dir / f for t, f in rows if float(t) == last]


def plot_pressures(run_dir: Path, png: Path, title: str = "") -> Path | None:
    """The picture, or None if no surface carries pressures."""
    import meshio

    from geompm.plots.figure import pyplot, save

    loaded = []
    for f in last_surfaces(run_dir):
        m = meshio.read(f)
        if "pressure_at_peak_force" in m.cell_data:
            loaded.append((f.stem.rsplit("_", 1)[0], m))
    if not loaded:
        return None
    status = run_dir / "status.json"
    obstacles = json.loads(status.read_text()).get("obstacles", {}) if status.is_file() else {}
    case = run_dir / "case.json"
    gravity = json.loads(case.read_text()).get("gravity") if case.is_file() else None
    plt = pyplot()
    three_d = loaded[0][1].cells[0].type == "triangle"
    fig = plt.figure(figsize=(6.5 * len(loaded), 5), dpi=120)
    for k, (label, m) in enumerate(loaded):
        p = m.cell_data["pressure_at_peak_force"][0]
        cells = m.cells[0].data
        ax = fig.add_subplot(1, len(loaded), k + 1, projection="3d" if three_d else None)
        art = _draw(ax, m.points, cells, p, three_d, m.cell_data["normal"][0], vertical_axis(gravity))
        fig.colorbar(art, ax=ax, shrink=0.7, label="normal pressure at the peak force [Pa]")
        o = obstacles.get(label, {})
        head = f"{label}: peak force at t = {o['peak_time']:.3g} s" if "peak_time" in o else label
        if "peak_pressure" in o:
            at = ", ".join(f"{c:.2f}" for c in o["peak_pressure_at"])
            head += f"\nhot spot {o['peak_pressure']:.3g} Pa at ({at}) m, t = {o['peak_pressure_time']:.3g} s"
        ax.set_title(head, fontsize=9)
    if title:
        fig.suptitle(title)
    return save(fig, png)


def vertical_axis(gravity) -> int:
    """The axis drawn upright: the one gravity acts along (z when there is none)."""
    g = np.asarray(gravity if gravity else [0.0, 0.0, -1.0], float)
    return int(np.argmax(np.abs(g))) if len(g) == 3 and np.any(g) else 2


def _draw(ax, points, cells, p, three_d, normals, up: int = 2):
    """A 3D obstacle is drawn with the axis gravity acts along upright (matplotlib's z): a model with
    gravity along -y stands as it stands in the flume, not on its side."""
    from matplotlib import cm, colors
    from matplotlib.ticker import MaxNLocator

    norm = colors.Normalize(vmin=0.0, vmax=max(float(p.max()), 1e-12))
    if three_d:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        order = [a for a in range(3) if a != up] + [up]
        if up == 1:
            order = [0, 2, 1]  # x, then z across, y up: right-handed seen from the flume's side
        points, normals = points[:, order], normals[:, order]
        tri = points[cells]
        art = Poly3DCollection(tri, facecolors=cm.viridis(norm(p)), edgecolor="none")
        ax.add_collection3d(art)
        lo, hi = points.min(axis=0), points.max(axis=0)
        for a, setl in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
            setl(lo[a], hi[a] if hi[a] > lo[a] else lo[a] + 1e-3)
        ax.set_box_aspect(np.maximum(hi - lo, 1e-3 * (hi - lo).max()))
        view = (np.clip(p, 0.0, None)[:, None] * normals).sum(axis=0)
        if np.linalg.norm(view) > 0.0:
            view /= np.linalg.norm(view)
            ax.view_init(elev=float(np.degrees(np.arcsin(np.clip(view[2], -1, 1)))) + 15.0,
                         azim=float(np.degrees(np.arctan2(view[1], view[0]))) + 30.0)  # three-quarter view:
            # straight along the load the axis across the screen collapses and its ticks overlap
        names = "xyz"
        ax.set_xlabel(f"{names[order[0]]} [m]")
        ax.set_ylabel(f"{names[order[1]]} [m]")
        ax.set_zlabel(f"{names[order[2]]} [m] (up)")
        span = np.maximum(hi - lo, 1e-12)
        for axis, a in zip((ax.xaxis, ax.yaxis, ax.zaxis), range(3)):  # fewer ticks on a short axis
            axis.set_major_locator(MaxNLocator(max(1, int(4 * span[a] / span.max()))))
        ax.tick_params(labelsize=7)
        return cm.ScalarMappable(norm=norm, cmap="viridis")
    from matplotlib.collections import LineCollection

    art = LineCollection(points[cells][:, :, :2], array=p, cmap="viridis", norm=norm, linewidths=4)
    ax.add_collection(art)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    return art
