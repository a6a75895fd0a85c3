"""What a study measures in each run, and how far it is from a reference.

Scalar metrics (one number per run):
- ``runout``: ``deposit_front`` [m] at the last row of series.csv when the
  series writer has ``deposit_threshold`` (a thickness front, robust to
  outlier particles); else, with several bodies, the front of the body whose
  front moved furthest (a slide's toe, not the edge of the ground under it);
  else ``front_x`` (the furthest particle);
- ``runout:body<b>``, ``runout:<material>``: the last front of each body and
  each material, where the case has more than one;
- ``height``: ``deposit_height`` [m] at the last row (the deposit's largest
  thickness, averaged over a window as wide as the threshold), when written;
- ``peak_force:LABEL``: the largest |F| [N; N/m in 2D] on obstacle LABEL, taken
  every step (status.json), not only at output times;
- ``impulse:LABEL``: the integral of |F| from first contact to the end [N s;
  N s/m in 2D], summed over every step (status.json; before it was recorded
  there, the trapezoid rule over the series.csv rows);
- ``filtered_peak_force:LABEL``: the peak of the force averaged over the
  obstacle's force window (contact/impact.py) [N; N/m in 2D];
- ``final_force:LABEL``: the window-averaged force at the end, the deposit's
  static load [N; N/m in 2D];
- ``alpha:LABEL``, ``hydrostatic_ratio:LABEL``: the filtered peak as the
  hydrodynamic and hydrostatic coefficients of the approach flow its probe
  measured (contact/impact_design.py) [-];
- with hazard maps (writers/hazard_maps.py, maps/summary.json): ``impact_area`` [m2],
  ``runout_length`` (horizontal, from the release's top) and ``runout_thalweg``
  (along the line of steepest descent from it) [m], ``travel_angle`` [deg] and
  ``deposit_volume`` [m3].
The obstacles that are a ground (``status.json``'s ``grounds``: a terrain) give no
force metrics: the weight and friction of a flow on the ground it runs over is no
design load.

Time-series metrics: ``front_x``, ``kinetic_energy`` and any other series.csv
column (``X_star``, ``K_star``, ...).  Their error is the relative L2 norm

    e = sqrt( int (a(t) - r(t))^2 dt / int r(t)^2 dt )

over the times both runs cover, with ``a`` interpolated linearly to the
reference's times.  Scalar errors are relative: |a - r| / |r|.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from geompm.writers.series import read_series

SERIES_DEFAULT = ("front_x", "kinetic_energy")
#: the hazard maps' summary entries (writers/hazard_maps.py) a study reports, by the metric name it gives them
MAP_METRICS = {"impact_area_m2": "impact_area", "runout_length_m": "runout_length",
               "runout_thalweg_m": "runout_thalweg", "travel_angle_deg": "travel_angle",
               "deposit_volume_m3": "deposit_volume"}
#: status.json's impact entries that a study can ask for per obstacle (contact/impact.py, impact_design.py)
IMPACT_METRICS = ("filtered_peak_force", "final_force", "alpha", "hydrostatic_ratio")


def obstacle_labels(series: dict) -> list[str]:
    return sorted(c[:-3] for c in series if c.endswith("_fx"))


def force_magnitude(series: dict, label: str) -> np.ndarray:
    comps = [series[f"{label}_f{c}"] for c in "xyz" if f"{label}_f{c}" in series]
    return np.sqrt(sum(f ** 2 for f in comps))


def body_fronts(series: dict) -> list[tuple[str, float, float]]:
    """(column, first value, last value) of each per-body and per-material front column of series.csv
    (``front_x_body<b>``, ``front_x_<material>``; written where a case has more than one)."""
    out = []
    for col in series:
        if col.startswith("front_x_") and len(series[col]):
            x = series[col][np.isfinite(series[col])]
            if len(x):
                out.append((col, float(x[0]), float(x[-1])))
    return out


def moving_front(series: dict) -> tuple[str, float, float] | None:
    """The body front that moved furthest (column, first, last): a slide's toe rather than the edge of
    the ground it rests on; None with a single body."""
    bodies = [f for f in body_fronts(series) if f[0].startswith("front_x_body")]
    return max(bodies, key=lambda f: f[2] - f[1]) if bodies else None


def scalar_metrics(series: dict, status: dict | None = None) -> dict[str, float]:
    out = {}
    moving = moving_front(series)
    if "deposit_front" in series and len(series["deposit_front"]):  # the robust front when written
        out["runout"] = float(series["deposit_front"][-1])
    elif moving is not None:
        out["runout"] = moving[2]
    elif "front_x" in series and len(series["front_x"]):
        out["runout"] = float(series["front_x"][-1])
    for col, _, last in body_fronts(series):
        out[f"runout:{col[len('front_x_'):]}"] = last
    if "deposit_height" in series and len(series["deposit_height"]):
        out["height"] = float(series["deposit_height"][-1])
    peaks = (status or {}).get("obstacles", {})
    grounds = set((status or {}).get("grounds", ()))
    for key, value in ((status or {}).get("maps") or {}).items():
        if key in MAP_METRICS and isinstance(value, (int, float)):
            out[MAP_METRICS[key]] = float(value)
    for label in obstacle_labels(series):
        if label in grounds:  # the force on the ground a flow runs over is no design load
            continue
        f = force_magnitude(series, label)
        mine = peaks.get(label, {})
        out[f"peak_force:{label}"] = float(mine["peak_force"]) if "peak_force" in mine else float(f.max())
        out[f"impulse:{label}"] = float(mine["impulse"]) if "impulse" in mine else _integral(f, series["time"])
        for key in IMPACT_METRICS:
            if key in mine:
                out[f"{key}:{label}"] = float(mine[key])
    return out


def read_run(run_dir: str | Path) -> tuple[dict, dict]:
    """(series columns, status) of a run folder; the hazard maps' summary, if written, as status["maps"]."""
    run_dir = Path(run_dir)
    status_file = run_dir / "status.json"
    status = json.loads(status_file.read_text()) if status_file.is_file() else {}
    maps = run_dir / "maps" / "summary.json"
    if maps.is_file():
        status["maps"] = json.loads(maps.read_text())
    return read_series(run_dir / "series.csv"), status


