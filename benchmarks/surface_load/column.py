"""The loaded confined column (geompm/testing/verification/loaded_column.py) at h = 0.1, 0.05, 0.025 m: errors against
u_y = -q y / M and sigma_yy = -q, with the observed orders between successive cell sizes.

    python benchmarks/surface_load/column.py > benchmarks/results/<date>-surface-load-column.txt
"""

import math


from geompm.testing.verification.loaded_column import E, NU, Q, H, M, run_column


def main():
    print(f"confined elastic column, H = {H} m, E = {E:.3g} Pa, nu = {NU}, q = {Q:.3g} Pa, "
          f"M = {M:.6g} Pa, q H / M = {Q * H / M * 1e3:.5f} mm")
    rows = [run_column(h) for h in (0.1, 0.05, 0.025)]
    keys = ("settlement_error", "profile_error", "stress_error")
    print("h [m] | steps | settlement [mm] | exact [mm] | settlement error | profile error | stress error | "
          "largest speed [m/s]")
    for r in rows:
        print(f"{r['h']} | {r['steps']} | {r['settlement'] * 1e3:.5f} | {r['settlement_exact'] * 1e3:.5f} | "
              f"{r['settlement_error']:+.3%} | {r['profile_error']:.3%} | {r['stress_error']:+.3%} | "
              f"{r['largest_speed']:.2e}")
    for k in keys:
        e = [abs(r[k]) for r in rows]
        orders = [math.log(e[i] / e[i + 1]) / math.log(2) if e[i + 1] > 0 else float("nan") for i in range(2)]
        print(f"observed order of {k}: {orders[0]:.2f}, {orders[1]:.2f}")


if __name__ == "__main__":
    main()
