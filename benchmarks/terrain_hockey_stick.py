"""Hockey stick: a block sliding down a 30 deg DEM slope onto flat DEM ground, against the point-mass closed form.

    python benchmarks/terrain_hockey_stick.py [0.05 0.025 0.0125] [--size 0.16 0.16 0.08] [--pixel-ratio 1]

    [--cohesion C]   (a von Mises block, DP with phi = 0, yielding at C [Pa]; default elastic)

The closed form and the scene: tests/verification/test_hockey_stick.py.  Prints the block centre's stopping distance
past the kink at each cell size (DEM pixel = cell size / pixel ratio) against both kink models.
"""

import time


from geompm.testing.verification.hockey_stick import ELASTIC, closed_form, stopping_distance


def main():
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("cell_sizes", nargs="*", type=float, default=[0.05, 0.025, 0.0125])
    ap.add_argument("--size", nargs=3, type=float, default=[0.16, 0.16, 0.08])
    ap.add_argument("--pixel-ratio", type=float, default=1.0)
    ap.add_argument("--cohesion", type=float, default=None)
    a = ap.parse_args()
    law = ELASTIC if a.cohesion is None else {"model": "drucker_prager", "friction_angle": 0.0,
                                              "dilation_angle": 0.0, "cohesion": a.cohesion}
    print(f"block {a.size} m, {law}, DEM pixel = h / {a.pixel_ratio:g}")
    d_imp, d_free = closed_form()
    print(f"closed form: stops {d_imp:.4f} m past the kink (impulsive friction), {d_free:.4f} m without")
    for h in a.cell_sizes:
        t0 = time.perf_counter()
        d, n, steps, t = stopping_distance(h, size=tuple(a.size), law=law, pixel_ratio=a.pixel_ratio)
        print(f"h = {h:g} m: {n} particles, {steps} steps to t = {t:.3g} s, {time.perf_counter() - t0:.1f} s: stops "
              f"{d:.4f} m past the kink ({100 * (d / d_imp - 1):+.1f} % against the impulsive-friction form, "
              f"{100 * (d / d_free - 1):+.1f} % against the frictionless kink)", flush=True)


if __name__ == "__main__":
    main()
