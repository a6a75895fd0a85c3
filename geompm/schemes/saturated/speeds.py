"""The wave speeds of saturated soil, for the stable step (the scheme's wave_speed; docs/pore-water.md).

An explicit step of the two-phase equations is bounded by the fastest of three waves:

    undrained   c_u = sqrt((M + K_w / n) / rho_sat)   solids and water moving together (Biot's fast wave
                                                       in the no-flow limit); M = K + 4G/3 of the skeleton
    water       c_w = sqrt(K_w / rho_w)                the water alone through the pores
    skeleton    c_s = the law's speed at the dry density  (the skeleton alone, where the water has drained)

M comes from the law's own speed: M = c_s^2 rho_d (rho_d = the solids' mass per volume, the particle
density the law sees).  Each is bounded over a material's particles by its extremes (the smallest n and
saturated density, the largest dry density), as the dry step bounds a law's speed by the block's densities.
The drag, taken implicitly on the nodes (kernels.node_relative), sets no bound.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from geompm.backend.cpu_loops import law_wave_speed
from geompm.errors import SimulationError
from geompm.schemes.saturated import kernels as tp
from geompm.schemes.saturated.kernels import speed_terms_one


@njit(parallel=True, cache=True)
def speed_bounds(p_v, p_vw, p_n, p_rho, p_sat, row, start, end):
    """Over the particles start..end of one material (row: its table row): (min n of the wet particles, 1
    if none; max dry density; min saturated density; max |v| of either phase), for the stable step."""
    n_min = 1.0
    rho_max = 0.0
    sat_min = math.inf
    v2_max = 0.0
    for p in prange(start, end):
        n, rho, sat, v2 = speed_terms_one(p, p_v, p_vw, p_n, p_rho, p_sat, row)
        n_min = min(n_min, n)
        rho_max = max(rho_max, rho)
        sat_min = min(sat_min, sat)
        v2_max = max(v2_max, v2)
    return n_min, rho_max, sat_min, math.sqrt(v2_max)


#: a material's row of the extremes the speeds are bounded by: its law's speed [m/s], minus the smallest
#: porosity of its wet particles, the largest dry density, minus the smallest saturated density [kg/m3] and the
#: largest speed of either phase [m/s]; each is a maximum, so the rows of several ranks reduce by a maximum
#: before they are combined, and the step is the one a single process takes
EMPTY_ROW = (0.0, -1.0, 0.0, -math.inf, 0.0)


def block_extremes(scene, state, pw) -> np.ndarray:
    """(materials, 5): each material block's row of EMPTY_ROW's quantities over this process's particles."""
    rows = np.tile(np.array(EMPTY_ROW), (len(scene.materials), 1))
    for k, (mat, (s, e)) in enumerate(zip(scene.materials, state.blocks)):
        if e <= s:
            continue
        n_min, rho_d, rho_sat, flow = speed_bounds(state.p_v, state.p_vw, state.p_n, state.p_rho, state.p_sat,
                                                      pw.table[k], s, e)
        rows[k] = (law_wave_speed(mat, state.p_rho[s:e]), -n_min, rho_d, -rho_sat, flow)
    return rows


def combined_speeds(rows: np.ndarray, pw, names, where=None) -> dict[str, float]:
    """{'undrained', 'water', 'skeleton', 'flow'} [m/s] from the blocks' extremes (block_extremes, reduced
    over the ranks).  A block whose extremes give no real undrained wave (a density or porosity that left its
    range: a blown-up particle) raises SimulationError (exit 3), naming the material (``names``) and the particle
    through ``where(k)`` (this process's particle of block k that is out of range, or '')."""
    out = {"undrained": 0.0, "water": 0.0, "skeleton": 0.0, "flow": 0.0}
    for k, (c, neg_n, rho_d, neg_sat, flow) in enumerate(rows):
        out["skeleton"] = max(out["skeleton"], float(c))
        out["flow"] = max(out["flow"], float(flow))
        n_min, rho_sat = -float(neg_n), -float(neg_sat)
        if not pw.wet[k] or n_min >= 1.0:
            continue
        row = pw.table[k]
        squared = (c * c * rho_d + row[tp.WATER.k_w] / n_min) / rho_sat
        if not (math.isfinite(squared) and squared > 0.0 and n_min > 0.0):
            raise SimulationError(
                f"the undrained wave speed of material '{names[k]}' is not real (smallest porosity {n_min:.4g}, smallest "
                f"saturated density {rho_sat:.4g} kg/m3, largest dry density {rho_d:.4g} kg/m3, law speed "
                f"{c:.4g} m/s){where(k) if where is not None else ''}. Likely cause: the particle was crushed or "
                "torn apart by a blow-up (a step too long for the waves, or linear shape functions in a fast "
                "flow: docs/pore-water.md, Limits)")
        out["undrained"] = max(out["undrained"], math.sqrt(squared))
        out["water"] = max(out["water"], math.sqrt(row[tp.WATER.k_w] / row[tp.WATER.rho_w]))
    return out


