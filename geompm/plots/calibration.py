"""calibration.png: soil and best-fit fluid X*(T*) and K*(T*) per cell size, and the fitted parameter against h."""

from __future__ import annotations

import numpy as np


def plot_calibration(path, rows, refs, fluids, fit, name: str, source: dict) -> None:
    """rows: calibration.csv rows; refs and fluids: the soil run's and the best fluid run's series per cell
    size; fit: (a, b, R^2) or None; source: the source study's values per cell size, drawn beside."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, r in enumerate(rows):
        h, c = r["cell_size"], colors[k % len(colors)]
        soil = refs[h]
        fluid = fluids[h]
        for ax, col in zip(axes[:2], ("X_star", "K_star")):
            ax.plot(soil["T_star"], soil[col], "-", color=c, lw=1.5, label=f"DP, h = {h:g} m")
            ax.plot(fluid["T_star"], fluid[col], "--", color=c, lw=1.2, label=f"Cross {name} = {r['value']:.3g}")
    for ax, col in zip(axes[:2], ("X* = (x_f - L0)/L0", "K* = E_k/(M g H0)")):
        ax.set_xlabel("T* = t sqrt(g/H0)")
        ax.set_ylabel(col)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7)
    ax = axes[2]
    hs = np.array([r["cell_size"] for r in rows])
    vals = np.array([r["value"] for r in rows])
    err = np.array([[r["value"] - r["bracket_low"] for r in rows], [r["bracket_high"] - r["value"] for r in rows]])
    ax.errorbar(hs, vals, yerr=err, fmt="o", color="tab:blue", capsize=3, label="geompm (bracket)")
    if fit is not None:
        x = np.linspace(0, hs.max() * 1.1, 50)
        ax.plot(x, fit[0] + fit[1] * x, "-", color="tab:blue", lw=1,
                label=f"fit {fit[0]:.3g} + {fit[1]:.3g} h, R² = {fit[2]:.3f}")
    sh = sorted(source)
    ax.plot(sh, [source[h] for h in sh], "s--", color="tab:gray", label="source study (sec. 3.2)")
    ax.set_xlabel("cell size h [m]")
    ax.set_ylabel(f"{name} [Pa s]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
