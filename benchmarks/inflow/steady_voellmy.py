"""A steady inflow down a Voellmy bed at three cell sizes (geompm/testing/verification/voellmy_inflow.py):
the probes' depth and speed, averaged over t = 2.5-4 s, against the viscous layer's steady depth h* (and the
plug's h_n), and the injected volume against the hydrograph's integral.
Run: python benchmarks/inflow/steady_voellmy.py [h ...] > out.txt"""

import sys
import time

from geompm.testing.verification.voellmy_inflow import normal_depth, normal_speed, run_inflow, viscous_depth, Q

sizes = [float(a) for a in sys.argv[1:]] or [0.05, 0.025, 0.0125]
hn, un, hv = normal_depth(), normal_speed(), viscous_depth()
print(f"plug: h_n = {hn:.5f} m, u_n = {un:.5f} m/s; viscous layer: h* = {hv:.5f} m, u* = {Q / hv:.5f} m/s "
      f"(q = {Q} m2/s)")
for h in sizes:
    t0 = time.perf_counter()
    means, (vin, vt, vp, held) = run_inflow(h)
    print(f"\nh = {h} m  (wall {time.perf_counter() - t0:.0f} s, 2 cores)")
    for x, (d, u) in means.items():
        print(f"  x = {x:g} m: depth {d:.5f} m ({100 * (d / hv - 1):+.2f} % of h*, {100 * (d / hn - 1):+.2f} % of h_n)"
              f", speed {u:.4f} m/s ({100 * (u * hv / Q - 1):+.2f} % of u*), q {d * u:.4f} m2/s")
    print(f"  injected {vin:.7f} m2, V(4 s) {vt:.7f} m2, V_p {vp:.3e} m2, difference {vin - vt:+.3e} m2; "
          f"held + left the grid {held:.7f} m2")
    sys.stdout.flush()
