"""An obstacle's contact force as pressures on its faces (docs/obstacles.md).

The rules share each contact node's and guard correction's force among the
faces under its patch (sdf_field.face_lattice_ids, contact/force.record_on_face);
``spread_matrix`` evens the faces' forces over about one cell, and
``face_pressure_step`` turns them, every step, into the normal pressure
p = -F.n / A (pushing in positive), the shear traction |F - (F.n) n| / A and
the running maximum of p with its time.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange


def spread_matrix(centres, normals, areas, h):
    """The sparse (faces, faces) matrix that shares each face's recorded force with its neighbours: face k's
    force goes to the faces j within h whose normals are within 60 degrees of its own, in proportion to
    A_j (1 - |c_j - c_k| / h).  Columns sum to 1, so the total force is kept exactly.

    A contact node's force is shared among the faces under four samples of its patch
    (sdf_field.face_lattice_ids), h/2 apart.  Where the faces are smaller than that (a refined STL has
    triangles of h^2/8 to h^2/2) some get no sample and the raw pressure is a checkerboard; the hat of
    half-width h evens it out over about one cell, the patch a node stands for.  Faces h apart (a 2D
    outline, a grid-aligned box) do not exchange anything: the hat is zero there."""
    from scipy.sparse import coo_matrix
    from scipy.spatial import cKDTree

    nf = len(centres)
    pairs = cKDTree(centres).query_pairs(h, output_type="ndarray").reshape(-1, 2)
    rows = np.concatenate([np.arange(nf), pairs[:, 0], pairs[:, 1]])  # receiving face j
    cols = np.concatenate([np.arange(nf), pairs[:, 1], pairs[:, 0]])  # source face k
    r = np.linalg.norm(centres[rows] - centres[cols], axis=1)
    w = areas[rows] * np.maximum(0.0, 1.0 - r / h) * ((normals[rows] * normals[cols]).sum(axis=1) > 0.5)
    w /= np.bincount(cols, w, nf)[cols]
    return coo_matrix((w, (rows, cols)), shape=(nf, nf)).tocsr()


@njit(cache=True, parallel=True)
def face_pressure_step(indptr, indices, data, raw, normal, area, time, force, p, shear, pmax, tmax):
    """force = S raw (S the CSR spread matrix, raw (faces d,) the faces' recorded forces [N; N/m in 2D]),
    then per face the pressure, the shear traction [Pa] and the running maximum, in place (one pass)."""
    nf, d = normal.shape
    for j in prange(nf):
        f0 = f1 = f2 = 0.0
        for q in range(indptr[j], indptr[j + 1]):
            w = data[q]
            k = indices[q] * d
            f0 += w * raw[k]
            f1 += w * raw[k + 1]
            if d == 3:
                f2 += w * raw[k + 2]
        force[j, 0] = f0
        force[j, 1] = f1
        fn = f0 * normal[j, 0] + f1 * normal[j, 1]
        if d == 3:
            force[j, 2] = f2
            fn += f2 * normal[j, 2]
        t2 = 0.0
        for a in range(d):
            t = force[j, a] - fn * normal[j, a]
            t2 += t * t
        p[j] = -fn / area[j]
        shear[j] = math.sqrt(t2) / area[j]
        if p[j] > pmax[j]:
            pmax[j] = p[j]
            tmax[j] = time
