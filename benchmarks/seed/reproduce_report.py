"""Figures and tables of benchmarks/seed/reproduce.py, from its run folders (nothing is run here).

The restatement of the source (docs/source-study.md) does not number its figures; the mapping
used here, by what each of the source's figures shows, is:

- fig02: the inclined-flow column and its deposit (side view; the source's set-up figure);
- fig05_06: X*(T*) and K*(T*) of the inclined flow at the three meshes (the source's mesh study);
- fig07_08: DP against the calibrated Cross fluid, X*(T*) and K*(T*), at each cell size;
- fig11: the calibrated mu_inf against h with its linear fit, beside the source's values.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

import inclined_flow as IF

from geompm.study.calibrate import SOURCE_MU_INF

LABELS = {"explicit": "Cross, explicit", "evp": "Cross, elasto-viscoplastic",
          "evp_fixed_zeta": "Cross, EVP, zeta fixed", "explicit_fixed_zeta": "Cross, explicit, zeta fixed"}


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def inclined_rows(out31: Path) -> list[dict]:
    runs = sorted(r for d in sorted(out31.iterdir()) if (d / "runs").is_dir() for r in (d / "runs").iterdir())
    return [IF.read(r) for r in runs if (r / "status.json").is_file()]


def calibration(out32: Path, name: str) -> dict:
    folder = out32 / name
    with open(folder / "calibration.csv", newline="") as fh:
        rows = {float(r["cell_size"]): r for r in csv.DictReader(fh)}
    return {"folder": folder, "rows": rows, "summary": json.loads((folder / "calibration.json").read_text())}


def fig02(rows: list[dict], png: Path) -> None:
    """Side view (x, y; every particle, all z) of the column at t = 0 and of the deposit at the end at each
    mesh, coloured by displacement, from each run's last checkpoint (p_x0 and p_x; a study keeps no VTU)."""
    plt = _plt()
    runs = IF.baseline(rows)
    fig, axes = plt.subplots(len(runs) + 1, 1, figsize=(9, 1.5 * (len(runs) + 1) + 0.8), sharex=True)
    for k, r in enumerate([runs[0]] + runs):
        ck = sorted((Path(r["run"]) / "checkpoints").glob("step_*.npz"))[-1]
        with np.load(ck) as d:
            x0, x = d["p_x0"], d["p_x"]
        ax = axes[k]
        pts, t = (x0, 0.0) if k == 0 else (x, float(r["series"]["time"][-1]))
        sc = ax.scatter(pts[:, 0], pts[:, 1], c=np.linalg.norm(x - x0, axis=1) if k else np.zeros(len(x0)),
                        s=0.3, cmap="viridis", vmin=0.0, vmax=0.35, rasterized=True)
        ax.set_aspect("equal")
        ax.set_ylim(0, 0.16)
        ax.set_ylabel("y [m]")
        ax.text(0.99, 0.8, f"h = {r['h']:g} m, t = {t:.2f} s", transform=ax.transAxes, ha="right", fontsize=8)
    axes[-1].set_xlabel("x along the 10 deg incline [m]")
    fig.colorbar(sc, ax=axes, label="displacement [m]", shrink=0.8)
    fig.suptitle("inclined flow, DP, 3D: the column (top) and its deposit at each mesh", fontsize=10)
    fig.savefig(png, dpi=130)
    plt.close(fig)


def fig05_06(rows: list[dict], png: Path) -> None:
    IF.plot([r for r in rows if r["E"] == 840000.0 and r["xi"] == 0.001], png)


