"""The saturated-soil verification columns of docs/pore-water.md at three cell sizes each
(geompm/testing/verification/saturated_columns.py): the hydrostatic column, Terzaghi's consolidation (stiff and soft sets),
undrained loading, steady seepage and the undrained P-wave.  One JSON line per run.

    python benchmarks/pore_water/columns.py [hydro|terzaghi|musl|undrained|seepage|wave ...]

(musl: the stiff Terzaghi set in MUSL order, solver.update saturated_musl.)
"""

import json
import sys


from geompm.testing.verification import saturated_columns as ts

SIZES = (0.1, 0.05, 0.025)


def show(label, r):
    print(label, json.dumps(r), flush=True)


def main(which):
    if "hydro" in which:
        for h in SIZES:
            show("hydro", ts.hydrostatic_column(h))
    if "undrained" in which:
        for h in SIZES:
            show("undrained", ts.undrained_column(h))
    if "seepage" in which:
        for h in SIZES:
            show("seepage", ts.seepage_column(h))
    if "wave" in which:
        for h in (0.05, 0.025, 0.0125):
            show("wave", ts.undrained_wave_speed(h))
    if "musl" in which:
        for h in SIZES:
            for r in ts.run_terzaghi(h, update="saturated_musl"):
                show("stiff-musl", r)
    if "terzaghi" in which:
        for soft in (False, True):
            for h in SIZES:
                for r in ts.run_terzaghi(h, soft=soft):
                    show("soft" if soft else "stiff", r)


if __name__ == "__main__":
    main(sys.argv[1:] or ["hydro", "undrained", "seepage", "wave", "terzaghi"])
