"""The loose-versus-dense slope (cases/loose_vs_dense_slope.json) at three cell sizes, loose or dense.

    python benchmarks/pore_water/loose_vs_dense.py --porosity 0.5 [--cells 0.1 0.07 0.05] [--out FILE]

One row per cell size (geompm/testing/verification/loose_dense.run_slope): the failure time, the largest speed
within 1 s of it, the mean speed after it, the base's pore pressure and the excess over the head's hydrostatic
above the held layer, and the time series every 0.5 s.
"""

import argparse

from geompm.testing.rows import emit
from geompm.testing.verification.loose_dense import run_slope


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--porosity", type=float, required=True)
    ap.add_argument("--cells", type=float, nargs="+", default=[0.1, 0.07, 0.05])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    for h in args.cells:
        r = run_slope(args.porosity, h, every=0.5)
        rows = r.pop("rows")
        emit({**r, "series": [[round(float(v), 6) for v in row] for row in rows]}, args.out)


if __name__ == "__main__":
    main()