def fig07_08(cals: dict, png: Path) -> None:
    from geompm.study import metrics as M

    plt = _plt()
    hs = sorted({h for c in cals.values() for h in c["rows"]}, reverse=True)
    fig, axes = plt.subplots(2, len(hs), figsize=(4 * len(hs), 6.5), sharex=True, squeeze=False)
    styles = {"explicit": "--", "evp": ":", "evp_fixed_zeta": "-.", "explicit_fixed_zeta": (0, (1, 3))}
    for j, h in enumerate(hs):
        dp = None
        for name, cal in cals.items():
            r = cal["rows"].get(h)
            if r is None or not r.get("value"):
                continue
            folder = cal["folder"] / f"h{h:g}"
            if dp is None:
                dp, _ = M.read_run(folder / "soil")
                for i, col in enumerate(("X_star", "K_star")):
                    axes[i, j].plot(dp["T_star"], dp[col], "k-", lw=2, label="DP")
            fl, _ = M.read_run(folder / f"fluid_{float(r['value']):.6g}")
            for i, col in enumerate(("X_star", "K_star")):
                axes[i, j].plot(fl["T_star"], fl[col], linestyle=styles[name],
                                label=f"{LABELS[name]}: {float(r['value']):.3g} Pa s")
        axes[0, j].set_title(f"h = {h:g} m")
        axes[1, j].set_xlabel("T* = t sqrt(g/H0)")
        axes[0, j].legend(fontsize=6)
    axes[0, 0].set_ylabel("X* = (x_f - L0)/L0")
    axes[1, 0].set_ylabel("K* = E_k/(M g H0)")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def fig11(cals: dict, png: Path) -> None:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for name, cal in cals.items():
        pts = sorted((h, float(r["value"])) for h, r in cal["rows"].items() if r.get("value"))
        if not pts:
            continue
        line = ax.plot(*zip(*pts), "o", label=LABELS[name])[0]
        fit = cal["summary"].get("fit")
        if fit:
            x = np.linspace(0.0, 0.022, 50)
            ax.plot(x, fit["intercept"] + fit["slope"] * x, "-", lw=0.8, color=line.get_color(),
                    label=f"  fit {fit['intercept']:.3g} + {fit['slope']:.3g} h, R² = {fit['r_squared']:.3f}")
    sh = sorted(SOURCE_MU_INF)
    ax.plot(sh, [SOURCE_MU_INF[h] for h in sh], "s--", color="gray", label="source (sec. 3.2)")
    ax.set_yscale("log")
    ax.set_xlabel("cell size h [m]")
    ax.set_ylabel("calibrated mu_inf [Pa s]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def table_31(rows: list[dict]) -> list[str]:
    from geompm.study.metrics import richardson_order

    lines = ["| run | h [m] | particles | steps | wall [s] | final X* | X*(T* = 3) | K* peak | at T* |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        what = ("shipped" if r["h_ref"] is None and r["E"] == 840000.0 and r["xi"] == 0.001 else
                f"zeta fixed (h_ref {r['h_ref']:g})" if r["h_ref"] else f"E = {r['E']:g} Pa, xi = {r['xi']:g}")
        x3 = float(np.interp(3.0, r["series"]["T_star"], r["series"]["X_star"]))
        lines.append(f"| {what} | {r['h']:g} | {r['particles']} | {r['steps']} | {r['wall_s']:.0f} | "
                     f"{r['final_X']:.3f} | {x3:.3f} | {r['K_peak']:.4f} | {r['T_at_K_peak']:.2f} |")
    for label, group in (("shipped (xi = 0.001)", IF.baseline(rows)),
                         ("zeta fixed", [r for r in IF.baseline(rows) if r["h"] == 0.02]  # h_ref = h there
                          + [r for r in rows if r["h_ref"] == 0.02])):
        group = sorted({r["h"]: r for r in group}.values(), key=lambda r: -r["h"])
        if len(group) < 2:
            continue
        a, b = group[-2], group[-1]
        line = (f"- {label}: the two finest meshes (h = {a['h']:g}, {b['h']:g} m) differ by "
                f"{abs(a['final_X'] - b['final_X']) / abs(b['final_X']):.1%} in final X* and "
                f"{abs(a['K_peak'] - b['K_peak']) / abs(b['K_peak']):.1%} in the K* peak")
        if len(group) >= 3:
            hs = [r["h"] for r in group]
            line += (f"; observed order over {hs}: final X* {richardson_order(hs, [r['final_X'] for r in group]):.2f}, "
                     f"K* peak {richardson_order(hs, [r['K_peak'] for r in group]):.2f} (nan: not monotone)")
        lines.append(line)
    return lines


def table_32(cals: dict) -> list[str]:
    lines = ["| calibration | h [m] | mu_inf [Pa s] | bracket | J | e2(X*) | e2(K*) | runs | status | source [Pa s] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name, cal in cals.items():
        for h, r in sorted(cal["rows"].items(), reverse=True):
            if not r.get("value"):
                lines.append(f"| {name} | {h:g} | - | | | | | | {r['status']} | {SOURCE_MU_INF.get(h, '')} |")
                continue
            f = {k: float(r[k]) for k in ("value", "bracket_low", "bracket_high", "objective", "X_star_error",
                                           "K_star_error")}
            lines.append(f"| {name} | {h:g} | **{f['value']:.4g}** | {f['bracket_low']:.3g} - {f['bracket_high']:.3g} | "
                         f"{f['objective']:.3f} | {f['X_star_error']:.3f} | {f['K_star_error']:.3f} | {r['evaluations']} | "
                         f"{r['status']} | {SOURCE_MU_INF.get(h, '')} |")
    for name, cal in cals.items():
        fit = cal["summary"].get("fit")
        if fit:
            lines.append(f"- {name}: mu_inf = {fit['intercept']:.4g} + {fit['slope']:.4g} h, R^2 = {fit['r_squared']:.4f} "
                         f"over every cell size with a value (bounds included)")
    return lines


def report(out: Path, timing: dict, calibrations: dict) -> None:
    figs = out / "figures"
    figs.mkdir(exist_ok=True)
    rows = inclined_rows(out / "3.1")
    cals = {name: calibration(out / "3.2", name) for name in calibrations if (out / "3.2" / name / "calibration.csv").is_file()}
    IF.summarise([Path(r["run"]) for r in rows], out / "3.1")
    fig02(rows, figs / "fig02_inclined_flow_side_view.png")
    fig05_06(rows, figs / "fig05_06_inclined_flow_meshes.png")
    fig07_08(cals, figs / "fig07_08_dp_vs_cross.png")
    fig11(cals, figs / "fig11_mu_inf_vs_h.png")
    lines = ["# The source study regenerated (benchmarks/seed/reproduce.py)", "",
             f"Wall time: section 3.1 {timing.get('3.1_s', float('nan')):.0f} s, section 3.2 "
             f"{timing.get('3.2_s', float('nan')):.0f} s, on {timing.get('cores')} cores ({timing.get('date')}).", "",
             "## Section 3.1: the inclined flow", "", *table_31(rows), "",
             "## Section 3.2: the DP-Cross calibration", "", *table_32(cals), ""]
    (out / "summary.md").write_text("\n".join(lines))
    print("\n".join(lines))
