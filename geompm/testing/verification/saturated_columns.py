"""Saturated soil columns (docs/pore-water.md): the hydrostatic column at rest, Terzaghi's consolidation
(cases/terzaghi_consolidation.json) and the undrained (sealed) loading, each at any cell size, with their
closed forms (tests/verification/test_pore_water.py, benchmarks/pore_water/columns.py)."""

import copy
import json
import math

import numpy as np

from geompm.api import scene_from_dict
from geompm.engine.scheduler import Simulation

from geompm.testing.verification.cases import shipped_case

GAMMA_W = 1000.0 * 9.80665  # unit weight of water at standard gravity [N/m3] (schemes/saturated/setup.py)
TERZAGHI = json.loads((shipped_case("terzaghi_consolidation.json")).read_text())


def run_to(sim, end):
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))


def rows(st, key="p_x0"):
    """(row heights, index arrays) of the particles grouped by their initial height."""
    y = np.round(getattr(st, key)[:, 1], 9)
    levels = np.unique(y)
    return levels, [np.flatnonzero(y == v) for v in levels]


#: the hydrostatic column's porosity, grain density [kg/m3] and gravity [m/s2]
HYDROSTATIC = (0.4, 2650.0, 9.81)


def scheme(case: dict, update: str = "saturated", kw=None) -> dict:
    """``case`` run by the scheme ``update``, its water's bulk modulus ``kw`` [Pa or "incompressible"] where
    given (every saturated material)."""
    case["solver"]["update"] = update
    if kw is not None:
        for mat in case["materials"].values():
            if "pore_water" in mat:
                mat["pore_water"].setdefault("fluid", {})["bulk_modulus"] = kw
    return case


def hydrostatic_case(h: float, end: float = 0.2, update: str = "saturated", kw=None, shape: str = "linear") -> dict:
    """A 1 m saturated elastic column (n = 0.4, rho_s = 2650, k = 1e-2 m/s) on an impermeable base between
    slip walls, geostatic and hydrostatic at t = 0, local damping 0.3, to ``end``; run by ``update`` with the
    water's bulk modulus ``kw`` (scheme) and ``shape`` functions."""
    n, rho_s, g = HYDROSTATIC
    case = {"name": "hydrostatic", "dimension": 2,
            "grid": {"origin": [0, 0], "extent": [0.2, 1.2], "cell_size": h, "shape_function": shape},
            "time": {"end": end}, "solver": {"transfer": "flip"}, "gravity": [0, -g],
            "materials": {"soil": {"model": "linear_elastic", "density": rho_s, "youngs_modulus": 10e6,
                                   "poisson_ratio": 0.3,
                                   "pore_water": {"porosity": n, "hydraulic_conductivity": 1e-2,
                                                  "fluid": {"bulk_modulus": 2.2e8}}}},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0], "max": [0.2, 1.0]},
                        "particles_per_cell": 2, "initial_stress": "geostatic"}],
            "damping": [{"model": "local", "alpha": 0.3}],
            "boundaries": [{"type": "wall", "side": s, "condition": "slip"} for s in ("y-", "x-", "x+")]}
    return scheme(case, update, kw)


def hydrostatic_column(h: float, end: float = 0.2, update: str = "saturated", kw=None, shape: str = "linear") -> dict:
    """The hydrostatic column (hydrostatic_case) run to ``end``. Returns the largest relative errors of
    p = rho_w g depth and sigma'_v = (1 - n)(rho_s - rho_w) g depth over the rows more than two cells from
    the base and the surface (the quadratic B-splines' boundary rows are reported apart: docs)."""
    n, rho_s, g = HYDROSTATIC
    sim = Simulation(scene_from_dict(hydrostatic_case(h, end, update, kw, shape)))
    st = sim.state
    run_to(sim, end)
    levels, idx = rows(st)
    p_err, s_err = [], []
    for y, i in zip(levels, idx):
        if y < 2 * h or y > 1.0 - 2 * h:
            continue
        depth = 1.0 - st.p_x[i, 1].mean()
        p_err.append(st.p_pore[i].mean() / (1000.0 * g * depth) - 1)
        s_err.append(st.p_stress[i, 1].mean() / (-(1 - n) * (rho_s - 1000.0) * g * depth) - 1)
    return {"h": h, "p_error": float(np.max(np.abs(p_err))), "stress_error": float(np.max(np.abs(s_err))),
            "steps": sim.step_count}


