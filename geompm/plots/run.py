"""Plots of a run folder (matplotlib, the optional 'plot' extra).

- ``plot_obstacle_forces(series_csv, png)``: every obstacle's force components
  (<name>_fx, _fy, _fz) and normal force (<name>_fn) over time;
- ``plot_series(series_csv, png)``: kinetic energy and front position over time;
- ``plot_deposit(positions, bodies, png)``: particle positions of a 2D run
  (the deposit profile at the last output), coloured by body and named by
  material, with the planes and obstacles drawn;
- ``plot_run(run_dir)``: all of them for ``geompm plot``, with the hazard maps
  (plots/maps.py) and the obstacles' face pressures (plots/pressure.py) when
  the run wrote them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geompm.plots.figure import pyplot, save
from geompm.writers.hazard_maps import HazardMapWriter
from geompm.writers.series import SeriesWriter


PNG_NAMES = ("series.png", "forces.png", "deposit.png", "map_depth_max.png", "map_speed_max.png",
             "map_pressure_max.png", "map_arrival.png", "map_deposit.png",
             "pressure.png")  # what plot_run writes (plots/maps.py, plots/pressure.py)


def _load(series_csv):
    return np.genfromtxt(series_csv, delimiter=",", names=True)


def obstacle_names(columns) -> list[str]:
    return sorted({c[: -len("_fn")] for c in columns if c.endswith("_fn")})


def force_unit(dim: int) -> str:
    """N in 3D; N/m in 2D plane strain (a force per metre of depth)."""
    return "N" if dim == 3 else "N/m"


def plot_obstacle_forces(series_csv: str | Path, png: str | Path, title: str = "", dim: int = 3,
                         peaks: dict | None = None) -> Path:
    """Each obstacle's force components and |F| at the series rows; the peak annotated is status.json's
    (``peaks``: label -> {peak_force, peak_time}), the largest |F| over every step, the figure the
    terminal, `geompm info` and `geompm study` report; without it the largest |F| of the rows."""
    plt = pyplot()
    data = _load(series_csv)
    names = obstacle_names(data.dtype.names)
    if not names:
        raise ValueError(f"{series_csv} has no obstacle force columns (<name>_fn)")
    unit = force_unit(dim)
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    for name in names:
        comps = [c for c in ("fx", "fy", "fz") if f"{name}_{c}" in data.dtype.names]
        mag = np.sqrt(sum(data[f"{name}_{c}"] ** 2 for c in comps))
        for c in comps:
            ax.plot(data["time"], data[f"{name}_{c}"], lw=1.0, ls="--", label=f"{name}_{c}")
        line = ax.plot(data["time"], mag, lw=1.8, label=f"{name} |F|")[0]
        peak = (peaks or {}).get(name)
        if peak is not None:
            f, t, how = float(peak["peak_force"]), float(peak["peak_time"]), "every step"
        else:
            k = int(np.argmax(mag))
            f, t, how = float(mag[k]), float(data["time"][k]), "series rows"
        ax.plot([t], [f], "o", color=line.get_color())
        late = t > 0.5 * (data["time"][0] + data["time"][-1])
        ax.annotate(f"peak |F| {f:.4g} {unit} at {t:.3g} s ({how})", (t, f), textcoords="offset points",
                    xytext=(-12 if late else 12, -14), ha="right" if late else "left")
        if f"{name}_f_filtered" in data.dtype.names:
            ax.plot(data["time"], data[f"{name}_f_filtered"], lw=1.8, color="k", alpha=0.7,
                    label=f"{name} |F| averaged over the force window")
        if peak is not None and "filtered_peak_force" in peak:
            fw, tw = float(peak["filtered_peak_force"]), float(peak["filtered_peak_time"])
            ax.plot([tw], [fw], "s", color="k")
            ax.annotate(f"filtered peak {fw:.4g} {unit} ({1e3 * float(peak['force_window']):.3g} ms window)",
                        (tw, fw), textcoords="offset points", xytext=(-12 if late else 12, 8),
                        ha="right" if late else "left")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"force on the obstacle [{unit}]")
    ax.set_title(title or Path(series_csv).parent.name)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, png)


def plot_series(series_csv: str | Path, png: str | Path, title: str = "", dim: int = 3) -> Path:
    plt = pyplot()
    data = np.atleast_1d(_load(series_csv))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), dpi=120, sharex=True)
    ax1.plot(data["time"], data["kinetic_energy"], color="C0")
    ax1.set_ylabel("kinetic energy [J]" if dim == 3 else "kinetic energy [J/m]")
    fronts = [c for c in data.dtype.names if c.startswith("front_x_body")]
    for k, col in enumerate(fronts or ["front_x"]):
        ax2.plot(data["time"], data[col], color=f"C{k + 1}", label=col)
    if fronts:
        ax2.legend(fontsize=8)
    ax2.set_ylabel("front position x [m]")
    ax2.set_xlabel("time [s]")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    ax1.set_title(title or Path(series_csv).parent.name)
    return save(fig, png)


def plot_deposit(positions: np.ndarray, labels: np.ndarray, png: str | Path, title: str = "",
                 names: dict | None = None, surfaces: list | None = None) -> Path:
    """A 2D run's particles coloured by ``labels`` (``names``: label -> legend text, e.g. the material),
    with the rigid surfaces (``surfaces``: (label, tessellate.Surface) of the planes and obstacles) drawn."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4), dpi=120)
    for b in np.unique(labels):
        sel = labels == b
        ax.scatter(positions[sel, 0], positions[sel, 1], s=2, label=(names or {}).get(int(b), f"body {b}"))
    lo, hi = positions.min(axis=0), positions.max(axis=0)
    for k, (label, surf) in enumerate(surfaces or []):
        seg = surf.vertices[surf.cells][:, :, :2]
        for j, (a, b) in enumerate(seg):
            ax.plot([a[0], b[0]], [a[1], b[1]], color="0.25", lw=2.0, label=label if j == 0 else None,
                    ls=["-", "--", ":", "-."][k % 4])
        lo, hi = np.minimum(lo, seg.reshape(-1, 2).min(axis=0)), np.maximum(hi, seg.reshape(-1, 2).max(axis=0))
    pad = 0.03 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    ax.legend(markerscale=4, fontsize=8)
    return save(fig, png)


