"""``geompm plot``'s design picture of each obstacle: the normal pressure over its height at the filtered
peak (averaged over the force window, contact/impact_design.pressure_profile) beside the hydrostatic and
hydrodynamic pressures of the approach flow its probe measured, and the design numbers."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geompm.plots.figure import pyplot, save


def plot_impact(obstacles: dict, png: Path, title: str = "", dim: int = 3) -> Path | None:
    """The picture from status.json's ``obstacles`` entries, or None when none has a pressure profile."""
    shown = {k: o for k, o in obstacles.items() if o.get("pressure_profile")}
    if not shown:
        return None
    plt = pyplot()
    unit = "N" if dim == 3 else "N/m"
    fig, axes = plt.subplots(1, len(shown), figsize=(5 * len(shown), 4.5), dpi=120, squeeze=False)
    for ax, (name, o) in zip(axes[0], shown.items()):
        prof = np.asarray(o["pressure_profile"], float)
        ax.plot(prof[:, 1] / 1e3, prof[:, 0], "o-", label="geompm, window mean at the filtered peak")
        lines = [f"filtered peak {o['filtered_peak_force']:.4g} {unit}, window {1e3 * o['force_window']:.3g} ms",
                 f"impulse {o['impulse']:.4g} {unit} s, load at the end {o['final_force']:.4g} {unit}"]
        if "hydrostatic_ratio" in o:
            h, v, rho = o["probe_depth"], o["probe_speed"], o["probe_density"]
            g = 9.81
            z = np.linspace(0.0, h, 20)
            ax.plot(rho * g * (h - z) / 1e3, z, "--", label="hydrostatic rho g (h - z), k = 1")
            ax.axvline(rho * v * v / 1e3, ls=":", color="C2", label="rho v^2 (alpha = 1)")
            lines.append(f"h = {h:.3g} m, v = {v:.3g} m/s: alpha = {o['alpha']:.3g}, k = {o['hydrostatic_ratio']:.3g}")
        ax.set_xlabel("normal pressure [kPa]")
        ax.set_ylabel("height above the lowest loaded face [m]")
        ax.set_title(f"{name}: " + "\n".join(lines), fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    return save(fig, png)