def terzaghi_constants(case=TERZAGHI) -> dict:
    """q, H, M, p0 (the undrained excess, 1D: q (K_w/n) / (M + K_w/n)) and c_v (with the water's
    compressibility, 1/c_v = gamma_w / k (1/M + n/K_w)) of a Terzaghi case."""
    soil = case["materials"]["soil"]
    pw = soil["pore_water"]
    E, nu, n, k, Kw = (soil["youngs_modulus"], soil["poisson_ratio"], pw["porosity"],
                       pw["hydraulic_conductivity"], pw["fluid"]["bulk_modulus"])
    Kw = float("inf") if Kw == "incompressible" else Kw
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    q = case["boundaries"][-1]["pressure"]
    H = case["bodies"][0]["geometry"]["max"][1]
    return {"q": q, "H": H, "M": M, "p0": q / (1 + n * M / Kw), "cv": k / (GAMMA_W * (1 / M + n / Kw)),
            "E": E, "nu": nu, "n": n, "Kw": Kw}


def terzaghi_case(h: float, soft: bool = False, update: str = "saturated", kw=None, cfl: float | None = None) -> dict:
    """cases/terzaghi_consolidation.json at cell size h, without writers, run by the scheme ``update``
    (saturated, saturated_musl or saturated_semi_implicit); ``soft``: E = 10 MPa, n = 0.4, K_w = 2.2e8 Pa (the
    issue's second set), its undrained start recomputed; ``kw``: the water's bulk modulus instead [Pa, or
    "incompressible"]; ``cfl``: time.cfl instead of the case's 0.4."""
    case = copy.deepcopy(TERZAGHI)
    case["outputs"] = []
    case["solver"]["update"] = update
    if cfl is not None:
        case["time"]["cfl"] = cfl
    case["grid"]["cell_size"] = h
    case["grid"]["extent"][0] = 2 * h
    case["bodies"][0]["geometry"]["max"][0] = 2 * h
    case["boundaries"][-1]["region"]["max"][0] = 2 * h
    soil = case["materials"]["soil"]
    if soft:
        soil["youngs_modulus"], soil["pore_water"]["porosity"] = 10e6, 0.4
        soil["pore_water"]["fluid"]["bulk_modulus"] = 2.2e8
    if kw is not None:
        soil["pore_water"]["fluid"]["bulk_modulus"] = kw
    c = terzaghi_constants(case)
    ds = -(c["q"] - c["p0"])  # the undrained effective stress increment, oedometric
    lat = ds * c["nu"] / (1 - c["nu"])
    case["bodies"][0]["stress_offset"] = [lat, ds, lat, 0, 0, 0]
    case["bodies"][0]["pore_pressure"] = {"excess": c["p0"]}
    return case


def terzaghi_series(z, tv, H=1.0, terms=400):
    """p / p0 = (4/pi) sum_{m odd} (1/m) sin(m pi z / 2H) exp(-m^2 pi^2 Tv / 4), z the depth below the
    drained top (Terzaghi 1943; Verruijt, Soil Mechanics, ch. 15)."""
    m = np.arange(1, 2 * terms, 2)[:, None]
    return (4 / np.pi * np.sin(m * np.pi * np.asarray(z)[None, :] / (2 * H)) / m
            * np.exp(-m * m * np.pi ** 2 * tv / 4)).sum(axis=0)


def degree(tv, terms=400):
    """Average degree of consolidation U(Tv) = 1 - sum_{m odd} 8/(m^2 pi^2) exp(-m^2 pi^2 Tv / 4)."""
    m = np.arange(1, 2 * terms, 2)
    return 1 - float((8 / (m * m * np.pi ** 2) * np.exp(-m * m * np.pi ** 2 * tv / 4)).sum())