def _rigid_surfaces(run_dir: Path) -> list:
    """(label, Surface) of the planes and obstacles of a 2D run, rebuilt from its case.json; [] where the
    case cannot be rebuilt here (a moved run folder whose case refers to files no longer beside it)."""
    import json

    from geompm.api import scene_from_dict
    from geompm.errors import CaseError

    try:
        scene = scene_from_dict(json.loads((run_dir / "case.json").read_text()), run_dir)
    except (CaseError, OSError, ValueError):
        return []
    out = []
    for stage in scene.stages:
        surf = stage.surface()
        if surf is not None and surf.kind == "line":
            out.append((f"{stage.json_path} ({stage.label})", surf))
    return out


def _declared(run_dir: Path, writer, name: str) -> Path:
    """The file ``name`` among a writer's declared ``files`` patterns, in ``run_dir``."""
    pattern = next(p for p in writer.files if p.rsplit("/", 1)[-1] == name)
    return run_dir / pattern


def plot_run(run_dir: str | Path, out_dir: str | Path | None = None) -> list[Path]:
    """PNGs of a run folder: series, obstacle forces, the 2D deposit at the last saved state, and the
    hazard maps over a hillshade when the run wrote them (plots/maps.py)."""
    from geompm.engine import checkpoint

    import json

    run_dir = Path(run_dir)
    out = Path(out_dir) if out_dir else run_dir / "plots"
    out.mkdir(parents=True, exist_ok=True)
    case = json.loads((run_dir / "case.json").read_text()) if (run_dir / "case.json").is_file() else {}
    dim = int(case.get("dimension", 3))
    status = run_dir / "status.json"
    peaks = json.loads(status.read_text()).get("obstacles", {}) if status.is_file() else {}
    series = _declared(run_dir, SeriesWriter, "series.csv")
    made = [plot_series(series, out / "series.png", run_dir.name, dim)]
    if obstacle_names(_load(series).dtype.names):
        made.append(plot_obstacle_forces(series, out / "forces.png", run_dir.name, dim, peaks))
    if checkpoint.newest(run_dir) is not None:
        arrays, meta = checkpoint.load(run_dir)
        if arrays["p_x"].shape[1] == 2:
            materials = [b.get("material", "?") for b in case.get("bodies", [])]
            names = {b: f"bodies.{b}: {m}" for b, m in enumerate(materials)}
            made.append(plot_deposit(arrays["p_x"], arrays["p_body"], out / "deposit.png",
                                     f"{run_dir.name}: particles at t = {meta['time']:.4g} s", names,
                                     _rigid_surfaces(run_dir)))
    if _declared(run_dir, HazardMapWriter, "summary.json").is_file():
        from geompm.plots.maps import plot_maps

        made += plot_maps(run_dir, out)
    from geompm.plots.pressure import PNG_NAME, plot_pressures

    pressure = plot_pressures(run_dir, out / PNG_NAME, run_dir.name)
    from geompm.plots.impact import plot_impact

    impact = plot_impact(peaks, out / "impact.png", run_dir.name, dim)
    return made + [p for p in (pressure, impact) if p is not None]
