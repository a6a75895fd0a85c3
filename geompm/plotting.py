"""Plots of a run folder (matplotlib, the optional 'plot' extra).

- ``plot_obstacle_forces(series_csv, png)``: every obstacle's force components
  (<name>_fx, _fy, _fz) and normal force (<name>_fn) over time;
- ``plot_series(series_csv, png)``: kinetic energy and front position over time;
- ``plot_deposit(positions, bodies, png)``: particle positions of a 2D run
  (the deposit profile at the last output), coloured by body;
- ``plot_run(run_dir)``: all of them for ``geompm plot``, with the hazard maps
  (maps_plot.py) and the obstacles' face pressures (pressure_plot.py) when
  the run wrote them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


PNG_NAMES = ("series.png", "forces.png", "deposit.png", "map_depth_max.png", "map_speed_max.png",
             "map_pressure_max.png", "map_arrival.png", "map_deposit.png",
             "pressure.png")  # what plot_run writes (maps_plot.py, pressure_plot.py)


def _load(series_csv):
    return np.genfromtxt(series_csv, delimiter=",", names=True)


def obstacle_names(columns) -> list[str]:
    return sorted({c[: -len("_fn")] for c in columns if c.endswith("_fn")})


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, png) -> Path:
    png = Path(png)
    fig.tight_layout()
    fig.savefig(png)
    fig.clf()
    _pyplot().close(fig)
    return png


def plot_obstacle_forces(series_csv: str | Path, png: str | Path, title: str = "") -> Path:
    plt = _pyplot()
    data = _load(series_csv)
    names = obstacle_names(data.dtype.names)
    if not names:
        raise ValueError(f"{series_csv} has no obstacle force columns (<name>_fn)")
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    for name in names:
        for comp in ("fx", "fy", "fz", "fn"):
            col = f"{name}_{comp}"
            if col in data.dtype.names:
                ax.plot(data["time"], data[col], lw=1.8 if comp == "fn" else 1.0,
                        ls="-" if comp == "fn" else "--", label=col)
        k = int(np.argmax(data[f"{name}_fn"]))
        ax.annotate(f"peak {data[f'{name}_fn'][k]:.0f} N at {data['time'][k]:.2f} s",
                    (data["time"][k], data[f"{name}_fn"][k]), textcoords="offset points", xytext=(12, -14))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("force on the obstacle [N]")
    ax.set_title(title or Path(series_csv).parent.name)
    ax.grid(alpha=0.3)
    ax.legend()
    return _save(fig, png)


def plot_series(series_csv: str | Path, png: str | Path, title: str = "") -> Path:
    plt = _pyplot()
    data = np.atleast_1d(_load(series_csv))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), dpi=120, sharex=True)
    ax1.plot(data["time"], data["kinetic_energy"], color="C0")
    ax1.set_ylabel("kinetic energy [J, J/m in 2D]")
    ax2.plot(data["time"], data["front_x"], color="C1")
    ax2.set_ylabel("front position x [m]")
    ax2.set_xlabel("time [s]")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    ax1.set_title(title or Path(series_csv).parent.name)
    return _save(fig, png)


def plot_deposit(positions: np.ndarray, bodies: np.ndarray, png: str | Path, title: str = "") -> Path:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 4), dpi=120)
    for b in np.unique(bodies):
        sel = bodies == b
        ax.scatter(positions[sel, 0], positions[sel, 1], s=2, label=f"body {b}")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    ax.legend(markerscale=4)
    return _save(fig, png)


def plot_run(run_dir: str | Path, out_dir: str | Path | None = None) -> list[Path]:
    """PNGs of a run folder: series, obstacle forces, the 2D deposit at the last saved state, and the
    hazard maps over a hillshade when the run wrote them (maps_plot.py)."""
    from .engine import checkpoint

    run_dir = Path(run_dir)
    out = Path(out_dir) if out_dir else run_dir / "plots"
    out.mkdir(parents=True, exist_ok=True)
    series = run_dir / "series.csv"
    made = [plot_series(series, out / "series.png", run_dir.name)]
    if obstacle_names(_load(series).dtype.names):
        made.append(plot_obstacle_forces(series, out / "forces.png", run_dir.name))
    if checkpoint.newest(run_dir) is not None:
        arrays, meta = checkpoint.load(run_dir)
        if arrays["p_x"].shape[1] == 2:
            made.append(plot_deposit(arrays["p_x"], arrays["p_body"], out / "deposit.png",
                                     f"{run_dir.name}: particles at t = {meta['time']:.4g} s"))
    if (run_dir / "maps" / "summary.json").is_file():
        from .maps_plot import plot_maps

        made += plot_maps(run_dir, out)
    from .pressure_plot import PNG_NAME, plot_pressures

    pressure = plot_pressures(run_dir, out / PNG_NAME, run_dir.name)
    return made + ([pressure] if pressure is not None else [])
