"""The pore-water verification columns run by both two-phase schemes side by side, at three cell sizes each
(geompm/testing/verification/saturated_columns.py; docs/pore-water.md, The semi-implicit step): the
hydrostatic column, Terzaghi's consolidation (stiff and soft sets) with water's real bulk modulus 2.2e9 Pa and
with incompressible water (semi-implicit only), undrained loading and steady seepage.  One JSON line per run,
with the steps and the wall time.

    python benchmarks/pore_water/semi_implicit_columns.py [hydro|terzaghi|undrained|seepage|quadratic ...]
"""

import json
import sys
import time

from geompm.testing.verification import saturated_columns as ts

SIZES = (0.1, 0.05, 0.025)
EXPLICIT, IMPLICIT = "saturated", "saturated_semi_implicit"
WATERS = ((EXPLICIT, 2.2e9), (IMPLICIT, 2.2e9), (IMPLICIT, "incompressible"))


def show(label, update, kw, r, t0):
    r = dict(r, scheme=update, kw=kw, wall=round(time.perf_counter() - t0, 2))
    print(label, json.dumps(r), flush=True)


def sizes(label, update, kw, run):
    """``run(h)`` at each cell size, one line each."""
    for h in SIZES:
        t0 = time.perf_counter()
        show(label, update, kw, run(h), t0)


def main(which):
    columns = {"hydro": lambda u, k: lambda h: ts.hydrostatic_column(h, update=u, kw=k),
               "hydro-quadratic": lambda u, k: lambda h: ts.hydrostatic_column(h, update=u, kw=k, shape="quadratic"),
               "undrained": lambda u, k: lambda h: ts.undrained_column(h, update=u, kw=k),
               "seepage": lambda u, k: lambda h: ts.seepage_column(h, update=u, kw=k)}
    for label, run in columns.items():
        if label.replace("hydro-quadratic", "quadratic") in which:
            for update, kw in WATERS:
                sizes(label, update, kw, run(update, kw))
    if "terzaghi" in which:
        for soft in (False, True):
            for update, kw in WATERS:
                for h in SIZES:
                    t0 = time.perf_counter()
                    for r in ts.run_terzaghi(h, tvs=(0.1, 0.2, 0.5, 1.0), soft=soft, update=update, kw=kw):
                        show("soft" if soft else "stiff", update, kw, r, t0)


if __name__ == "__main__":
    main(sys.argv[1:] or ["hydro", "undrained", "seepage", "terzaghi", "quadratic"])
