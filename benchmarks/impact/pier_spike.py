"""The first-contact face-pressure spike on a pier against the acoustic pressure rho c v of the flow's
stiffness (docs/impact-forces.md, The filtered force).

A 0.3 x 0.2 x 0.3 m block of Drucker-Prager debris (phi 35, rho 2000 kg/m3, nu 0.3) slides at 3 m/s on a
slip floor between slip side walls, without gravity along the floor and without damping, into a rigid cylinder pier (radius 0.1 m,
vertical).  For E = 2 and 8 MPa (c = 36.7 and 73.4 m/s) and h = 0.05 and 0.025 m it prints the largest face
pressure within 10 ms of first contact, over the whole run, against rho c v and rho v^2, and the filtered
peak force.  Raw output: benchmarks/results/2026-12-05-issue57/pier-spike.txt.

    python benchmarks/impact/pier_spike.py
"""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path

import numpy as np

RHO, NU, V = 2000.0, 0.3, 3.0


def case(h: float, E: float) -> dict:
    return {
        "name": "pier_spike", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [1.2, 0.6, 0.6], "cell_size": h},
        "time": {"end": 0.25, "cfl": 0.4}, "gravity": [0.0, -9.81, 0.0],
        "solver": {"transfer": "apic", "update": "usl"},
        "materials": {"debris": {"model": "drucker_prager", "density": RHO, "youngs_modulus": E, "poisson_ratio": NU,
                                 "friction_angle": 35.0, "cohesion": 0.0, "dilation_angle": 0.0}},
        "bodies": [{"material": "debris", "geometry": {"type": "box", "min": [0.2, 0.0, 0.15], "max": [0.5, 0.2, 0.45]},
                    "velocity": [V, 0.0, 0.0], "particles_per_cell": 2}],
        "boundaries": [{"type": "wall", "side": s, "condition": "slip"} for s in ("y-", "x+", "z-", "z+")],
        "obstacles": [{"type": "cylinder", "name": "pier", "center": [0.75, 0.3, 0.3], "radius": 0.1, "axis": "y",
                       "length": 0.6, "condition": "slip"}],
        "outputs": [{"writer": "surfaces", "interval": 0.05}],
    }


def measure(h: float, E: float) -> dict:
    from geompm.api import scene_from_dict
    from geompm.engine.scheduler import Simulation

    sim = Simulation(scene_from_dict(case(h, E)))
    pier = sim.scene.obstacles[0]
    if pier.faces is None:  # the surfaces writer asks for faces in set-up
        raise SystemExit("no faces")
    early = 0.0
    while sim.time < 0.25:
        sim.step(sim.stable_dt())
        first = pier.impact.first_contact
        if first is not None and sim.time <= first + 0.01:
            early = max(early, float(pier.face_pressure.max()))
    c = math.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)) / RHO)
    rep = pier.impact_report()
    return {"h": h, "E": E, "c": c, "early": early, "whole": float(pier.face_pmax.max()), "rcv": RHO * c * V,
            "rv2": RHO * V * V, "raw": pier.peak[0], "filtered": rep["filtered_peak_force"], "window": rep["force_window"]}


def main() -> int:
    rows = [measure(h, E) for h in (0.05, 0.025) for E in (2e6, 8e6)]
    print("h [m]  E [MPa]  c [m/s]  face p in 10 ms after contact [kPa]  over the run [kPa]  rho c v [kPa]  "
          "rho v^2 [kPa]  raw peak F [N]  filtered peak F [N] (window)")
    for r in rows:
        print(f"{r['h']:<6} {r['E'] / 1e6:<8g} {r['c']:<8.1f} {r['early'] / 1e3:<36.1f} {r['whole'] / 1e3:<19.1f} "
              f"{r['rcv'] / 1e3:<14.1f} {r['rv2'] / 1e3:<14.1f} {r['raw']:<15.1f} {r['filtered']:.1f} "
              f"({1e3 * r['window']:.1f} ms)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
