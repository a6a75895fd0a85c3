"""The semi-implicit step's pressure solve against the number of nodes (docs/pore-water.md, The semi-implicit
step): a cube of saturated soil (n = 0.4, rho_s = 2650 kg/m3, k = 1e-5 m/s, water's K_w = 2.2e9 Pa) on a 3D
grid, one particle per cell at its centre, linear or quadratic shape functions, its top drained (dp = 0) and the
other faces impermeable, the step of the skeleton (cfl 0.4 of a 100 m/s wave); the system assembled by the
scheme's own kernels (schemes/saturated/pressure_system.py) for a random divergence field, then solved by its
solver (pressure_solver.py: CG with pyamg's smoothed aggregation) from zero, with a fresh hierarchy and once
more on it (the hierarchy's cost: the difference).  Prints one JSON line per size: nodes, unknowns, seconds to assemble, to build the hierarchy and to
solve, CG iterations, and the bytes per node the band, the matrix and the hierarchy hold.

    python benchmarks/pore_water/solve_scaling.py [linear|quadratic] [NODES ...]
"""

import json
import sys
import time

import numpy as np
import scipy.sparse as sp

from geompm.kernels.stencil import stencil_tag
from geompm.schemes.saturated import pressure_system as ps
from geompm.schemes.saturated.pressure_solver import PressureSolver

KIND = {"linear": 0, "quadratic": 1}


def system(nodes_target: int, shape: str):
    kind = KIND[shape]
    S = kind + 2
    tag = stencil_tag(kind)
    m = max(int(round(nodes_target ** (1 / 3))) - (S - 1), 2)  # cells per side
    h = 1.0 / m
    nloc = np.array([m + S - 1] * 3, np.int64)
    nn = int(np.prod(nloc))
    lo = np.zeros(3, np.int64)
    origin = np.zeros(3)
    c = (np.arange(m) + 0.5) * h
    X, Y, Z = np.meshgrid(c, c, c, indexing="ij")
    p_x = np.ascontiguousarray(np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1))
    n = p_x.shape[0]
    rho_s, nw, rho_w, kw, k = 2650.0, 0.4, 1000.0, 2.2e9, 1e-5
    rs, rw, q = (1 - nw) * rho_s, nw * rho_w, nw * nw * 9.80665 * rho_w / (k * rho_w)
    dt = 0.4 * h / 100.0
    g, b = nw / rw - (1 - nw) / rs, 1 / rw + 1 / rs
    coef = (1 - nw) ** 2 / rs + nw ** 2 / rw - dt * q * g * g / (1 + dt * q * b)
    p_vol = np.full(n, h ** 3)
    p_coef = np.full(n, coef)
    p_store = np.full(n, nw / kw)
    p_div = np.random.default_rng(1).normal(size=n) * 1e-3
    t0 = time.perf_counter()
    keys = np.zeros(n, np.int64)
    ps.stencil_keys(p_x, origin, h, kind, lo, nloc, S, keys)
    groups = ps.colour_groups(keys, nn, S ** 3)
    band = np.zeros((nn, (2 * S - 1) ** 3))
    rhs = np.zeros(nn)
    ps.assemble_band(tag, *groups, p_x, p_vol, p_coef, p_store, p_div, dt, origin, h, kind, lo, nloc, band, rhs)
    idx = np.indices(tuple(nloc)).reshape(3, -1).T + lo
    unknown = ((band[:, ps.band_offset(0, 0, 0, S, 3)] > 0) & (idx[:, 1] < m)).astype(np.int64)  # top drained
    counts = np.zeros(nn, np.int64)
    ps.band_row_counts(band, unknown, nloc, S, counts)
    indptr = np.zeros(nn + 1, np.int64)
    np.cumsum(counts, out=indptr[1:])
    indices = np.zeros(indptr[-1], np.int32)
    data = np.zeros(indptr[-1])
    ps.band_csr_fill(band, unknown, nloc, S, indptr, indices, data)
    A = sp.csr_matrix((data, indices, indptr), shape=(nn, nn))
    return A, rhs * unknown, int(unknown.sum()), dt, time.perf_counter() - t0, band.nbytes


def main(argv):
    shape = argv[0] if argv and argv[0] in KIND else "linear"
    sizes = [int(a) for a in argv if a.isdigit()] or [10_000, 100_000, 1_000_000]
    system(1000, shape)  # compile
    for target in sizes:
        A, b, unknowns, dt, assemble, band_bytes = system(target, shape)
        solver = PressureSolver(1e-8, 1000, 20)
        solver.solve(A, b, unknowns, np.zeros(3), dt, "scaling")  # a fresh hierarchy, then the solve
        first = (solver.iterations, solver.seconds)
        solver._x = None
        solver.solve(A, b, unknowns, np.zeros(3), dt, "scaling")  # on the same hierarchy, from zero
        build = first[1] - solver.seconds
        ml_bytes = sum(x.nbytes for x in (A.data, A.indices, A.indptr))
        print(json.dumps({"shape": shape, "nodes": b.size, "unknowns": unknowns, "assemble_s": round(assemble, 4),
                          "hierarchy_s": round(build, 4), "iterations": first[0], "solve_s": round(first[1], 4),
                          "iterations_reused": solver.iterations, "solve_reused_s": round(solver.seconds, 4),
                          "residual": solver.residual, "band_bytes_per_node": band_bytes / b.size,
                          "matrix_bytes_per_node": ml_bytes / b.size}), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
