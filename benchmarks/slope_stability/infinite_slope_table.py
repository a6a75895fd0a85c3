"""The infinite-slope tables of docs/slope-stability.md: `geompm stability` at three cell sizes against the
closed forms, and the factor's sensitivity to the trials' local damping and to the failure criterion.

    python benchmarks/slope_stability/infinite_slope_table.py OUT_FOLDER [main|sensitivity] > table.txt

Cases (geompm/testing/verification/slopes.py): beta = 20 deg, phi = 30 deg, 1 m deep, gamma = 2000 x 9.81 N/m3.
  associated (psi = phi), c = 0:        F = tan(phi) / tan(beta) = 1.5863
  associated, c = 2 kPa:                F = c / (gamma z cos^2 beta tan beta) + tan(phi) / tan(beta) = 1.9035
  psi = 0, c = 0 (Mohr-Coulomb):        Davis (1968): the slip plane carries tan(phi*) = sin(phi) cos(psi) /
                                        (1 - sin(phi) sin(psi)), so F solves sin(atan(tan(phi) / F)) = tan(beta):
                                        F = 1.4774
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time
from pathlib import Path

from geompm.testing.verification.slopes import infinite_slope_case, limit_equilibrium


def davis(beta=20.0, phi=30.0):
    return math.tan(math.radians(phi)) / math.tan(math.asin(math.tan(math.radians(beta))))


def run(out: Path, name: str, case: dict, *args) -> dict:
    path = out / f"{name}.json"
    path.write_text(json.dumps(case, indent=1))
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "geompm.cli", "stability", str(path), "--out", str(out / name),
                           "--overwrite", "--quiet", "--json", "--workers", "2", "--threads", "1", *args],
                          capture_output=True, text=True)
    if proc.returncode:
        raise SystemExit(proc.stderr)
    s = json.loads(proc.stdout.strip().splitlines()[-1])
    s["wall"] = time.perf_counter() - t0
    return s


def line(label, s, ref):
    lo, hi = s["bracket"]
    steps = 0
    for t in s["trials"]:
        rows = Path(t["run_dir"], "series.csv").read_text().splitlines()
        steps += int(rows[-1].split(",")[1])
    f = s["factor_of_safety"]
    return (f"{label:34s} F = {f:.4f} [{lo:.4f}, {hi:.4f}]  reference {ref:.4f}  error {100 * (f / ref - 1):+.2f} %  "
            f"{len(s['trials'])} trials, {steps} steps, {s['wall']:.0f} s")


def column(model: str, dilation: float, tau, beta=20.0, phi=30.0, depth=1.0, duration=2.0) -> float:
    """The one-dimensional column's factor for the same trial (geompm/testing/verification/slope_column.py)."""
    from geompm.contract.registry import get
    from geompm.testing.verification.slope_column import column_factor

    params = dict(density=2000.0, youngs_modulus=2e6, poisson_ratio=0.3, friction_angle=phi,
                  dilation_angle=dilation, cohesion=0.0, dilation_cutoff=1.0)
    return column_factor(get("materials", model), params, low=1.0, high=2.5, elements=40, slope=beta,
                         depth=depth, duration=duration, viscoplastic_time=tau)[0]


def regularised(out: Path) -> None:
    """psi = 0 with the trials' default viscoplastic time (duration / 800) against the column's factor with the
    same regularisation, at three cell sizes; the set-up of a 0.2 m strip; the steep associated slope."""
    print("reference: the column's factor (slope_column.py, 40 elements) with the same viscoplastic time\n")
    for model in ("mohr_coulomb", "drucker_prager"):
        ref = column(model, 0.0, 0.0025)
        print(f"{model} psi = 0: column {ref:.4f} (inviscid {column(model, 0.0, None):.4f}, Davis {davis():.4f})")
        for h in (0.1, 0.05, 0.025):
            name = f"reg_{model}_psi0_{h:g}"
            print(line(f"  h = {h:g} m", run(out, name, infinite_slope_case(h, dilation=0.0, model=model)), ref),
                  flush=True)
    strip_and_steep(out)


