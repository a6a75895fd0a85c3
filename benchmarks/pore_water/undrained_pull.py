"""Terzaghi's column as an undrained oedometer, pushed and pulled, its side walls ``roller`` and ``slip``, at
three cell sizes (geompm/testing/verification/saturated_columns.oedometer_undrained): the pore pressure
against p = B q in compression and in suction.

    python benchmarks/pore_water/undrained_pull.py > benchmarks/results/<date>-undrained-pull.txt

Measured: with ``roller`` sides (the ring of an oedometer, holding the column laterally both ways) suction is
held as compression is; with ``slip`` sides (one-sided contacts) the pulled column's total lateral stress is
tensile, it leaves the walls and the water relaxes: a boundary effect, not the two-phase step's.  Pulled by
300 kPa, past what the water sustains, the acting pressure is held at the cavitation pressure (-100 kPa) and
the skeleton takes the rest; with the bound off it is B q.
"""

import json

from geompm.testing.verification.saturated_columns import oedometer_undrained


def main():
    for sides in ("roller", "slip"):
        for h in (0.1, 0.05, 0.025):
            for q in (50e3, -50e3):
                print(json.dumps(oedometer_undrained(h, q, sides)), flush=True)
    for h in (0.1, 0.05, 0.025):  # past the water's tension: the cavitation pressure holds, or not
        for cavitation in (None, -1e12):
            print(json.dumps(dict(oedometer_undrained(h, -300e3, cavitation=cavitation),
                                  cavitation=cavitation or "default -100 kPa")), flush=True)


if __name__ == "__main__":
    main()
