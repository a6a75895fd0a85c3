"""A Voellmy dam break on a 30 deg incline (geompm/testing/verification/voellmy_dam_break.py): the depth-averaged
reference on four grids and its extrapolation, against MPM at three cell sizes.
Run: python benchmarks/voellmy/dam_break.py > out.txt"""

import sys
import time

from geompm.testing.verification.voellmy_dam_break import mpm_dam_break, reference

TIMES = (0.25, 0.5, 1.0, 1.5)
NAMES = ("centroid x [m]", "centroid speed [m/s]", "front x [m]")
refs = {}
for cells in (1200, 2400, 4800, 9600):
    t0 = time.perf_counter()
    refs[cells] = reference(TIMES, cells)
    print(f"reference, {cells} cells ({time.perf_counter() - t0:.1f} s): " +
          "; ".join(f"t={r[0]}: " + ", ".join(f"{v:.4f}" for v in r[1:]) for r in refs[cells]))


def extrapolated(k, q):
    """Aitken's extrapolation of the last three grids (a geometric sequence of differences)."""
    a, b, c = (refs[n][k][q] for n in (2400, 4800, 9600))
    d1, d2 = b - a, c - b
    if d1 == 0 or abs(d2 / d1) >= 1 or d1 * d2 <= 0:
        return c
    r = d2 / d1
    return c + d2 * r / (1 - r)


ext = [[extrapolated(k, q) for q in (1, 2, 3)] for k in range(len(TIMES))]
print("extrapolated reference: " + "; ".join(f"t={t}: " + ", ".join(f"{v:.4f}" for v in e) for t, e in zip(TIMES, ext)))
sys.stdout.flush()
for h in (0.05, 0.025, 0.0125):
    t0 = time.perf_counter()
    rows = mpm_dam_break(h, TIMES)
    print(f"\nMPM h = {h} m ({time.perf_counter() - t0:.0f} s, 2 cores)")
    for (t, *vals), e, r in zip(rows, ext, refs[9600]):
        cells = "  ".join(f"{n} {v:.4f} ({100 * (v / x - 1):+.2f} % of extrapolated, {100 * (v / f - 1):+.2f} % of 9600 cells)"
                          for n, v, x, f in zip(NAMES, vals, e, r[1:]))
        print(f"  t = {t}: {cells}")
    sys.stdout.flush()