def strip_and_steep(out: Path) -> None:
    """The 0.2 m strip (psi = 0) at h = 0.02 / 0.01 / 0.005 m, and the steep associated slope with trials of 2 s
    and of 4 s (the column: a 2 s trial stops 3-4 % short of the closed form on this slope)."""
    ref = column("mohr_coulomb", 0.0, 0.0025, depth=0.2)
    print(f"0.2 m strip, mohr_coulomb psi = 0: column {ref:.4f} (0.2 m deep)")
    for h in (0.02, 0.01, 0.005):
        name = f"reg_strip_{h:g}"
        print(line(f"  h = {h:g} m", run(out, name, infinite_slope_case(h, dilation=0.0, model="mohr_coulomb",
                                                                        depth=0.2)), ref), flush=True)
    closed = limit_equilibrium(36, 40, 0)
    for duration in (2.0, 4.0):
        ref = column("drucker_prager", 40.0, duration / 800.0, beta=36.0, phi=40.0, duration=duration)
        print(f"steep associated slope (beta 36, phi 40), T = {duration:g} s: tan(phi)/tan(beta) = {closed:.4f}, "
              f"column {ref:.4f} ({100 * (ref / closed - 1):+.2f} %)")
        for h in (0.1, 0.05, 0.025):
            name = f"reg_steep_{h:g}_T{duration:g}"
            s = run(out, name, infinite_slope_case(h, slope=36.0, friction=40.0, dilation=40.0, end=duration))
            print(line(f"  h = {h:g} m", s, closed) + f"  against the column {100 * (s['factor_of_safety'] / ref - 1):+.2f} %",
                  flush=True)


def main():
    out = Path(sys.argv[1])
    part = sys.argv[2] if len(sys.argv) > 2 else "main"
    out.mkdir(parents=True, exist_ok=True)
    print("2-core development machine, 2 trials in flight, 1 thread each; tolerance 0.01; trials T = 2 s unless "
          "said (F0 for T/4, ramp over T/4, hold T/2), viscous damping 40 / T, increment ratio 0.5 unless said\n")
    cases = (("associated, c = 0", {}, limit_equilibrium(20, 30, 0)),
             ("associated, c = 2 kPa", {"cohesion": 2000.0}, limit_equilibrium(20, 30, 2000)),
             ("psi = 0, c = 0 (Mohr-Coulomb, Davis)", {"dilation": 0.0, "model": "mohr_coulomb"}, davis()))
    if part == "main":
        for label, kw, ref in cases:
            for duration in ((2.0, 4.0) if "associated" in label else (2.0,)):
                for h in (0.1, 0.05, 0.025):
                    name = f"{label.split(',')[0].replace(' ', '_').replace('=', '')}_{kw.get('cohesion', 0):g}_{h:g}_T{duration:g}"
                    print(line(f"{label}, T = {duration:g} s, h = {h:g} m",
                               run(out, name, infinite_slope_case(h, end=duration, **kw)), ref), flush=True)
        return
    if part == "regularised":
        regularised(out)
        return
    if part == "strip_and_steep":
        strip_and_steep(out)
        return
    label, kw, ref = cases[1]
    print(f"failure criterion: increment ratio ({label}, h = 0.05 m):")
    for r in (0.5, 0.7, 0.9):
        print(line(f"ratio = {r:g}", run(out, f"ratio_{r:g}", infinite_slope_case(0.05, **kw), "--ratio", str(r)), ref),
              flush=True)
    print(f"\ntrial duration and damping rate ({label}, h = 0.05 m):")
    for extra in (("--duration", "4"), ("--damping-rate", "10"), ("--damping-rate", "40")):
        print(line(" ".join(extra), run(out, "_".join(extra).strip("-"), infinite_slope_case(0.05, **kw), *extra), ref),
              flush=True)
    print(f"\nCundall local damping added to the viscous one ({label}):")
    for h in (0.1, 0.05, 0.025):
        print(line(f"alpha = 0.02, h = {h:g} m", run(out, f"local_{h:g}", infinite_slope_case(h, **kw),
                                                      "--local-damping", "0.02"), ref), flush=True)

if __name__ == "__main__":
    main()
