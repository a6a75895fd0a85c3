"""What `geompm stability` leaves: stability.json, the failure mechanism as VTU and PNG, the terminal lines."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np

from geompm.files.atomic import atomic_path
from geompm.stability import slip


def write_mechanism(out: Path, run_dir: Path, title: str, dim: int = 2, cell_size: float = 1.0,
                    duration: float = 1.0, circle=None, vertical: int | None = None) -> list[str]:
    """mechanism.vtu (the failed trial's last VTU: displacement and every state variable, the plastic shear
    strain among them), slip_surface.csv (the band of largest plastic shear strain rate over the trial's last
    quarter: slip.py) and mechanism.png (2D: particles coloured by plastic strain and by displacement, the slip
    surface over them, and the limit-equilibrium ``circle`` (x_c, y_c, R) [m] where given); the names of the
    files written."""
    files = sorted((run_dir / "particles").glob("particles_*.vtu"))
    if not files:
        return []
    src = files[-1]
    with atomic_path(out / "mechanism.vtu") as tmp:
        shutil.copyfile(src, tmp)
    made = ["mechanism.vtu"]
    surface = None
    if len(files) >= 2:
        x, rate = slip.plastic_rate(files[-2], src, duration / 4.0)
        surface = slip.slip_surface(x, rate, dim, cell_size, vertical=vertical)
        slip.write_csv(out / "slip_surface.csv", surface, dim)
        made.append("slip_surface.csv")
    try:
        made += _png(out / "mechanism.png", src, title, surface if dim == 2 else None, circle)
    except ImportError:
        print("mechanism.png not drawn: install matplotlib (python -m pip install 'geompm[plot]')")
    return made


def _png(png: Path, vtu: Path, title: str, surface=None, circle=None) -> list[str]:
    import meshio

    from geompm.plots.figure import pyplot, save

    mesh = meshio.read(vtu)
    x = mesh.points
    disp = np.linalg.norm(np.asarray(mesh.point_data["displacement"]), axis=1)
    strain = np.asarray(mesh.point_data.get("plastic_strain", np.zeros(len(x))))
    plt = pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(8.0, 7.0), sharex=True)
    size = max(0.5, min(8.0, 2e4 / max(len(x), 1)))
    for ax, value, label in ((axes[0], strain, "equivalent plastic shear strain [-]"),
                             (axes[1], disp, "displacement [m]")):
        sc = ax.scatter(x[:, 0], x[:, 1], c=value, s=size, cmap="viridis", linewidths=0)
        fig.colorbar(sc, ax=ax, label=label)
        if surface is not None and len(surface):
            ax.plot(surface[:, 0], surface[:, 1], "r-", lw=1.2, label="slip surface (largest plastic strain rate)")
        if circle is not None:
            xc, yc, r = circle
            t = np.linspace(0.0, 2.0 * np.pi, 721)
            cx, cy = xc + r * np.cos(t), yc + r * np.sin(t)
            inside = (cx >= x[:, 0].min()) & (cx <= x[:, 0].max()) & (cy >= x[:, 1].min()) & (cy <= x[:, 1].max())
            ax.plot(np.where(inside, cx, np.nan), np.where(inside, cy, np.nan), "w--", lw=1.2,
                    label=f"limit-equilibrium circle ({xc:g}, {yc:g}) m, R = {r:g} m")
        if surface is not None or circle is not None:
            ax.legend(fontsize=7, loc="upper right")
        ax.set_aspect("equal")
        ax.set_ylabel("y [m]")
    axes[1].set_xlabel("x [m]")
    axes[0].set_title(title, fontsize=9)
    with atomic_path(png) as tmp:
        save(fig, tmp)
    return ["mechanism.png"]


def print_result(summary: dict) -> None:
    fos, (lo, hi) = summary["factor_of_safety"], summary["bracket"]
    if fos is not None:
        verdict = "the slope fails as it stands (F < 1)" if hi <= 1.0 else (
            "stable" if lo >= 1.0 else "at its limit")
        print(f"factor of safety  F = {fos:.3f}, bracket [{lo:.4g}, {hi:.4g}] (tolerance {summary['tolerance']:g}): "
              f"{verdict}")
    else:
        print(f"factor of safety  {summary['bound']} (no bracket inside the searched range)")
    for t in summary["trials"]:
        state = "failed" if t["failed"] else "stable"
        if t.get("error"):
            print(f"  F = {t['factor']:.4f}  failed  the run stopped: {t['error'][-160:]}")
            continue
        r = t["ratio"]
        print(f"  F = {t['factor']:.4f}  {state:6}  increment ratio {r:.3g}  "
              f"last increment {t['last_increment']:.3g} m  u_max {t['max_displacement']:.3g} m  "
              f"E_k end/peak {t['kinetic_energy_ratio']:.2g}  ({t['wall_seconds']:.1f} s)"
              if math.isfinite(r) else f"  F = {t['factor']:.4f}  {state}")
    if summary.get("mechanism"):
        print(f"mechanism         {', '.join(summary['mechanism'])} (the trial at F = {summary['mechanism_factor']:.4f})")


def print_info(folder: Path) -> None:
    """`geompm info` of a stability folder: the factor of safety, its bracket and the trials' count."""
    import json

    summary = json.loads((folder / "stability.json").read_text())
    print(f"stability    {folder} (case {summary['case']})")
    fos, (lo, hi) = summary["factor_of_safety"], summary["bracket"]
    if fos is not None:
        print(f"factor of safety  F = {fos:.3f}, bracket [{lo:.4g}, {hi:.4g}]")
    else:
        print(f"factor of safety  {summary['bound']}")
    c = summary["criterion"]
    print(f"trials       {len(summary['trials'])}, {c['duration_s']:g} s each, viscous damping {c['damping_rate']:.3g} "
          f"1/s" + (f" and local damping alpha {c['local_damping']:g}" if c["local_damping"] else "")
          + f"; failed when the largest displacement's last-quarter increment was >= {c['ratio']:g} of the one "
          "before")
    if summary.get("mechanism"):
        print(f"mechanism    {', '.join(summary['mechanism'])} (F = {summary['mechanism_factor']:.4f})")
