"""Steady stream against a rigid wall: the reported force per width is alpha rho v^2 d.

Set-up: a 2D stream of water (newtonian, rho 1000 kg/m3, c = 25 m/s), depth
d = 0.1 m and length 1.0 m, moving at v = 2 m/s on a slip floor under gravity
into a rigid slip `box` obstacle 0.3 m ahead (h = 0.01 m, 4000 particles).
The stream turns up the wall; over the quasi-steady phase t = 0.2-0.45 s
(impact at 0.15 s; afterwards the reflected bore slows the incoming stream)
the mean horizontal force per metre must lie in the hydrodynamic range
alpha rho v^2 d with alpha in [1, 2.5] (Hungr, Morgan & Kellerhals 1984:
alpha = 1.5; Watanabe & Ikeya 1981: 2.0; tests/refdata/
debris_flow_impact_design_formulas.csv).  The hydrostatic part rho g d^2 / 2
is 1% of rho v^2 d here.  Measured: alpha = 1.05-1.17 over that phase.
"""

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

V, D, RHO = 2.0, 0.1, 1000.0


def stream_case() -> dict:
    """The 2D stream (h = 0.01 m) and the slip wall 0.3 m ahead of it."""
    return {
        "name": "stream", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.6, 2.0], "cell_size": 0.01},
        "time": {"end": 0.45, "cfl": 0.3}, "gravity": [0.0, -9.81],
        "materials": {"water": {"model": "newtonian", "density": RHO, "viscosity": 1e-3, "sound_speed": 25.0}},
        "bodies": [{"material": "water", "geometry": {"type": "box", "min": [0.1, 0.0], "max": [1.1, D]},
                    "velocity": [V, 0.0]}],
        "boundaries": [{"type": "wall", "side": "y-", "condition": "slip"},
                       {"type": "wall", "side": "y+", "condition": "slip"}],
        "obstacles": [{"type": "box", "name": "wall", "min": [1.4, -0.05], "max": [1.5, 2.05], "condition": "slip"}],
    }


def test_stream_force_on_wall_is_hydrodynamic():
    sim = Simulation(scene_from_dict(stream_case()))
    obstacle = sim.scene.obstacles[0]
    impulse, span = 0.0, 0.0
    while sim.time < 0.45:
        dt = min(sim.stable_dt(), 0.45 - sim.time)
        sim.step(dt)
        if sim.time > 0.2:
            impulse += obstacle.force[0] * dt
            span += dt
    alpha = impulse / span / (RHO * V ** 2 * D)
    assert 1.0 <= alpha <= 2.5, f"alpha = {alpha:.3f}"
