"""study.csv, study_summary.json and study.png from the finished variants.

study.csv has one row per variant: its varied values, outcome, particles,
cells, cell size [m], steps, wall seconds, particle-steps per second, peak
resident memory [MiB], numba threads, every metric and its error against the
reference (metrics.py).  The summary holds the observed orders of
convergence (three or more cell sizes) and, for sampled studies, the mean,
standard deviation and 5/50/95% quantiles of each scalar metric.
"""

from __future__ import annotations

import csv
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from geompm.study import metrics as M

RESOLUTION_KEY = "grid.cell_size"


def run_row(variant, run_dir: Path, outcome: dict | None) -> tuple[dict, dict | None]:
    """(row of facts about the run, its series or None)."""
    row = {"variant": variant.name, **variant.values, "label": variant.label()}
    try:
        series, status = M.read_run(run_dir)
    except (OSError, ValueError):
        series, status = None, {}
    ok = bool(status.get("finished"))
    if ok:
        row["status"] = "finished"
    elif outcome is not None and outcome.get("error"):
        row["status"] = f"failed (exit {outcome['exit_code']}): {outcome['error']}"
    else:
        row["status"] = "failed: " + (status.get("reason") or "no status.json (killed?)")
    steps, n, wall = status.get("steps"), status.get("particles"), status.get("wall_seconds")
    row.update({
        "particles": n, "cells": status.get("cells"), "cell_size": status.get("cell_size"), "steps": steps,
        "wall_seconds": wall,
        "particle_steps_per_second": (n * steps / wall) if ok and wall else None,
        "peak_memory_mib": status["peak_rss_bytes"] / 2 ** 20 if status.get("peak_rss_bytes") else None,
        "threads": status.get("threads"),
    })
    if ok and series is not None:
        row.update(M.scalar_metrics(series, status))
    return row, (series if ok else None)


def finest(rows: list[dict]) -> int | None:
    """Index of the reference among the finished rows: smallest cell, then most particles, then most steps."""
    done = [i for i, r in enumerate(rows) if r["status"] == "finished"]
    if not done:
        return None
    return min(done, key=lambda i: (rows[i]["cell_size"] or math.inf, -(rows[i]["particles"] or 0),
                                    -(rows[i]["steps"] or 0), i))


def add_errors(rows, series, ref_scalars: dict, ref_series: dict | None, scalar_names, series_names) -> None:
    for row, ser in zip(rows, series):
        if ser is None:
            continue
        for name in scalar_names:
            if name in row and name in ref_scalars:
                row[f"{name}_error"] = M.relative_error(row[name], ref_scalars[name])
        for col in series_names:
            if ref_series is not None:
                row[f"{col}_l2_error"] = M.series_error(ser, ref_series, col)


def convergence_orders(rows, vary_keys, scalar_names, series_names) -> list[dict]:
    """Observed orders per group of variants that differ only in the cell size (three or more)."""
    if RESOLUTION_KEY not in vary_keys:
        return []
    others = [k for k in vary_keys if k != RESOLUTION_KEY]
    groups = defaultdict(list)
    for r in rows:
        if r["status"] == "finished":
            groups[tuple(str(r.get(k)) for k in others)].append(r)
    out = []
    for key, grp in groups.items():
        hs = [r[RESOLUTION_KEY] for r in grp]
        if len(set(hs)) < 3:
            continue
        entry = {"group": dict(zip(others, key)), "cell_sizes": sorted(set(hs))}
        for name in scalar_names:
            vals = [(r[RESOLUTION_KEY], r.get(name)) for r in grp if r.get(name) is not None]
            if len(vals) >= 3:
                entry[f"{name} (Richardson, 3 finest)"] = M.richardson_order([a for a, _ in vals], [b for _, b in vals])
        for name in [f"{n}_error" for n in scalar_names] + [f"{c}_l2_error" for c in series_names]:
            pts = [(r[RESOLUTION_KEY], r.get(name)) for r in grp if r.get(name)]
            if len(pts) >= 2:
                entry[f"{name} (fit against h)"] = M.fitted_order([a for a, _ in pts], [b for _, b in pts])
        out.append(entry)
    return out


def distribution(rows, scalar_names) -> dict:
    """Mean, standard deviation and quantiles of each scalar metric over the finished variants."""
    out = {}
    for name in scalar_names:
        x = np.array([r[name] for r in rows if r["status"] == "finished" and r.get(name) is not None])
        if len(x):
            out[name] = {"n": int(len(x)), "mean": float(x.mean()), "std": float(x.std(ddof=1)) if len(x) > 1 else 0.0,
                         "p05": float(np.quantile(x, 0.05)), "p50": float(np.quantile(x, 0.5)),
                         "p95": float(np.quantile(x, 0.95)), "min": float(x.min()), "max": float(x.max())}
    return out


def write_csv(path: Path, rows: list[dict]) -> None:
    cols = []
    for r in rows:
        cols += [c for c in r if c not in cols]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow({c: _fmt(r.get(c)) for c in cols})


def _fmt(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:.8g}"
    return v


def pareto(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the points no other point beats in both cost and error (lower is better), by cost."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def plot_study(path: Path, rows: list[dict], error_names: list[str], scalar_names: list[str], title: str) -> bool:
    """study.png: error against wall time per metric with the Pareto front, or histograms for a sampled study."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    done = [r for r in rows if r["status"] == "finished"]
    panels = [n for n in error_names if any(r.get(n) for r in done)]
    hist = [] if panels else [n for n in scalar_names if any(r.get(n) is not None for r in done)]
    if not panels and not hist:
        return False
    k = len(panels or hist)
    fig, axes = plt.subplots(1, k, figsize=(4.6 * k, 4.0), squeeze=False)
    for ax, name in zip(axes[0], panels):
        pts = [(r["wall_seconds"], r[name], r) for r in done if r.get(name)]
        for w, e, r in pts:
            ax.loglog(w, e, "o", color="tab:blue")
            ax.annotate(f"{r['variant']} {r['label']}", (w, e), textcoords="offset points", xytext=(4, 3), fontsize=7)
        front = [pts[i] for i in pareto([(w, e) for w, e, _ in pts])]
        ax.loglog([w for w, _, _ in front], [e for _, e, _ in front], "-", color="tab:red", lw=1.2,
                  label="Pareto front")
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(f"{name.replace('_', ' ')} [-]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    for ax, name in zip(axes[0], hist):
        x = [r[name] for r in done if r.get(name) is not None]
        ax.hist(x, bins=max(5, int(math.sqrt(len(x)))), color="tab:blue", alpha=0.8)
        for q, ls in ((0.05, ":"), (0.5, "-"), (0.95, ":")):
            ax.axvline(float(np.quantile(x, q)), color="k", ls=ls, lw=1)
        ax.set_xlabel(name)
        ax.set_ylabel("variants")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True
