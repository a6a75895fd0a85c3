"""A contact surface's design numbers beside the code formulas: the filtered peak as equivalent coefficients.

With the flow's depth h [m], speed v [m/s] and density rho [kg/m3] read by the surface's probe
(probes/section.py) when its momentum flux rho v^2 h was largest, from the start to one force window after
first contact (the surge whose load makes the filtered peak: the front that touches first is a few
particles thin, the flow that backs up from the surface afterwards is slow), the surface's width w [m] (1 m in 2D, forces per metre) and the filtered peak
force F (contact/impact.py):

    alpha = F / (rho v^2 h w)           the hydrodynamic coefficient of F = alpha rho v^2 h w
                                        (Hungr et al. 1984; Kwan 2012, GEO Report 270: alpha = 2.5 for a
                                        rigid barrier; Armanini et al. 2020 review the range)
    k     = F / (rho g h^2 w / 2)       the hydrostatic coefficient of p = k rho g h at the base of a
                                        triangular distribution over the depth h (Lichtenhahn 1973: k = 2.8-4.4;
                                        Armanini 1997: 5 dynamic, 1 static), g = |gravity|
    Fr    = v / sqrt(g h)               the Froude number of the approaching flow

The width w (3D) is ``design_width`` or the extent of the surface across the flow: the horizontal
direction normal to the probe's velocity.  The pressure profile is the normal pressure of the faces
averaged over the filtered peak's window, in bins one cell high over the surface's height (along
-gravity) from the lowest loaded face centre (the bed, for a wall standing in it), each the area-weighted
mean of the faces loaded in it; its resultant acts at ``pressure_centre_height`` above that face.
"""

from __future__ import annotations

import math

import numpy as np


def momentum_flux(reading) -> float:
    """rho v^2 h [N/m] of a probe reading (depth, speed, density, ...)."""
    return reading[2] * reading[1] ** 2 * reading[0]


def across_width(stage, velocity) -> float | None:
    """The surface's extent [m] along the horizontal direction normal to ``velocity`` (3D), from its
    tessellated surface; None without one."""
    surf = stage.surface()
    if surf is None:
        return None
    up = -stage.gravity / np.linalg.norm(stage.gravity)
    flow = np.zeros(3)
    flow[:len(velocity)] = velocity
    across = np.cross(up, flow)
    if np.linalg.norm(across) == 0.0:
        return None
    proj = surf.vertices @ (across / np.linalg.norm(across))
    return float(proj.max() - proj.min())


def _heights(stage):
    """(height of each face centre along -gravity [m], normal pressures at the filtered peak [Pa], loaded
    faces) with heights measured from the lowest loaded face centre (the bed, where the surface stands in it)."""
    p = stage.impact.face_pressure_at_peak
    up = -stage.gravity / np.linalg.norm(stage.gravity)
    z = stage.face_centre[:, :stage.dim] @ up[:stage.dim]
    loaded = p > 0.0
    return z - z[loaded].min(), p, loaded


def pressure_profile(stage) -> list[list[float]]:
    """[[height above the lowest loaded face centre [m], pressure [Pa]], ...] at the filtered peak."""
    p = stage.impact.face_pressure_at_peak
    if p is None or stage.faces is None or not stage.gravity.any() or not (p > 0.0).any():  # no load, no height
        return []
    z, p, loaded = _heights(stage)
    h = stage.grid.h
    bins = np.floor(z / h).astype(int)
    out = []
    for b in range(int(bins[loaded].max()) + 1):
        sel = loaded & (bins == b)
        if sel.any():
            a = stage.face_area[sel]
            out.append([float((b + 0.5) * h), float((p[sel] * a).sum() / a.sum())])
    return out


def pressure_centre(stage) -> float:
    """Height [m] above the lowest loaded face centre of the resultant of the normal pressures at the
    filtered peak (the point of action that an overturning check needs)."""
    z, p, loaded = _heights(stage)
    force = np.where(loaded, p, 0.0) * stage.face_area
    return float((force * z).sum() / force.sum())


def design_report(stage) -> dict:
    """The impact quantities (ImpactRecord.report), the approach flow its probe read (the largest momentum
    flux up to a window after first contact) and the equivalent coefficients; {} before first contact."""
    out = stage.impact.report()
    if not out:
        return out
    profile = pressure_profile(stage)  # [] without faces or without gravity
    if profile:
        out["pressure_profile"] = profile
        out["pressure_centre_height"] = pressure_centre(stage)
    if stage.approach is None:
        return out
    depth, speed, rho, vel = stage.approach
    g = float(np.linalg.norm(stage.gravity))
    width = 1.0 if stage.dim == 2 else (stage.params.design_width or across_width(stage, vel))
    out.update(probe=stage.probe.label, probe_depth=depth, probe_speed=speed, probe_density=rho, design_width=width)
    if depth > 0.0 and speed > 0.0 and width:
        F = out["filtered_peak_force"]
        out["alpha"] = F / (rho * speed ** 2 * depth * width)
        if g > 0.0:
            out["hydrostatic_ratio"] = F / (0.5 * rho * g * depth ** 2 * width)
            out["froude"] = speed / math.sqrt(g * depth)
    return out
