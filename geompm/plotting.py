"""Plots of a run's series.csv (matplotlib, the optional 'plot' extra).

``plot_obstacle_forces(series_csv, png)`` draws every obstacle's force
components (<name>_fx, _fy, _fz) and normal force (<name>_fn) over time.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _load(series_csv):
    return np.genfromtxt(series_csv, delimiter=",", names=True)


def obstacle_names(columns) -> list[str]:
    return sorted({c[: -len("_fn")] for c in columns if c.endswith("_fn")})


def plot_obstacle_forces(series_csv: str | Path, png: str | Path, title: str = "") -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
    fig.tight_layout()
    png = Path(png)
    fig.savefig(png)
    plt.close(fig)
    return png
