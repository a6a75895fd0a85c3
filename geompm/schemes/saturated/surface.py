"""The flow's own free surface above each particle: the hydrostatic reference of the excess pore pressure
(docs/pore-water.md, Outputs).

The particles are binned in columns of one cell width across the upward direction (up = -g / |g|); a
column's surface is the height of its highest particle plus half that particle's spacing.  A particle's
hydrostatic pore pressure is then

    p_h = rho_w |g| max(0, z_s(x, t) - d_wt - z)

with z its height, z_s its column's surface now and d_wt the depth of its body's water table below the
surface at set-up (0 for a body saturated to its top, the usual flow): the reference follows the mass as
it descends, thins or piles up, where a table fixed at the release's elevation would read a flow 100 m
lower as 1 MPa of suction.  The columns' surfaces are a maximum over every rank (``comm_max``).
"""

from __future__ import annotations

import numpy as np


def across(up: np.ndarray) -> np.ndarray:
    """An orthonormal basis (d - 1, d) of the directions across ``up``."""
    d = len(up)
    if d == 2:
        return np.array([[up[1], -up[0]]])
    helper = np.eye(3)[int(np.argmin(np.abs(up)))]
    e1 = np.cross(up, helper)
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(up, e1)])


def column_surface(p_x, spacing, up, origin, extent, h, comm_max=None) -> np.ndarray:
    """z_s of each particle's column [m] (module docstring); ``origin``, ``extent``: the grid's, which bound
    the columns' index range so that every rank bins alike."""
    if len(p_x) == 0 and comm_max is None:
        return np.zeros(0)
    basis = across(up)
    d = len(up)
    corners = np.array(np.meshgrid(*[(o, o + e) for o, e in zip(origin, extent)])).reshape(d, -1).T
    lo = (corners @ basis.T).min(axis=0)
    hi = (corners @ basis.T).max(axis=0)
    shape = np.maximum(np.ceil((hi - lo) / h).astype(np.int64), 1) + 1
    cols = np.clip(np.floor((p_x @ basis.T - lo) / h).astype(np.int64), 0, shape - 1)
    flat = np.ravel_multi_index(tuple(cols.T), tuple(shape)) if len(p_x) else np.zeros(0, np.int64)
    top = np.full(int(np.prod(shape)), -np.inf)
    np.maximum.at(top, flat, p_x @ up + 0.5 * spacing)
    if comm_max is not None:
        top = comm_max(top)
    return top[flat]