def run_terzaghi(h: float, tvs=(0.05, 0.2, 0.5, 1.0), soft: bool = False, update: str = "saturated", kw=None,
                 cfl: float | None = None) -> list[dict]:
    """At each Tv: the largest |p - p_exact| / p0 over the particles, and the top row's settlement against
    p0 H / M U(Tv) (relative); arguments as terzaghi_case."""
    case = terzaghi_case(h, soft, update, kw, cfl)
    c = terzaghi_constants(case)
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    out = []
    for tv in tvs:
        run_to(sim, tv * c["H"] ** 2 / c["cv"])
        z = c["H"] - st.p_x0[:, 1]
        err = float(np.abs(st.p_pore - c["p0"] * terzaghi_series(z, tv, c["H"])).max() / c["p0"])
        top = st.p_x0[:, 1] > c["H"] - h / 2
        settle = float(-(st.p_x[top, 1] - st.p_x0[top, 1]).mean())
        exact = c["p0"] * c["H"] / c["M"] * degree(tv)
        out.append({"h": h, "Tv": tv, "p_error": err, "settlement": settle, "settlement_exact": exact,
                    "settlement_error": settle / exact - 1, "steps": sim.step_count})
    return out


def undrained_column(h: float, k: float = 1e-9, update: str = "saturated", kw=None) -> dict:
    """The stiff Terzaghi column from rest (p = 0, sigma' = 0) loaded by q over 2 ms, with a conductivity so
    small that no water leaves in the 40 ms run, brought to rest by local damping (the column rings for about
    20 ms: at 10 ms its total stress is still 1.4 % off q): the interior's pore pressure against the
    oedometric (1D) Skempton ratio p / q = (K_w/n) / (M + K_w/n) = 1 / (1 + n M / K_w), and the ratio of pore
    pressure to effective stress against (K_w/n) / M (``update``, ``kw``: scheme)."""
    case = copy.deepcopy(terzaghi_case(h, update=update, kw=kw))
    case["bodies"][0].pop("stress_offset")
    case["bodies"][0].pop("pore_pressure")
    case["materials"]["soil"]["pore_water"]["hydraulic_conductivity"] = k
    case["boundaries"][-1]["ramp_time"] = 0.002
    case["damping"] = [{"model": "local", "alpha": 0.3}]
    c = terzaghi_constants(case)
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    run_to(sim, 0.04)
    inner = (st.p_x0[:, 1] > 2 * h) & (st.p_x0[:, 1] < c["H"] - 2 * h)
    p, s = float(st.p_pore[inner].mean()), float(st.p_stress[inner, 1].mean())
    exact = 1 / (1 + c["n"] * c["M"] / c["Kw"])
    split = (c["Kw"] / c["n"]) / c["M"]
    return {"h": h, "B": p / c["q"], "B_exact": exact, "error": p / c["q"] / exact - 1,
            "split_error": p / -s / split - 1 if math.isfinite(split) else float(-s / p), "total_error": (s - p) / -c["q"] - 1}


def oedometer_undrained(h: float, q: float, sides: str = "roller", k: float = 1e-9,
                        cavitation: float | None = None, transfer: str = "flip", end: float = 0.04) -> dict:
    """Terzaghi's column as an undrained oedometer, pushed (q > 0) or pulled (q < 0) [Pa]: from rest (p = 0,
    sigma' = 0), k so small that no water moves in the 40 ms run, the base ``fixed``, the sides ``sides``
    (``roller`` holds the column laterally both ways, as an oedometer's ring; ``slip`` only against
    compression), the load ramped over 2 ms, local damping 0.3.  Undrained and oedometric the interior's pore
    pressure is p = B q, B = 1 / (1 + n M / K_w), whatever the load's sign.  Returns the interior's mean pore
    pressure, its error against B q, the total stress's error against the load, the column's lateral
    extent's change [m] and the least pore pressure any particle held during the run (``cavitation``: the
    material's cavitation pressure, default the schema's -100 kPa; ``transfer`` and the run's ``end`` [s]:
    PIC damps the ringing of a cavitated column, which is 1.3 % off rest at 40 ms under FLIP)."""
    case = copy.deepcopy(terzaghi_case(h))
    case["solver"]["transfer"] = transfer
    case["bodies"][0].pop("stress_offset")
    case["bodies"][0].pop("pore_pressure")
    case["materials"]["soil"]["pore_water"]["hydraulic_conductivity"] = k
    if cavitation is not None:
        case["materials"]["soil"]["pore_water"]["cavitation_pressure"] = cavitation
    case["boundaries"][0]["condition"] = "fixed"
    for wall in case["boundaries"][1:3]:
        wall["condition"] = sides
    case["boundaries"][-1]["pressure"] = q
    case["boundaries"][-1]["ramp_time"] = 0.002
    case["damping"] = [{"model": "local", "alpha": 0.3}]
    c = terzaghi_constants(case)
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    width0 = float(np.ptp(st.p_x[:, 0]))
    least = 0.0
    while sim.time < end - 1e-12:
        sim.step(min(sim.stable_dt(), end - sim.time))
        least = min(least, float(st.p_pore.min()))
    inner = (st.p_x0[:, 1] > 2 * h) & (st.p_x0[:, 1] < c["H"] - 2 * h)
    p, s = float(st.p_pore[inner].mean()), float(st.p_stress[inner, 1].mean())
    exact = q / (1 + c["n"] * c["M"] / c["Kw"])
    return {"h": h, "q": q, "sides": sides, "p": p, "p_exact": exact, "error": p / exact - 1,
            "total_error": (s - p) / -q - 1, "width_change": float(np.ptp(st.p_x[:, 0])) - width0,
            "effective": s, "least": least, "steps": sim.step_count}


