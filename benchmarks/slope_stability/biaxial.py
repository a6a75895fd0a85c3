"""The softening biaxial test of docs/slope-stability.md: the platen force against its displacement at
several cell sizes, with the softening regularised by the cell size and without.

    python benchmarks/slope_stability/biaxial.py OUT_FOLDER [h ...] > biaxial.txt
    GEOMPM_BIAXIAL_TAU=0.001 python benchmarks/slope_stability/biaxial.py ...   (the laws' viscoplastic time [s])
    GEOMPM_BIAXIAL_ONLY=plain ...   (only the set whose softening thresholds are strains, not scaled by the cell)

Case: geompm/testing/verification/slopes.biaxial_case (a 1 m x 2 m sample, c softening from 100 to 50 kPa, phi = 0, a weak
corner, a smooth platen at 0.02 m/s).  Printed: the peak force [N/m] and the force at platen displacements
of 10 to 30 mm, and each curve's largest difference from the finest one's over 12-30 mm, relative to the
finest one's force there.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

from geompm.testing.verification.slopes import biaxial_case

import geompm

SPEED = 0.02
AT = np.array([0.010, 0.012, 0.016, 0.020, 0.025, 0.030])


TAU = float(os.environ.get("GEOMPM_BIAXIAL_TAU", "0")) or None


def curve(out: Path, h: float, ref: float | None) -> tuple[np.ndarray, np.ndarray, float]:
    t0 = time.perf_counter()
    run = geompm.run(biaxial_case(h, ref, viscoplastic_time=TAU), out=out / f"h{h:g}_{'reg' if ref else 'plain'}",
                     overwrite=True, progress=False, quiet=True)
    assert run.exit_code == 0, run.exit_code
    s = run.series
    return s["time"] * SPEED, np.asarray(s["platen_fy"]), time.perf_counter() - t0


def main():
    out = Path(sys.argv[1])
    hs = [float(x) for x in sys.argv[2:]] or [0.2, 0.1, 0.05]
    print(__doc__.strip().splitlines()[0])
    print(f"2-core development machine, one run at a time; viscoplastic time {TAU or 'none'} s\n")
    sets = ((0.05, "regularised (reference_cell_size 0.05 m)"), (None, "not regularised"))
    if os.environ.get("GEOMPM_BIAXIAL_ONLY") == "plain":
        sets = sets[1:]
    for ref, label in sets:
        print(label)
        curves = {h: curve(out, h, ref) for h in hs}
        fine = curves[min(hs)]
        window = (fine[0] >= 0.012) & (fine[0] <= 0.030)
        for h in hs:
            u, f, wall = curves[h]
            at = np.interp(AT, u, f)
            diff = np.max(np.abs(np.interp(fine[0][window], u, f) - fine[1][window]) / np.abs(fine[1][window]))
            print(f"  h = {h:<6g} peak {f.max() / 1e3:7.1f} kN/m at {1e3 * u[np.argmax(f)]:5.1f} mm; force at "
                  + ", ".join(f"{1e3 * a:g} mm {v / 1e3:6.1f}" for a, v in zip(AT, at))
                  + f" kN/m; largest difference from h = {min(hs):g} over 12-30 mm {100 * diff:5.1f} %  ({wall:.0f} s)",
                  flush=True)
        print()


if __name__ == "__main__":
    main()
