"""Experiment for issue 38: a block-coloured P2G against geompm's chunked one, on the bench scene fluid3d (MLS,
force folded: the per-node update is mass and momentum only).

    python benchmarks/experiments/block_coloured_p2g.py [--cells 64] [--block 4] [--repeats 10] [--block-order]

geompm's P2G (kernels/transfer3d.p2g_3d) gives each thread ("chunk") a private copy of the grid window, zeroes
it, scatters its particles into it and sums the copies.  The block-coloured P2G of Hu et al. (2018, ACM TOG
37(4):150; read in yuanming-hu/taichi_mpm, src/transfer.cpp) instead groups the particles by blocks of B^3
base nodes; a block's particles touch (B + 2)^3 nodes, which it accumulates in a scratch small enough for L1
and adds to the one global grid once; blocks of equal coordinate parity (8 colours in 3D) never share a node,
so each colour's blocks run in parallel without atomics, private grids or a reduction.

Run it with NUMBA_SLP_VECTORIZE=1 and =0 (each with its own NUMBA_CACHE_DIR): numba leaves LLVM's SLP
vectoriser off by default (numba.core.config.SLP_VECTORIZE = 0), and it is what packs a node's four updates.

Printed: ns per particle of each P2G (best of --repeats, 2 threads unless NUMBA_NUM_THREADS says otherwise;
then 4 x --repeats rounds of the two in turn: their medians and the quartiles of the per-round ratio),
the cost of grouping the particles by block (a counting sort of an index, per step or per sort), and the
largest difference of the two grids (they must agree to round-off).  The scene's particles are in the order
geompm's spatial sort leaves them.

With ``--block-order`` it then stores the particles block by block (what a sort by block would leave) and
measures a coloured P2G whose blocks' scratch is widened by a one-node slack (no index array, no grouping per
step) against the chunked P2G on that order, and how many particles drift past the slack over
``--drift-steps`` steps without a sort (docs/performance.md, issue 38).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit, prange

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from geompm.api import scene_from_dict  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402
from geompm.kernels.shape import axis_stencil  # noqa: E402


@njit(cache=True)
def group_by_block(p_x, origin, inv_h, kind, lo, block, nb):
    """(order, start, bcoord): particle indices grouped by the block of their stencil's base node (counting
    sort), each block's range in ``order`` and its block coordinates (nblocks, 3)."""
    n = p_x.shape[0]
    key = np.empty(n, np.int64)
    for p in range(n):
        b0 = (axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)[0] - lo[0]) // block
        b1 = (axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)[0] - lo[1]) // block
        b2 = (axis_stencil((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h)[0] - lo[2]) // block
        key[p] = (b0 * nb[1] + b1) * nb[2] + b2
    nblk = nb[0] * nb[1] * nb[2]
    count = np.zeros(nblk + 1, np.int64)
    for p in range(n):
        count[key[p] + 1] += 1
    for b in range(nblk):
        count[b + 1] += count[b]
    fill = count[:-1].copy()
    order = np.empty(n, np.int64)
    for p in range(n):
        order[fill[key[p]]] = p
        fill[key[p]] += 1
    return order, count


@njit(cache=True)
def colour_lists(count, nb):
    """Non-empty blocks sorted by colour (parity of the block coordinates): (blocks, colour_start)."""
    nblk = nb[0] * nb[1] * nb[2]
    blocks = np.empty(nblk, np.int64)
    cstart = np.zeros(9, np.int64)
    k = 0
    for colour in range(8):
        cstart[colour] = k
        for b in range(nblk):
            if count[b + 1] == count[b]:
                continue
            b2 = b % nb[2]
            b1 = (b // nb[2]) % nb[1]
            b0 = b // (nb[1] * nb[2])
            if (b0 % 2) * 4 + (b1 % 2) * 2 + (b2 % 2) == colour:
                blocks[k] = b
                k += 1
    cstart[8] = k
    return blocks[:k], cstart


@njit(cache=True, inline="always")
def _block_origin(b, nb, block, slack):
    """Window-relative first node of block b's scratch (its first base node less ``slack`` along each axis)."""
    b2 = b % nb[2]
    b1 = (b // nb[2]) % nb[1]
    b0 = b // (nb[1] * nb[2])
    return b0 * block - slack, b1 * block - slack, b2 * block - slack


@njit(parallel=True, fastmath=True, cache=True)
def p2g_coloured(order, count, blocks, cstart, nb, block, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h,
                 kind, lo, nloc, f_scale, mls_dinv, g, zero):
    """MLS P2G with the force folded into the momentum, block by block, colour by colour; g (nn, 4) zeroed by
    the caller: [m, mv_x, mv_y, mv_z].  The four updates of a node are made alike (the mass gets a term
    zero[0] k w_k, zero[0] = 0 at run time, so that fastmath cannot fold it away): the form LLVM's SLP
    vectoriser packs into one 4-wide multiply-add (with NUMBA_SLP_VECTORIZE=1; without it the mass's own
    form measured the same)."""
    z = zero[0]
    inv_h = 1.0 / h
    sy = nloc[2]
    sx = nloc[1] * nloc[2]
    W = block + 2
    for colour in range(8):
        for t in prange(cstart[colour + 1] - cstart[colour]):
            b = blocks[cstart[colour] + t]
            n0, n1, n2 = _block_origin(b, nb, block, 0)  # the block's first base node, window-relative
            s = np.zeros((W, W, W, 4))
            for q in range(count[b], count[b + 1]):
                p = order[q]
                bx, wx, _dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
                by, wy, _dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
                bz, wz, _dz = axis_stencil((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h)
                lx, ly, lz = bx - lo[0] - n0, by - lo[1] - n1, bz - lo[2] - n2
                _scatter_mls(p, bx, wx, by, wy, bz, wz, lx, ly, lz, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h,
                             f_scale, mls_dinv, z, s)
            for i in range(W):
                gx = n0 + i
                if gx >= nloc[0]:
                    break
                for j in range(W):
                    gy = n1 + j
                    if gy >= nloc[1]:
                        break
                    for k in range(W):
                        gz = n2 + k
                        if gz >= nloc[2]:
                            break
                        row = g[gx * sx + gy * sy + gz]
                        for a in range(4):
                            row[a] += s[i, j, k, a]


@njit(parallel=True, fastmath=True, cache=True)
def p2g_coloured_slack(count, blocks, cstart, nb, block, slack, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h,
                       kind, lo, nloc, f_scale, mls_dinv, g, zero, missed_by_block):
    """p2g_coloured for particles stored in block order (block b's particles are count[b]..count[b+1]-1, no
    index array), each block's scratch widened by ``slack`` nodes on every side, so that a particle may drift
    up to slack cells out of the block it was sorted into: (B + 2 + 2 slack)^d nodes, at most 2B so that
    blocks of one colour still share no node.  A particle beyond that is not scattered and counted in
    ``missed_by_block[b]`` (a backend would add those few particles in a serial pass after the colours)."""
    z = zero[0]
    inv_h = 1.0 / h
    sy = nloc[2]
    sx = nloc[1] * nloc[2]
    W = block + 2 + 2 * slack
    top = block - 1 + 2 * slack  # the highest first-stencil-node index inside the scratch
    for colour in range(8):
        for t in prange(cstart[colour + 1] - cstart[colour]):
            b = blocks[cstart[colour] + t]
            n0, n1, n2 = _block_origin(b, nb, block, slack)
            s = np.zeros((W, W, W, 4))
            missed = 0
            for p in range(count[b], count[b + 1]):
                bx, wx, _dx = axis_stencil((p_x[p, 0] - origin[0]) * inv_h, kind, inv_h)
                by, wy, _dy = axis_stencil((p_x[p, 1] - origin[1]) * inv_h, kind, inv_h)
                bz, wz, _dz = axis_stencil((p_x[p, 2] - origin[2]) * inv_h, kind, inv_h)
                lx, ly, lz = bx - lo[0] - n0, by - lo[1] - n1, bz - lo[2] - n2
                if lx < 0 or ly < 0 or lz < 0 or lx > top or ly > top or lz > top:
                    missed += 1
                    continue
                _scatter_mls(p, bx, wx, by, wy, bz, wz, lx, ly, lz, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h,
                             f_scale, mls_dinv, z, s)
            missed_by_block[b] = missed
            for i in range(W):
                gx = n0 + i
                if gx < 0 or gx >= nloc[0]:
                    continue
                for j in range(W):
                    gy = n1 + j
                    if gy < 0 or gy >= nloc[1]:
                        continue
                    for k in range(W):
                        gz = n2 + k
                        if gz < 0 or gz >= nloc[2]:
                            continue
                        row = g[gx * sx + gy * sy + gz]
                        for a in range(4):
                            row[a] += s[i, j, k, a]


@njit(cache=True)
def drifted(p_x, count, nb, block, slack, origin, inv_h, kind, lo):
    """Particles whose first stencil node has left their block (as sorted) by more than ``slack`` nodes."""
    out = 0
    for b in range(count.shape[0] - 1):
        b2 = b % nb[2]
        b1 = (b // nb[2]) % nb[1]
        b0 = b // (nb[1] * nb[2])
        for p in range(count[b], count[b + 1]):
            for a, bb in ((0, b0), (1, b1), (2, b2)):
                base = axis_stencil((p_x[p, a] - origin[a]) * inv_h, kind, inv_h)[0] - lo[a] - bb * block
                if base < -slack or base > block - 1 + slack:
                    out += 1
                    break
    return out

@njit(cache=True, inline="always")
def _scatter_mls(p, bx, wx, by, wy, bz, wz, lx, ly, lz, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, f_scale,
                 mls_dinv, z, s):
    """MLS P2G of particle p, force folded, into the scratch s whose first stencil node is (lx, ly, lz): the four
    updates of a node made alike (the mass gets a term z k w_k, z = 0 at run time, so that fastmath cannot fold
    it away), the form LLVM's SLP vectoriser packs into one 4-wide multiply-add."""
    m = p_mass[p]
    ox = bx * h + origin[0] - p_x[p, 0]
    oy = by * h + origin[1] - p_x[p, 1]
    oz = bz * h + origin[2] - p_x[p, 2]
    nv = -p_vol[p] * f_scale
    sxx, syy, szz = nv * p_stress[p, 0], nv * p_stress[p, 1], nv * p_stress[p, 2]
    sxy, syz, sxz = nv * p_stress[p, 3], nv * p_stress[p, 4], nv * p_stress[p, 5]
    a00 = m * p_C[p, 0, 0] + mls_dinv * sxx
    a01 = m * p_C[p, 0, 1] + mls_dinv * sxy
    a02 = m * p_C[p, 0, 2] + mls_dinv * sxz
    a10 = m * p_C[p, 1, 0] + mls_dinv * sxy
    a11 = m * p_C[p, 1, 1] + mls_dinv * syy
    a12 = m * p_C[p, 1, 2] + mls_dinv * syz
    a20 = m * p_C[p, 2, 0] + mls_dinv * sxz
    a21 = m * p_C[p, 2, 1] + mls_dinv * syz
    a22 = m * p_C[p, 2, 2] + mls_dinv * szz
    q0 = m * p_v[p, 0] + a00 * ox + a01 * oy + a02 * oz
    q1 = m * p_v[p, 1] + a10 * ox + a11 * oy + a12 * oz
    q2 = m * p_v[p, 2] + a20 * ox + a21 * oy + a22 * oz
    ax0, ax1, ax2 = h * a00, h * a10, h * a20
    ay0, ay1, ay2 = h * a01, h * a11, h * a21
    az0, az1, az2 = h * a02, h * a12, h * a22
    for i in range(3):
        wi = wx[i]
        qi0, qi1, qi2 = q0 + i * ax0, q1 + i * ax1, q2 + i * ax2
        for j in range(3):
            wij = wi * wy[j]
            mij = wij * m
            Q0, Q1, Q2 = wij * (qi0 + j * ay0), wij * (qi1 + j * ay1), wij * (qi2 + j * ay2)
            R0, R1, R2 = wij * az0, wij * az1, wij * az2
            Rm = wij * z
            for k in range(3):
                wk = wz[k]
                kwk = k * wk
                r = s[lx + i, ly + j, lz + k]
                r[0] += mij * wk + Rm * kwk
                r[1] += Q0 * wk + R0 * kwk
                r[2] += Q1 * wk + R1 * kwk
                r[3] += Q2 * wk + R2 * kwk


def best(fn, repeats):
    fn()
    t = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        t = min(t, time.perf_counter() - t0)
    return t


def interleaved(a, b, rounds):
    """Times of a and b run in turn (the order alternating each round), and the per-round ratios b / a: a
    drift of the machine falls on both."""
    ta, tb = [], []
    for r in range(rounds):
        for fn, out in (((a, ta), (b, tb)) if r % 2 == 0 else ((b, tb), (a, ta))):
            t0 = time.perf_counter()
            fn()
            out.append(time.perf_counter() - t0)
    return np.array(ta), np.array(tb), np.array(tb) / np.array(ta)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cells", type=int, default=64)
    ap.add_argument("--block", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--block-order", action="store_true",
                    help="then store the particles in block order and measure the coloured P2G with a drift slack "
                         "of one node against the chunked P2G on that order, and the drift over --drift-steps "
                         "steps without a sort")
    ap.add_argument("--drift-steps", type=int, default=100)
    a = ap.parse_args()
    case = json.loads((ROOT / "benchmarks" / "fluid3d.json").read_text())
    case["solver"]["transfer"] = "mls"
    case["solver"]["sort_interval"] = 0  # the experiment sorts once, below
    case["grid"]["cell_size"] = 1.0 / a.cells
    sim = Simulation(scene_from_dict(case, base_dir=ROOT / "benchmarks"))
    for _ in range(5):
        sim.step(sim.stable_dt())
    be, sc, st = sim.backend, sim.scene, sim.state
    be.sort_particles()
    view = be.window()
    g = sc.grid
    dt = sim.dt
    nn = view.g_mass.shape[0]
    n = st.n

    def chunked():
        be.p2g(view, dt)

    t_chunked = best(chunked, a.repeats)
    ref_m, ref_mv = view.g_mass.copy(), view.g_mom.copy()

    inv_h = 1.0 / g.h
    nb = (view.nloc + a.block - 1) // a.block
    order, count = group_by_block(st.p_x, g.origin, inv_h, g.kind, view.lo, a.block, nb)
    blocks, cstart = colour_lists(count, nb)
    t_group = best(lambda: group_by_block(st.p_x, g.origin, inv_h, g.kind, view.lo, a.block, nb), a.repeats)
    grid = np.zeros((nn, 4))
    zero = np.zeros(1)

    def coloured():
        grid[:] = 0.0
        p2g_coloured(order, count, blocks, cstart, nb, a.block, st.p_x, st.p_v, st.p_C, st.p_mass, st.p_vol,
                     st.p_stress, g.origin, g.h, g.kind, view.lo, view.nloc, dt, sc.apic_dinv, grid, zero)

    t_col = best(coloured, a.repeats)
    ta, tb, ratio = interleaved(chunked, coloured, 4 * a.repeats)
    dm = np.abs(grid[:, 0] - ref_m).max() / np.abs(ref_m).max()
    dmv = np.abs(grid[:, 1:] - ref_mv).max() / np.abs(ref_mv).max()
    import numba
    print(json.dumps({"particles": n, "nodes": nn, "threads": numba.get_num_threads(), "block": a.block,
                      "blocks": int(len(blocks)), "particles_per_block": n / max(len(blocks), 1),
                      "chunked_ns": 1e9 * t_chunked / n, "coloured_ns": 1e9 * t_col / n,
                      "group_ns": 1e9 * t_group / n, "diff_mass": float(dm), "diff_momentum": float(dmv),
                      "interleaved_rounds": len(ratio), "chunked_median_ns": 1e9 * float(np.median(ta)) / n,
                      "coloured_median_ns": 1e9 * float(np.median(tb)) / n,
                      "coloured_over_chunked": [float(q) for q in np.quantile(ratio, [0.25, 0.5, 0.75])]}))
    if a.block_order:
        block_order(a, sim, view, order, count, blocks, cstart, nb, chunked, grid, zero)
    return 0


def block_order(a, sim, view, order, count, blocks, cstart, nb, chunked, grid, zero):
    """The particles stored in block order (what a sort by block would leave): the chunked P2G and the coloured
    P2G with a one-node drift slack on that order, interleaved; then the particles that drift out of their
    block's slack over the following steps, which a backend would add in a serial pass or re-sort for."""
    sc, st = sim.scene, sim.state
    g = sc.grid
    dt = sim.dt
    n = st.n
    st.reorder(order)
    slack = 1
    missed = np.zeros(len(count) - 1, np.int64)

    def coloured_slack():
        grid[:] = 0.0
        p2g_coloured_slack(count, blocks, cstart, nb, a.block, slack, st.p_x, st.p_v, st.p_C, st.p_mass, st.p_vol,
                           st.p_stress, g.origin, g.h, g.kind, view.lo, view.nloc, dt, sc.apic_dinv, grid, zero,
                           missed)

    t_chunked = best(chunked, a.repeats)
    ref_m, ref_mv = view.g_mass.copy(), view.g_mom.copy()
    t_slack = best(coloured_slack, a.repeats)
    dm = np.abs(grid[:, 0] - ref_m).max() / np.abs(ref_m).max()
    dmv = np.abs(grid[:, 1:] - ref_mv).max() / np.abs(ref_mv).max()
    ta, tb, ratio = interleaved(chunked, coloured_slack, 4 * a.repeats)
    lo0 = view.lo.copy()
    drift = {}
    for k in range(1, a.drift_steps + 1):
        sim.step(sim.stable_dt())
        if k in (1, 2, 5, 10, 20, 50, 100, 200, 500) or k == a.drift_steps:
            drift[k] = int(drifted(st.p_x, count, nb, a.block, slack, g.origin, 1.0 / g.h, g.kind, lo0))
    print(json.dumps({"block_order": True, "particles": n, "slack_nodes": slack, "missed_at_sort": int(missed.sum()),
                      "chunked_ns": 1e9 * t_chunked / n, "coloured_slack_ns": 1e9 * t_slack / n,
                      "diff_mass": float(dm), "diff_momentum": float(dmv),
                      "chunked_median_ns": 1e9 * float(np.median(ta)) / n,
                      "coloured_slack_median_ns": 1e9 * float(np.median(tb)) / n,
                      "coloured_slack_over_chunked": [float(q) for q in np.quantile(ratio, [0.25, 0.5, 0.75])],
                      "drifted_beyond_slack_after_steps": drift, "max_speed": float(np.abs(st.p_v).max()),
                      "dt": sim.dt, "cell": g.h}))


if __name__ == "__main__":
    sys.exit(main())