def saturated_speeds(scene, state, pw, comm=None) -> dict[str, float]:
    """{'undrained', 'water', 'skeleton', 'flow'} [m/s]: the three wave speeds of the module docstring,
    largest over the particles (of every rank of ``comm``), and the largest speed of either phase."""
    rows = block_extremes(scene, state, pw)
    if comm is not None:
        rows = np.asarray(comm.max(rows.ravel())).reshape(rows.shape)
    return combined_speeds(rows, pw, scene.material_names, lambda k: out_of_range(scene, state, pw, k))


def skeleton_speeds(scene, state, pw) -> tuple[float, float]:
    """(the skeleton's wave speed, the largest speed of either phase) [m/s] over the particles: the step of
    the semi-implicit scheme (semi_implicit.py), where the pressure is implicit and no undrained or water
    wave binds.  A porosity outside (0, 1) or a density that is not positive raises SimulationError (exit 3)
    naming the particle."""
    rows = block_extremes(scene, state, pw)
    for k, (c, neg_n, rho_d, neg_sat, flow) in enumerate(rows):
        n_min, rho_sat = -float(neg_n), -float(neg_sat)
        if pw.wet[k] and n_min < 1.0 and not (n_min > 0.0 and rho_sat > 0.0 and math.isfinite(rho_sat)
                                              and math.isfinite(c)):
            raise SimulationError(
                f"material '{scene.material_names[k]}' left its range (smallest porosity {n_min:.4g}, smallest "
                f"saturated density {rho_sat:.4g} kg/m3, law speed {c:.4g} m/s)"
                f"{out_of_range(scene, state, pw, k)}. Likely cause: a blow-up (a step too long for the "
                "skeleton: lower time.cfl)")
    return float(rows[:, 0].max(initial=0.0)), float(rows[:, 4].max(initial=0.0))


def out_of_range(scene, state, pw, k: int) -> str:
    """', at particle <id> (...)': this process's particle of material k whose density or porosity is out of
    range (the smallest saturated density if none is), or '' when this process holds none of them."""
    s, e = state.blocks[k]
    if e <= s:
        return ""
    n = state.p_n[s:e]
    rho_sat = state.p_rho[s:e] + state.p_sat[s:e] * n * pw.table[k, tp.WATER.rho_w]
    bad = ~np.isfinite(rho_sat) | (rho_sat <= 0.0) | ~(n > 0.0)
    p = s + int(np.argmax(bad) if bad.any() else np.argmin(rho_sat))
    return (f", at particle {int(state.p_id[p])} (body {int(state.p_body[p])}, x = "
            f"{np.round(state.p_x[p], 4).tolist()} m, density "
            f"{float(state.p_rho[p]):.4g} kg/m3, porosity {float(state.p_n[p]):.4g})")


def drag_limit(state, pw) -> float:
    """The step an explicit drag would need, 2 m_w / c = 2 rho_w kappa(n) / (n mu_w) [s], at the particle
    where it is smallest (reported by `geompm validate`; the drag is implicit, so it does not bind)."""
    wet = state.p_sat > 0
    if not wet.any():
        return float("inf")
    rows = pw.table[state.p_material[wet]]
    n = state.p_n[wet].astype(float)
    n0 = rows[:, tp.WATER.n0]
    kozeny = n ** 3 * (1.0 - n0) ** 2 / (n0 ** 3 * (1.0 - n) ** 2)  # kernels.permeability, vectorised
    kappa = rows[:, tp.WATER.kappa0] * np.where(rows[:, tp.WATER.kozeny] > 0.0, kozeny, 1.0)
    return float(np.min(2.0 * rows[:, tp.WATER.rho_w] * kappa / (n * rows[:, tp.WATER.mu_w])))