def seepage_column(h: float, k: float = 1e-2, end: float = 0.3, update: str = "saturated", kw=None) -> dict:
    """Steady downward seepage through a saturated column drained at its top (free surface) and at its base
    (a drained slip wall: water leaves, the skeleton stays), between impermeable slip walls: the pore
    pressure falls to 0 and the water flows under the unit gradient i = 1 of its own weight. Returns the
    Darcy flux q = n (v_w - v_s) averaged over the rows more than two cells from the ends, against k i
    (g / g0: the conductivity is given at standard gravity), and the largest |p| there over rho_w g H
    (``update``, ``kw``: scheme)."""
    n, g, H = 0.4, 9.81, 1.0
    case = {"name": "seepage", "dimension": 2,
            "grid": {"origin": [0, 0], "extent": [0.2, 1.2], "cell_size": h, "shape_function": "linear"},
            "time": {"end": end}, "solver": {"transfer": "flip"}, "gravity": [0, -g],
            "materials": {"soil": {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": 10e6,
                                   "poisson_ratio": 0.3,
                                   "pore_water": {"porosity": n, "hydraulic_conductivity": k,
                                                  "fluid": {"bulk_modulus": 2.2e8}}}},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0, 0], "max": [0.2, H]},
                        "particles_per_cell": 2, "initial_stress": "geostatic"}],
            "damping": [{"model": "local", "alpha": 0.3}],
            "boundaries": [{"type": "wall", "side": "y-", "condition": "slip", "drainage": "drained"},
                           {"type": "wall", "side": "x-", "condition": "slip"},
                           {"type": "wall", "side": "x+", "condition": "slip"}]}
    sim = Simulation(scene_from_dict(scheme(case, update, kw)))
    st = sim.state
    run_to(sim, end)
    inner = (st.p_x0[:, 1] > 2 * h) & (st.p_x0[:, 1] < H - 2 * h)
    flux = float((st.p_n[inner] * -(st.p_vw[inner, 1] - st.p_v[inner, 1])).mean())
    exact = k * g / 9.80665
    return {"h": h, "flux": flux, "flux_exact": exact, "error": flux / exact - 1,
            "pressure": float(np.abs(st.p_pore[inner]).max() / (1000.0 * g * H))}