def series_error(run: dict, ref: dict, column: str) -> float:
    """Relative L2 distance of ``run[column]`` from ``ref[column]`` over their common times."""
    if column not in run or column not in ref:
        return math.nan
    t_ref, r = ref["time"], ref[column]
    t_run = run["time"]
    if len(t_run) < 2 or len(t_ref) < 2:
        return math.nan
    inside = (t_ref >= t_run[0]) & (t_ref <= t_run[-1])
    if inside.sum() < 2:
        return math.nan
    t = t_ref[inside]
    a = np.interp(t, t_run, run[column])
    r = r[inside]
    num = _integral((a - r) ** 2, t)
    den = _integral(r ** 2, t)
    return math.sqrt(num / den) if den > 0 else math.sqrt(num)


def _integral(y, t) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)))


def relative_error(value: float, ref: float) -> float:
    if value is None or ref is None or not math.isfinite(value) or not math.isfinite(ref):
        return math.nan
    return abs(value - ref) / abs(ref) if ref != 0 else abs(value - ref)


def richardson_order(h: list[float], f: list[float], iterations: int = 50) -> float:
    """Observed order p from three solutions f at cell sizes h (any order, h distinct).

    Celik et al. (2008) J. Fluids Eng. 130:078001, eqs. 3-5, which allow a
    non-constant refinement ratio:  p = |ln|e32/e21| + q(p)| / ln r21,
    q(p) = ln((r21^p - s) / (r32^p - s)), s = sign(e32/e21), with h1 < h2 < h3,
    e21 = f2 - f1, e32 = f3 - f2, r21 = h2/h1, r32 = h3/h2.  NaN when the
    differences vanish or change sign (oscillatory convergence).
    """
    (h1, f1), (h2, f2), (h3, f3) = sorted(zip(h, f))[:3]
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0 or e32 == 0 or e32 / e21 < 0:
        return math.nan
    r21, r32 = h2 / h1, h3 / h2
    s = 1.0
    p = abs(math.log(abs(e32 / e21))) / math.log(r21)
    for _ in range(iterations):
        try:
            q = math.log((r21 ** p - s) / (r32 ** p - s))
        except (ValueError, ZeroDivisionError, OverflowError):
            return math.nan
        p = abs(math.log(abs(e32 / e21)) + q) / math.log(r21)
    return p


def fitted_order(h: list[float], err: list[float]) -> float:
    """Slope of log(error) against log(h): the order of the error against a finer reference."""
    pts = [(a, b) for a, b in zip(h, err) if a > 0 and b is not None and math.isfinite(b) and b > 0]
    if len(pts) < 2 or len({a for a, _ in pts}) < 2:
        return math.nan
    x, y = np.log([a for a, _ in pts]), np.log([b for _, b in pts])
    return float(np.polyfit(x, y, 1)[0])
