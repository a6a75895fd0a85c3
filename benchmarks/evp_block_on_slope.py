"""Bingham layer on a gentle slope under the elasto-viscoplastic integration (issue 19, verification 3).

    python benchmarks/evp_block_on_slope.py RATIO CELLS [M]

A 0.05 m Bingham layer (rho 1800 kg/m3, tau_y 50 Pa, mu 1 Pa s, Papanastasiou M, default 1e4 s) on a no-slip
bed, periodic along the slope, driven by gravity tilted so that the basal shear stress is RATIO tau_y.
Prints how far the top moved between t = 0.5 and 1.5 s (in cells) and the top speed against the closed form
of a Bingham layer, u_top = G / (2 mu) (H - tau_y / G)^2 with G = rho g sin(theta).
"""
import math
import sys
import time
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
ratio = float(sys.argv[1])
ncell = int(sys.argv[2])
M = float(sys.argv[3]) if len(sys.argv) > 3 else 1e4
RHO, TY, H, g = 1800.0, 50.0, 0.05, 9.81
s = ratio * TY / (RHO * g * H); th = math.asin(s)
h = H / ncell
case = {"name": "bblock", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [4 * h, H + 4 * h], "cell_size": h},
        "time": {"end": 1.5, "cfl": 0.4}, "gravity": [g * math.sin(th), -g * math.cos(th)],
        "materials": {"mud": {"model": "bingham", "density": RHO, "viscosity": 1.0, "yield_stress": TY,
                              "regularisation_time": M, "sound_speed": 10.0, "integration": "elastoviscoplastic"}},
        "bodies": [{"material": "mud", "geometry": {"type": "box", "min": [0.0, 0.0], "max": [4 * h, H]}, "initial_stress": "geostatic"}],
        "boundaries": [{"type": "periodic", "axis": "x"}, {"type": "wall", "side": "y-", "condition": "fixed"}]}
sim = Simulation(scene_from_dict(case)); st = sim.state
top = st.p_x[:, 1] > H - h / 2
x_half = None; t0 = time.time()
while sim.time < 1.5 - 1e-12:
    sim.step(min(sim.stable_dt(), 1.5 - sim.time))
    if x_half is None and sim.time >= 0.5:
        x_half = (st.p_x - st.p_x0)[top, 0].mean()  # displacement: continuous across the periodic wrap
creep = (st.p_x - st.p_x0)[top, 0].mean() - x_half
G = RHO * g * s
u_exact = G / 2 * (H - TY / G) ** 2 if ratio > 1 else 0.0
print(f"ratio {ratio} n {ncell} M {M}: steps {sim.step_count} wall {time.time()-t0:.1f}s; top moved {creep:.3e} m from 0.5 to 1.5 s = {creep/h:.4f} h; top speed {st.p_v[top,0].mean():.4f} m/s (closed form {u_exact:.4f})")
