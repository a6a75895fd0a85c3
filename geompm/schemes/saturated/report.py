"""What `geompm validate` says about saturated soil (docs/pore-water.md, The time step): which wave sets the
step, the step an explicit drag would need, and each saturated material's consolidation coefficient with
the effect of its water compressibility:

    1/c_v = gamma_w / k (1/M + n/K_w),   M = K + 4G/3 (the law's speed^2 x the dry density)
"""

from __future__ import annotations

import numpy as np

from geompm.backend.cpu_loops import law_wave_speed
from geompm.schemes.saturated import kernels as tp
from geompm.schemes.saturated.setup import STANDARD_GRAVITY
from geompm.schemes.saturated.speeds import drag_limit, saturated_speeds

#: the bulk modulus of water at 20 C [Pa]: a smaller K_w is a user's speed-up and is reported as such
WATER_BULK_MODULUS = 2.2e9


def pore_water_lines(scene, pw) -> list[str]:
    st = scene.state
    if st.n == 0:
        return []
    sp = saturated_speeds(scene, st, pw)
    waves = {"undrained": "undrained wave sqrt((M + K_w/n) / rho_sat)", "water": "water's wave sqrt(K_w / rho_w)",
             "skeleton": "skeleton's wave (the law's, at the dry density)"}
    top = max(waves, key=lambda k: sp[k])
    lines = [f"pore water: the wave step is set by the {waves[top]}, {sp[top]:.4g} m/s (undrained "
             f"{sp['undrained']:.4g}, water {sp['water']:.4g}, skeleton {sp['skeleton']:.4g} m/s)"]
    drag = drag_limit(st, pw)
    if drag < float("inf"):
        lines.append(f"pore water: the drag is implicit and sets no limit; an explicit drag would need "
                     f"dt <= 2 k / (n g) = {drag:.3g} s")
    return lines + consolidation_lines(scene, pw)


def semi_implicit_lines(scene, pw) -> list[str]:
    """The semi-implicit step (semi_implicit.py): the skeleton's wave sets the step; what the explicit
    scheme's undrained wave would ask; the consolidation coefficients."""
    from geompm.schemes.saturated.speeds import skeleton_speeds

    st = scene.state
    if st.n == 0:
        return []
    skeleton, _ = skeleton_speeds(scene, st, pw)
    line = (f"pore water: semi-implicit (the pore pressure solved on the grid each step: CG with pyamg's "
            f"smoothed aggregation, tolerance {pw.pressure_solver.tolerance:g}); the step is set by the skeleton's "
            f"wave (the law's, at the dry density), {skeleton:.4g} m/s, and the flow's speed")
    if np.isfinite(pw.table[:, tp.WATER.k_w]).all():
        undrained = saturated_speeds(scene, st, pw)["undrained"]
        line += (f"; the explicit scheme's undrained wave, {undrained:.4g} m/s, would take "
                 f"{undrained / max(skeleton, 1e-300):.3g} times more steps")
    else:
        line += "; incompressible water (the explicit scheme cannot run it)"
    return [line] + consolidation_lines(scene, pw)


def consolidation_lines(scene, pw) -> list[str]:
    """Each saturated material's c_v, with the effect of its water's compressibility."""
    st = scene.state
    lines = []
    for k, (mat, name, (s, e)) in enumerate(zip(scene.materials, scene.material_names, st.blocks)):
        if not pw.wet[k] or e <= s:
            continue
        row = pw.table[k]
        modulus = law_wave_speed(mat, st.p_rho[s:e]) ** 2 * mat.density
        cond = row[tp.WATER.kappa0] * row[tp.WATER.rho_w] * STANDARD_GRAVITY / row[tp.WATER.mu_w]
        gamma = row[tp.WATER.rho_w] * STANDARD_GRAVITY
        n0, kw = row[tp.WATER.n0], row[tp.WATER.k_w]
        cv = cond / (gamma * (1.0 / modulus + n0 / kw))
        stiff = cond / (gamma / modulus)
        text = (f"materials.{name}.pore_water: c_v = {cv:.4g} m2/s (k = {cond:.3g} m/s, M = {modulus:.4g} Pa, "
                f"K_w = {kw:.4g} Pa; {stiff:.4g} m2/s with incompressible water)")
        if kw == float("inf"):
            text = (f"materials.{name}.pore_water: c_v = {cv:.4g} m2/s (k = {cond:.3g} m/s, M = {modulus:.4g} Pa, "
                    "incompressible water)")
        elif kw < WATER_BULK_MODULUS:
            full = cond / (gamma * (1.0 / modulus + n0 / WATER_BULK_MODULUS))
            text += (f"; the reduced K_w makes c_v {100 * (1 - cv / full):.1f} % smaller than water's "
                     f"{WATER_BULK_MODULUS:g} Pa would, and the undrained wave slower")
        lines.append(text)
    return lines
