"""A steady inflow down a Voellmy bed: the normal depth of the law.

A discharge q [m2/s per metre] enters through a gate on a rigid bed inclined at beta (gravity tilted, the bed
the grid's y- wall with condition 'voellmy', mu and xi) thinner and faster than the flow the bed sustains.  A
plug in uniform steady flow balances, per unit bed area, rho g h (sin beta - mu cos beta) = rho g u^2 / xi with
u h = q, so it settles at the normal depth and speed

    h_n = (q^2 / (xi (sin beta - mu cos beta)))^(1/3),   u_n = q / h_n

(the steady depth of Voellmy's law that RAMMS's users calibrate against; Salm 1993, Christen et al. 2010).  The
flow is a Newtonian fluid of viscosity mu_v stiff enough in shear to move nearly as a plug.  Exactly, a layer in
uniform steady flow with Voellmy's law at its base carries the driving shear rho g sin beta (h - y) through its
depth, so above the base speed u_b it has the parabola u - u_b = rho g sin beta (h y - y^2 / 2) / mu_v, whose
mean adds rho g sin beta h^2 / (3 mu_v) to u_b, and the base balances Voellmy's law with u_b:

    u_b = sqrt(xi h (sin beta - mu cos beta)),   q = h (u_b + rho g sin beta h^2 / (3 mu_v))

(``viscous_depth`` solves it; here 3 % below h_n).  Probes downstream average the depth and speed over the
last seconds (the flow, Froude number about 2, carries small surface waves); the hydrograph's injected volume
is compared with its integral.
"""

from __future__ import annotations

import math

import numpy as np

G, BETA, MU, XI, Q, RHO = 9.81, 30.0, 0.2, 100.0, 0.5, 2000.0  # m/s2, deg, -, m/s2, m2/s, kg/m3
VISCOSITY = 2000.0  # Pa s: shear across a 0.2 m plug about 0.13 m/s, 5 % of u_n
INLET_SPEED = 1.25  # the inflow enters at this multiple of u_n (0.8 of the normal depth)
LENGTH, PROBE_X, GATE_X = 6.0, (2.0, 4.0, 5.5), 0.1  # m


def slope_term() -> float:
    b = math.radians(BETA)
    return math.sin(b) - MU * math.cos(b)


def normal_depth(q: float = Q) -> float:
    return (q * q / (XI * slope_term())) ** (1.0 / 3.0)


def normal_speed(q: float = Q) -> float:
    return q / normal_depth(q)


def viscous_depth(q: float = Q) -> float:
    """The depth h [m] of the viscous layer's uniform steady flow (module docstring), by bisection."""
    grow = RHO * G * math.sin(math.radians(BETA)) / (3.0 * VISCOSITY)
    lo, hi = 1e-6, 10.0 * normal_depth(q)
    for _ in range(200):
        h = 0.5 * (lo + hi)
        if h * (math.sqrt(XI * h * slope_term()) + grow * h * h) < q:
            lo = h
        else:
            hi = h
    return 0.5 * (lo + hi)


def inflow_case(h: float, end: float = 2.5, q: float = Q) -> dict:
    b = math.radians(BETA)
    v_in = INLET_SPEED * normal_speed(q)
    return {"name": "voellmy_inflow", "dimension": 2,
            "grid": {"origin": [0.0, 0.0], "extent": [LENGTH, 0.5], "cell_size": h},
            "time": {"end": end, "cfl": 0.4}, "gravity": [G * math.sin(b), -G * math.cos(b)],
            "solver": {"transfer": "apic"},
            "materials": {"debris": {"model": "newtonian", "density": RHO, "viscosity": VISCOSITY,
                                     "sound_speed": 10.0 * v_in}},
            "inflows": [{"name": "gate", "material": "debris", "section": [[GATE_X, 0.0]], "direction": [1.0, 0.0],
                         "table": [[0.0, q, v_in], [end, q, v_in]], "columns": "velocity"}],
            "probes": [{"name": f"x{x:g}", "point": [x, 0.0], "half_width": 0.1, "direction": [0.0, 1.0]}
                       for x in PROBE_X],
            "boundaries": [{"type": "wall", "side": "x-"},
                           {"type": "wall", "side": "y-", "condition": "voellmy", "friction": MU, "xi": XI}],
            "run": {"on_leave_domain": "delete"}}


def run_inflow(h: float, end: float = 4.0, average_from: float = 2.5):
    """{probe x: (mean depth [m], mean speed [m/s])} over the steps from ``average_from`` to ``end`` [s], and the
    mass balance (injected volume, V(end), particle volume, volume held plus volume that left) [m2]."""
    from geompm.api import scene_from_dict
    from geompm.engine.health import check_domain
    from geompm.engine.scheduler import Simulation

    sim = Simulation(scene_from_dict(inflow_case(h, end)))
    gate, probes = sim.scene.inflows[0], sim.scene.probes
    left, sums, weight = 0.0, np.zeros((len(probes), 2)), 0.0
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
        before = float(sim.state.p_vol0.sum())
        check_domain(sim, True)
        left += before - float(sim.state.p_vol0.sum())
        if sim.time > average_from:
            sums += sim.dt * np.array([p.reading[:2] for p in probes])
            weight += sim.dt
    means = {x: tuple(m) for x, m in zip(PROBE_X, sums / weight)}
    return means, (gate.count * gate.vp, gate.hydrograph.volume(sim.time), gate.vp,
                   float(sim.state.p_vol0.sum()) + left)
