"""Print the numerical envelope of docs/numerical-envelope.md as a markdown table: every row of
tests/envelope/test_envelope.py's SOIL list, run with its harness.

    python benchmarks/envelope/envelope_table.py > table.md

Columns: steps, first and smallest dt [s], the largest E_k over what the run can supply, the furthest
particle [m], the densest particle / rho0 [-], and the harness's verdict (stable: finite, inside the
grid, E_k within 5 % of the supply).
"""

from __future__ import annotations


from geompm.testing.verification.envelope import column, run
from geompm.testing.verification.envelope import SOIL


def main() -> None:
    print("| case | steps | dt first / smallest [s] | max E_k / supply | front [m] | ρ_max / ρ0 | result |")
    print("|---|---|---|---|---|---|---|")
    for label, over in SOIL:
        case = column(**over)
        out = run(case)
        rho0 = next(iter(case["materials"].values()))["density"]
        verdict = "stable" if out.stable else ("NaN/Inf" if not out.finite else
                                               "left the grid" if not out.inside else "gains energy")
        print(f"| {label} | {out.steps} | {out.dt_first:.3g} / {out.dt_min:.3g} | {out.energy_ratio:.3f} | "
              f"{out.front_x:.3f} | {out.rho_max / rho0:.2f} | {verdict} |", flush=True)


if __name__ == "__main__":
    main()
