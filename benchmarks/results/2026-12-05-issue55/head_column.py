import json, sys, numpy as np
from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation
H = float(sys.argv[1]) if len(sys.argv) > 1 else 1.5
case = {"name": "head", "dimension": 2, "grid": {"origin": [0, 0], "extent": [0.2, 1.2], "cell_size": 0.05},
 "time": {"end": float(sys.argv[3]) if len(sys.argv) > 3 else 0.6}, "gravity": [0, -9.81],
 "materials": {"soil": {"model": "linear_elastic", "density": 2650, "youngs_modulus": 2e7, "poisson_ratio": 0.3,
   "pore_water": {"porosity": 0.4, "hydraulic_conductivity": float(sys.argv[2]) if len(sys.argv) > 2 else 1e-2, "fluid": {"bulk_modulus": 2e7}}}},
 "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0], "max": [0.2, 1.0]}, "initial_stress": "geostatic"}],
 "boundaries": [{"type": "wall", "side": "x-", "condition": "slip"}, {"type": "wall", "side": "x+", "condition": "slip"},
   ({"type": "wall", "side": "y-", "condition": "fixed", "drainage": "head", "head": H} if H > 0 else {"type": "wall", "side": "y-", "condition": "fixed"})],
 "damping": [{"model": "local", "alpha": 0.3}],
 "outputs": []}
sim = Simulation(scene_from_dict(case))
while sim.time < case["time"]["end"] - 1e-12:
    sim.step(min(sim.stable_dt(), case["time"]["end"] - sim.time))
st = sim.state
y = st.p_x[:, 1]
order = np.argsort(y)
hz = H + (1.0 - H) * y  # linear head from H at the base to the top 1.0
closed = 1000 * 9.81 * (hz - y)
for q in np.linspace(0, len(y) - 1, 12).astype(int):
    i = order[q]
    print(f"{y[i]:.3f} {st.p_pore[i]:10.1f} {closed[i]:10.1f}")
