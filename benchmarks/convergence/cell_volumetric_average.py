"""Experimental anti-locking pass for the convergence probe (2D only; not a geompm plugin).

After G2P and before the stress update, every particle's volumetric strain rate tr(L) is replaced by
the volume-weighted mean over the particles of its grid cell (the B-bar idea over cells, Coombs et al.
2018, CMAME 338), keeping plane strain (L_zz = 0):  L_p <- L_p + (<tr L>_cell - tr L_p) / 2 (e_x e_x + e_y e_y).

    PYTHONPATH=benchmarks/convergence python benchmarks/convergence/column_probe.py 0.02 0.01 \\
        --stage cell_volumetric_average:CellVolumetricAverage

A per-cell average is not a per-particle function (contract/stages.py), so this is no stage: the probe runs its
``apply(state)`` on the host just before each stress update (column_probe.py wraps the backend's
update_stress).
"""

import numpy as np
from numba import njit



@njit(cache=True)
def cell_average_trace(p_x, p_L, p_vol, origin, h):
    n = p_x.shape[0]
    cx = np.floor((p_x[:, 0] - origin[0]) / h).astype(np.int64)
    cy = np.floor((p_x[:, 1] - origin[1]) / h).astype(np.int64)
    ny = cy.max() + 1
    cell = cx * ny + cy
    m = (cx.max() + 1) * ny
    vol, vol_tr = np.zeros(m), np.zeros(m)
    for p in range(n):
        vol[cell[p]] += p_vol[p]
        vol_tr[cell[p]] += p_vol[p] * (p_L[p, 0, 0] + p_L[p, 1, 1])
    for p in range(n):
        corr = 0.5 * (vol_tr[cell[p]] / vol[cell[p]] - p_L[p, 0, 0] - p_L[p, 1, 1])
        p_L[p, 0, 0] += corr
        p_L[p, 1, 1] += corr


class CellVolumetricAverage:
    label = "cell_volumetric_average"

    def setup(self, scene):
        self.grid = scene.grid

    def apply(self, state):
        cell_average_trace(state.p_x, state.p_L, state.p_vol, self.grid.origin, self.grid.h)
