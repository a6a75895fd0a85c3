"""The CPU backend's loops around a stage's per-node and per-particle functions (contract/stages.py).

    node_pass(prm, aux, dt, origin, h, lo, nloc, first, last, g_mass, g_vel, g_vel_old, g_force, g_pore, wet, work,
              out)
        the rule on every node with mass whose global index lies in [first, last] (inclusive, per axis);
        g_pore the nodes' pore water (contact/rules.NODE_PORE) with ``wet``, else one row of zeros for all
    merge_pass(prm, lo, nloc, g_mass, g_vel, g_vel_old, fold_old, nchunks)
        every node merged with its image: summed mass, mass-weighted velocity
    particle_pass(prm, aux, dt, k, start, end, p_x, p_x0, p_v, p_C, p_mass, p_stress, work, out)
        the rule on particles start..end-1 of block k

Each pass splits its range into ``out.shape[0]`` contiguous chunks, one per
thread, each with its own scratch row ``work[c]`` and accumulator row
``out[c]``; the caller zeroes ``out`` and sums its rows in chunk order, so a
reduction (an obstacle's force) depends on the thread count only, as P2G
does (kernels/chunks.py).  A node's position is computed from its global
index exactly as the grid defines it, origin + (lo + i) h.

The merge pass is race-free because each node has at most one ghost
(contract/stages.py: images are not ghosts, and a period of at least 4 cells keeps
two ghosts of one window from sharing an image).
"""

from __future__ import annotations

from geompm.backend.codegen import loops

NODE_BODY = '''
@njit(parallel=True, cache=True)
def node_pass(prm, aux, dt, origin, h, lo, nloc, first, last, g_mass, g_vel, g_vel_old, g_force, g_pore, wet, work,
              out):
    d = g_vel.shape[1]
    b0 = np.empty(d, np.int64)  # the box [first, last] (global) as window indices [b0, b0 + bn)
    bn = np.empty(d, np.int64)
    total = 1
    for a in range(d):
        b0[a] = min(max(first[a] - lo[a], 0), nloc[a])
        bn[a] = max(min(last[a] - lo[a] + 1, nloc[a]) - b0[a], 0)
        total *= bn[a]
    nc = out.shape[0]
    per = (total + nc - 1) // nc
    for c in prange(nc):
        w = work[c]
        x = w[:d]
        scratch = w[d:]
        acc = out[c]
        for q in range(c * per, min(total, (c + 1) * per)):
            rem = q
            idx = 0
            stride = 1
            for a in range(d - 1, -1, -1):
                idx += (b0[a] + rem % bn[a]) * stride
                rem //= bn[a]
                stride *= nloc[a]
            m = g_mass[idx]
            if m <= 0.0:
                continue
            rem = idx
            for a in range(d - 1, -1, -1):
                x[a] = origin[a] + (lo[a] + rem % nloc[a]) * h
                rem //= nloc[a]
            node_rule(prm, aux, dt, x, m, g_vel[idx], g_vel_old[idx], g_force[idx], g_pore[idx if wet else 0],
                      scratch, acc)
'''

#: one node merged with its image (summed mass, mass-weighted velocity): the body of the CPU merge pass
#: and of the CUDA merge kernel (backend/cuda_loops.py), around ``node_image``
MERGE_NODE = '''
@njit(inline="always", cache=True)
def merge_node(prm, lo, nloc, g_mass, g_vel, g_vel_old, fold_old, g):
    d = g_vel.shape[1]
    rem = g
    r = 0
    stride = 1
    moved = False
    inside = True
    for a in range(d - 1, -1, -1):
        gi = lo[a] + rem % nloc[a]
        rem //= nloc[a]
        j = node_image(prm, a, gi) - lo[a]
        moved = moved or j != gi - lo[a]
        inside = inside and 0 <= j < nloc[a]
        r += j * stride
        stride *= nloc[a]
    if not moved or not inside:
        return  # not a ghost, or its image is outside the window: the ghost holds the whole node
    m = g_mass[g] + g_mass[r]
    if m <= 0.0:
        return
    for a in range(d):
        v = (g_mass[g] * g_vel[g, a] + g_mass[r] * g_vel[r, a]) / m
        g_vel[g, a] = v
        g_vel[r, a] = v
        if fold_old:
            vo = (g_mass[g] * g_vel_old[g, a] + g_mass[r] * g_vel_old[r, a]) / m
            g_vel_old[g, a] = vo
            g_vel_old[r, a] = vo
    g_mass[g] = m
    g_mass[r] = m
'''

MERGE_BODY = MERGE_NODE + '''

@njit(parallel=True, cache=True)
def merge_pass(prm, lo, nloc, g_mass, g_vel, g_vel_old, fold_old, nc):
    nn = g_vel.shape[0]
    per = (nn + nc - 1) // nc
    for c in prange(nc):
        for g in range(c * per, min(nn, (c + 1) * per)):
            merge_node(prm, lo, nloc, g_mass, g_vel, g_vel_old, fold_old, g)
'''

PARTICLE_BODY = '''
@njit(parallel=True, cache=True)
def particle_pass(prm, aux, dt, k, start, end, p_x, p_x0, p_v, p_C, p_mass, p_stress, work, out):
    nc = out.shape[0]
    per = (end - start + nc - 1) // nc
    for c in prange(nc):
        w = work[c]
        acc = out[c]
        for p in range(start + c * per, min(end, start + (c + 1) * per)):
            particle_rule(prm, aux, dt, k, p_x[p], p_x0[p], p_v[p], p_C[p], p_mass[p], p_stress[p], w, acc)
'''


def node_loop(rule):
    return loops("node", {"node_rule": rule}, NODE_BODY, ("node_pass",))[0]


def merge_loop(image):
    return loops("merge", {"node_image": image}, MERGE_BODY, ("merge_pass",))[0]


def particle_loop(rule):
    return loops("particle", {"particle_rule": rule}, PARTICLE_BODY, ("particle_pass",))[0]