def undrained_wave_speed(h: float) -> dict:
    """The undrained P-wave of a 2 m column of the stiff Terzaghi set (k = 1e-9 m/s), loaded at once on its
    top: the speed between depths 0.5 and 1.0 m from the times the interior's pore pressure there first
    passes half its undrained value (interpolated linearly between the two steps around the crossing),
    against sqrt((M + K_w/n) / rho_sat)."""
    case = copy.deepcopy(terzaghi_case(h))
    for key in ("stress_offset", "pore_pressure"):
        case["bodies"][0].pop(key)
    case["materials"]["soil"]["pore_water"]["hydraulic_conductivity"] = 1e-9
    case["grid"]["extent"][1] = 2.2
    case["bodies"][0]["geometry"]["max"][1] = 2.0
    case["boundaries"][-1]["region"] = {"min": [0, 1.0], "max": [2 * h, 2.0]}
    c = terzaghi_constants(case)
    rho_s = case["materials"]["soil"]["density"]
    rho_sat = (1 - c["n"]) * rho_s + c["n"] * 1000.0
    exact = float(np.sqrt((c["M"] + c["Kw"] / c["n"]) / rho_sat))
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    half = 0.5 * c["q"] / (1 + c["n"] * c["M"] / c["Kw"])
    arrive, before = {}, {1.5: (0.0, 0.0), 1.0: (0.0, 0.0)}
    while sim.time < 2.0 / exact and len(arrive) < 2:
        sim.step(sim.stable_dt())
        for y in (1.5, 1.0):
            near = np.abs(st.p_x0[:, 1] - y) < h / 2
            p = float(st.p_pore[near].mean())
            if y not in arrive and p > half:
                t0, p0 = before[y]
                arrive[y] = t0 + (sim.time - t0) * (half - p0) / (p - p0)
            before[y] = (sim.time, p)
    speed = 0.5 / (arrive[1.0] - arrive[1.5])
    return {"h": h, "speed": speed, "exact": exact, "error": speed / exact - 1}


def isotropic_undrained(h: float, L: float = 0.4, kw: float = 1e8, end: float = 0.04) -> dict:
    """A sealed saturated cube of the stiff set (E = 98 MPa, nu = 0.3, n = 0.3, k = 1e-9 m/s) with K_w = kw,
    on three impermeable slip walls (symmetry planes x = y = z = 0) and loaded by a pressure q on its three
    other faces over 2 ms, brought to rest by local damping: the interior's pore pressure over the mean total
    stress against Skempton's B = 1 / (1 + n K / K_w) (Skempton 1954, Geotechnique 4(4):143), K the
    skeleton's bulk modulus. With kw = 1e8 Pa, B = 0.803, the oedometric ratio 0.716."""
    E, nu, n, q = 98e6, 0.3, 0.3, 10e3
    lo = [0.0, 0.0, 0.0]
    case = {"name": "isotropic_b", "dimension": 3,
            "grid": {"origin": lo, "extent": [L + 2 * h] * 3, "cell_size": h, "shape_function": "linear"},
            "time": {"end": end}, "solver": {"transfer": "flip"}, "gravity": [0.0, 0.0, 0.0],
            "materials": {"soil": {"model": "linear_elastic", "density": 2650.0, "youngs_modulus": E,
                                   "poisson_ratio": nu,
                                   "pore_water": {"porosity": n, "hydraulic_conductivity": 1e-9,
                                                  "fluid": {"bulk_modulus": kw}}}},
            "bodies": [{"material": "soil", "geometry": {"type": "box", "min": lo, "max": [L] * 3},
                        "particles_per_cell": 2}],
            "damping": [{"model": "local", "alpha": 0.3}],
            "boundaries": [{"type": "wall", "side": s, "condition": "slip"} for s in ("x-", "y-", "z-")] + [
                {"type": "surface_load", "name": f"load_{a}", "normal": [float(a == b) for b in range(3)],
                 "region": {"min": [L / 2 if a == b else 0.0 for b in range(3)], "max": [L] * 3},
                 "pressure": q, "ramp_time": 0.002} for a in range(3)]}
    sim = Simulation(scene_from_dict(case))
    st = sim.state
    run_to(sim, end)
    inner = np.all((st.p_x0 > h) & (st.p_x0 < L - 2 * h), axis=1)
    p = float(st.p_pore[inner].mean())
    mean_total = float(-(st.p_stress[inner, :3].sum(axis=1) / 3.0).mean()) + p
    K = E / (3 * (1 - 2 * nu))
    exact = 1 / (1 + n * K / kw)
    return {"h": h, "B": p / mean_total, "B_exact": exact, "error": p / mean_total / exact - 1,
            "load_error": mean_total / q - 1, "particles": int(inner.sum())}
