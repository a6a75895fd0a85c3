"""A saturated column fed from below by a held head, at three cell sizes (geompm/testing/verification/head_column.py).

    python benchmarks/pore_water/head_column.py [--out FILE]

Rows: cell size, conductivity, the base's head, the mean pore pressure at 0.1 / 0.25 / 0.5 / 0.75 m against the
steady closed form, and the discharge against Darcy's k (H - L) / L: a steady head of 1.5 m on a 1 m column
(upward seepage, gradient 0.5) at h = 0.1 / 0.05 / 0.025 m, the same with the head raised from 1.0 to 1.5 m
over the first 0.3 s, and the head at the top (no flow).
"""

import argparse

from geompm.testing.rows import emit
from geompm.testing.verification.head_column import run_column


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    for h in (0.1, 0.05, 0.025):
        for label, head, times in (("steady", 1.5, (0.0,)), ("rising", (1.0, 1.5), (0.0, 0.3)),
                                   ("at_top", 1.0, (0.0,))):
            r = run_column(h, 1e-3, head, times, end=1.0)
            emit({"case": label, "h": h, "k": 1e-3, "head": r["head"],
                  "p_measured": [round(float(v), 1) for v in r["measured"]],
                  "p_closed": [round(float(v), 1) for v in r["closed"]],
                  "error_pct": [round(100 * float(v), 2) for v in r["error"]],
                  "flux": r["flux"], "flux_closed": r["flux_closed"]}, args.out)


if __name__ == "__main__":
    main()
