"""The CUDA backend's own kernels (numba-cuda): P2G by atomics, the grid update, G2P fused with the
volume update, and the step-end reduction the time step, the grid window and the health checks read.

One thread per particle (P2G, G2P) or per node (grid update).  The arithmetic
is that of the dimension-generic reference (tests/support/reference_transfer.py) and
of the CPU kernels (kernels/transfer2d.py, transfer3d.py): weights from the
same B-splines (kernels/shape.py), MLS pseudo-gradients D^-1 w (x_i - x_p),
APIC's C = sum w v_i (x_i - x_p)^T D^-1, FLIP's blend, and
V <- V det(I + dt L).  P2G adds into one grid with atomics, so the sums per
node are taken in thread order: results equal the CPU's to round-off, not
bit for bit.  Shapes: ``d`` (2 or 3) is read from the arrays; per-thread
scratch is a local array of the largest size (3 axes, 4 weights).

Arrays are as on the CPU (mpm/state.py, mpm/grid.py): p_x (n, d),
p_C (n, d, d), p_L (n, 3, 3), p_stress (n, 6) Voigt (xx, yy, zz, xy, yz, xz),
g_mass (nn,), g_mom / g_force / g_vel / g_vel_old (nn, d) over the window
[lo, lo + nloc) of global nodes, last axis fastest.
"""

from __future__ import annotations

import math

from numba import cuda, float64, int64

from geompm.kernels.held_box import fits
from geompm.kernels.shape import axis_stencil
from geompm.kernels.step_end import END_MAXIMA, END_ROW, END_START, particle_row  # noqa: F401  (the layout)
from geompm.kernels.stencil import APIC, FLIP, MLS
from geompm.kernels.volume import update_volume
from geompm.backend.cuda_loops import THREADS, simulated, simulator_call  # noqa: F401  (THREADS: every launch's)


def blocks(n: int) -> int:
    return max(1, (n + THREADS - 1) // THREADS)


#: the CPU kernels' own helpers, called from the kernels: numba-cuda compiles them as device functions on a
#: GPU; the simulator gets them through backend/cuda_loops.simulator_call (array arguments unwrapped)
_volume = simulator_call(update_volume) if simulated() else update_volume
_fits = simulator_call(fits) if simulated() else fits
_particle_row = simulator_call(particle_row) if simulated() else particle_row


@cuda.jit(device=True)
def _axis(xi, kind, inv_h, w, dw):
    """The weights and derivatives of kernels/shape.axis_stencil written into w[0..3], dw[0..3]; returns base."""
    base, wt, dwt = axis_stencil(xi, kind, inv_h)
    for k in range(4):
        w[k] = wt[k]
        dw[k] = dwt[k]
    return base


@cuda.jit(device=True)
def _axes(p, p_x, origin, h, kind, w, dw, base):
    """Particle p's weights and derivatives along each axis into w[a], dw[a] and its first nodes into base."""
    inv_h = 1.0 / h
    for a in range(p_x.shape[1]):
        base[a] = _axis((p_x[p, a] - origin[a]) * inv_h, kind, inv_h, w[a], dw[a])


@cuda.jit(device=True)
def _voigt(a, b):
    """Voigt column of the tensor entry (a, b): xx yy zz xy yz xz (kernels/voigt.py)."""
    if a == b:
        return a
    s = a + b
    if s == 1:
        return 3
    if s == 3:
        return 4
    return 5


@cuda.jit(device=True)
def _node(s, S, d, base, lo, nloc, w, dw, k, gw):
    """Flat window index and weight of stencil entry s (last axis fastest); gradient into gw."""
    t = s
    for a in range(d - 1, -1, -1):
        k[a] = t % S
        t //= S
    idx = 0
    wt = 1.0
    for a in range(d):
        wt *= w[a, k[a]]
        idx = idx * nloc[a] + (base[a] + k[a] - lo[a])
    for a in range(d):
        g = dw[a, k[a]]
        for b in range(d):
            if b != a:
                g *= w[b, k[b]]
        gw[a] = g
    return idx, wt


@cuda.jit(device=True)
def _p2g_entry(s, S, mode, d, p, p_x, p_v, p_C, p_stress, origin, h, base, lo, nloc, w, dw, k, gw, dx, dinv, m, nv,
               split, val):
    """Stencil entry s of particle p: its flat window index; val[0] = w m_p, val[1 + a] = w m_p (v_p + C_p
    (x_i - x_p))_a (plus the force when folded), val[1 + d + a] = -f_scale V_p (sigma_p grad w)_a (split);
    k holds the entry's offsets from base."""
    idx, wt = _node(s, S, d, base, lo, nloc, w, dw, k, gw)
    for a in range(d):
        dx[a] = (base[a] + k[a]) * h + origin[a] - p_x[p, a]
    if mode == MLS:
        for a in range(d):
            gw[a] = dinv * wt * dx[a]
    val[0] = wt * m
    for a in range(d):
        mv = p_v[p, a]
        for b in range(d):
            mv += p_C[p, a, b] * dx[b]
        f = 0.0
        for b in range(d):
            f += p_stress[p, _voigt(a, b)] * gw[b]
        if split:
            val[1 + a] = wt * m * mv
            val[1 + d + a] = nv * f
        else:
            val[1 + a] = wt * m * mv + nv * f
    return idx


@cuda.jit(device=True)
def _add_node(g_mass, g_mom, g_force, idx, val, d, split):
    """Add a node's row (mass, momentum, force: _p2g_entry's layout) into the grid with global atomics."""
    cuda.atomic.add(g_mass, idx, val[0])
    for a in range(d):
        cuda.atomic.add(g_mom, (idx, a), val[1 + a])
        if split:
            cuda.atomic.add(g_force, (idx, a), val[1 + d + a])


@cuda.jit
def p2g(S, mode, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc, split, f_scale, dinv,
        g_mass, g_mom, g_force, halt):
    """m_i += w m_p; (mv)_i += w m_p (v_p + C_p (x_i - x_p)); f_i -= f_scale V_p sigma_p grad w (MLS, mode 3:
    grad w ~ D^-1 w (x_i - x_p)); folded (not split): the force goes into the momentum.  One thread per
    particle, every entry added into the grid with a global atomic."""
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    p = cuda.grid(1)
    if p >= p_x.shape[0]:
        return
    d = p_x.shape[1]
    w = cuda.local.array((3, 4), float64)
    dw = cuda.local.array((3, 4), float64)
    base = cuda.local.array(3, int64)
    k = cuda.local.array(3, int64)
    gw = cuda.local.array(3, float64)
    dx = cuda.local.array(3, float64)
    val = cuda.local.array(7, float64)
    _axes(p, p_x, origin, h, kind, w, dw, base)
    m = p_mass[p]
    nv = -p_vol[p] * f_scale
    for s in range(S ** d):
        idx = _p2g_entry(s, S, mode, d, p, p_x, p_v, p_C, p_stress, origin, h, base, lo, nloc, w, dw, k, gw, dx,
                         dinv, m, nv, split, val)
        _add_node(g_mass, g_mom, g_force, idx, val, d, split)


#: nodes of the shared-memory tile of p2g_tiled (7 float64 columns: 28 KiB of the 48 KiB a block may
#: take statically); the simulator's is small, so that its 3D scenes also take the fallback
TILE = 32 if simulated() else 512
_FAR = 1 << 62


@cuda.jit
def p2g_tiled(S, mode, p_x, p_v, p_C, p_mass, p_vol, p_stress, origin, h, kind, lo, nloc, split, f_scale, dinv,
              g_mass, g_mom, g_force, halt):
    """p2g with a block-local accumulation: the block's particles (consecutive, so neighbours once sorted
    by cell) add into a float64 tile of shared memory over the nodes their stencils cover, and the tile
    is added into the grid once per node, so a node shared by the block's particles takes one global
    atomic instead of one per particle.  A block whose stencils span more than TILE nodes (particles
    not sorted, or a block across a row of cells) adds with global atomics, as p2g."""
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    sh = cuda.shared.array((TILE, 7), float64)
    box = cuda.shared.array((2, 3), int64)
    t = cuda.threadIdx.x
    nt = cuda.blockDim.x
    p = cuda.grid(1)
    live = p < p_x.shape[0]
    d = p_x.shape[1]
    w = cuda.local.array((3, 4), float64)
    dw = cuda.local.array((3, 4), float64)
    base = cuda.local.array(3, int64)
    k = cuda.local.array(3, int64)
    gw = cuda.local.array(3, float64)
    dx = cuda.local.array(3, float64)
    val = cuda.local.array(7, float64)
    ext = cuda.local.array(3, int64)
    if t < 3:
        box[0, t] = _FAR
        box[1, t] = -_FAR
    cuda.syncthreads()
    inv_h = 1.0 / h
    if live:
        for a in range(d):
            base[a] = _axis((p_x[p, a] - origin[a]) * inv_h, kind, inv_h, w[a], dw[a])
            cuda.atomic.min(box, (0, a), base[a])
            cuda.atomic.max(box, (1, a), base[a] + S - 1)
    cuda.syncthreads()
    size = 1
    for a in range(d):
        ext[a] = box[1, a] - box[0, a] + 1
        size *= ext[a]
    ncol = 1 + d + (d if split else 0)
    nst = S ** d
    if size > TILE:  # the same for every thread of the block: no barrier below is skipped by some
        if live:
            m = p_mass[p]
            nv = -p_vol[p] * f_scale
            for s in range(nst):
                idx = _p2g_entry(s, S, mode, d, p, p_x, p_v, p_C, p_stress, origin, h, base, lo, nloc, w, dw, k,
                                 gw, dx, dinv, m, nv, split, val)
                _add_node(g_mass, g_mom, g_force, idx, val, d, split)
        return
    for q in range(t, size, nt):
        for c in range(ncol):
            sh[q, c] = 0.0
    cuda.syncthreads()
    if live:
        m = p_mass[p]
        nv = -p_vol[p] * f_scale
        for s in range(nst):
            _p2g_entry(s, S, mode, d, p, p_x, p_v, p_C, p_stress, origin, h, base, lo, nloc, w, dw, k, gw, dx,
                       dinv, m, nv, split, val)
            q = 0
            for a in range(d):
                q = q * ext[a] + (base[a] + k[a] - box[0, a])
            for c in range(ncol):
                cuda.atomic.add(sh, (q, c), val[c])
    cuda.syncthreads()
    for q in range(t, size, nt):
        used = False
        for c in range(ncol):
            if sh[q, c] != 0.0:
                used = True
        if used:
            rem = q
            idx = 0
            stride = 1
            for a in range(d - 1, -1, -1):
                idx += (box[0, a] + rem % ext[a] - lo[a]) * stride
                stride *= nloc[a]
                rem //= ext[a]
            _add_node(g_mass, g_mom, g_force, idx, sh[q], d, split)


@cuda.jit
def g2p(S, mode, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old, origin, h, kind, lo, nloc, dt,
        flip_ratio, dinv, set_velocity, move, do_gradient, halt):
    """``g2p_particle`` on every particle."""
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    p = cuda.grid(1)
    if p < p_x.shape[0]:
        g2p_particle(p, S, mode, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old, origin, h, kind, lo,
                     nloc, dt, flip_ratio, dinv, set_velocity, move, do_gradient)


@cuda.jit(device=True)
def g2p_particle(p, S, mode, p_x, p_v, p_C, p_L, p_vol, p_rho, p_mass, g_vel, g_vel_old, origin, h, kind, lo, nloc,
                 dt, flip_ratio, dinv, set_velocity, move, do_gradient):
    """Particle p from the grid: v_pic = sum w v_i; L = sum v_i (x) grad w (MLS: L = C); APIC/MLS
    C = sum w v_i (x_i - x_p)^T D^-1 (linear APIC: C = L); FLIP: v = r (v + sum w (v_i - v_old_i)) + (1 - r) v_pic;
    x += dt v_pic; V <- V det(I + dt L), rho = m / V.  Also the first act of cuda_loops.PARTICLE_STEP."""
    d = p_x.shape[1]
    w = cuda.local.array((3, 4), float64)
    dw = cuda.local.array((3, 4), float64)
    base = cuda.local.array(3, int64)
    k = cuda.local.array(3, int64)
    gw = cuda.local.array(3, float64)
    dx = cuda.local.array(3, float64)
    vpic = cuda.local.array(3, float64)
    dv = cuda.local.array(3, float64)
    B = cuda.local.array((3, 3), float64)
    L = cuda.local.array((3, 3), float64)
    for a in range(3):
        vpic[a] = 0.0
        dv[a] = 0.0
        for b in range(3):
            B[a, b] = 0.0
            L[a, b] = 0.0
    _axes(p, p_x, origin, h, kind, w, dw, base)
    nst = S ** d
    for s in range(nst):
        idx, wt = _node(s, S, d, base, lo, nloc, w, dw, k, gw)
        for b in range(d):
            dx[b] = (base[b] + k[b]) * h + origin[b] - p_x[p, b]
        for a in range(d):
            vi = g_vel[idx, a]
            vpic[a] += wt * vi
            if mode == FLIP:
                dv[a] += wt * (vi - g_vel_old[idx, a])
            for b in range(d):
                L[a, b] += vi * gw[b]
                B[a, b] += wt * vi * dx[b]
    if mode == MLS:
        for a in range(d):
            for b in range(d):
                L[a, b] = B[a, b] * dinv
    if set_velocity:
        for a in range(d):
            if mode == FLIP:
                p_v[p, a] = flip_ratio * (p_v[p, a] + dv[a]) + (1.0 - flip_ratio) * vpic[a]
            else:
                p_v[p, a] = vpic[a]
            for b in range(d):
                if (mode == APIC or mode == MLS) and S > 2:
                    p_C[p, a, b] = B[a, b] * dinv
                elif mode == APIC:
                    p_C[p, a, b] = L[a, b]
                else:
                    p_C[p, a, b] = 0.0
    if move:
        for a in range(d):
            p_x[p, a] += dt * vpic[a]
    if do_gradient:
        _volume(p, p_L, p_vol, p_rho, p_mass, L, dt)


@cuda.jit
def zero_grid(g_mass, g_mom, g_force, split, halt):
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    i = cuda.grid(1)
    if i >= g_mass.shape[0]:
        return
    g_mass[i] = 0.0
    for a in range(g_mom.shape[1]):
        g_mom[i, a] = 0.0
        if split:
            g_force[i, a] = 0.0


@cuda.jit(device=True)
def update_node(i, g_mass, g_mom, g_force, gravity, dt, mass_eps, split, g_vel, g_vel_old):
    """Node i of ``grid_update`` (also the first act of cuda_loops.UPDATE_GROUP, the update joined to node rules)."""
    m = g_mass[i]
    for a in range(g_mom.shape[1]):
        if m > mass_eps:
            vo = g_mom[i, a] / m
            if split:
                g_vel_old[i, a] = vo
                g_vel[i, a] = vo + dt * (g_force[i, a] / m + gravity[a])
            else:
                g_vel[i, a] = vo + dt * gravity[a]
        else:
            g_vel[i, a] = 0.0
            if split:
                g_vel_old[i, a] = 0.0


@cuda.jit
def grid_update(g_mass, g_mom, g_force, gravity, dt, mass_eps, split, g_vel, g_vel_old, halt):
    """v_old = (mv)/m, v = v_old + dt (f/m + g) (split), or v = ((mv) + dt f)/m + dt g (folded);
    nodes at or below mass_eps get zero velocity (kernels/grid_update.py)."""
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    i = cuda.grid(1)
    if i < g_mass.shape[0]:
        update_node(i, g_mass, g_mom, g_force, gravity, dt, mass_eps, split, g_vel, g_vel_old)


@cuda.jit
def momentum_to_velocity(g_mass, g_mom, mass_eps, g_vel, halt):
    """MUSL re-map: v = (mv) / m."""
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    i = cuda.grid(1)
    if i >= g_mass.shape[0]:
        return
    m = g_mass[i]
    for a in range(g_mom.shape[1]):
        g_vel[i, a] = g_mom[i, a] / m if m > mass_eps else 0.0


#: what ``step_end`` reduces per material block, in its row: kernels/step_end.py (END_ROW, END_MAXIMA, END_START)


@cuda.jit(device=True)
def _end_is_max(q):
    return q < 6 or 9 <= q < 12


@cuda.jit
def step_end(p_x, p_x0, p_v, p_rho, p_stress, p_mass, gravity, start, end, row, halt):
    """One material block's END_ROW quantities over particles start..end-1, each thread block reduced in shared
    memory and added into ``row`` with one atomic per quantity (maxima by atomic max)."""
    if halt[0] != 0.0:  # a held batch ended before this step (engine/held_step.py)
        return
    t = cuda.threadIdx.x
    p = start + cuda.grid(1)
    acc = cuda.shared.array((THREADS, END_ROW), float64)
    end_start(acc, t)
    if p < end:
        _particle_row(p, p_x, p_x0, p_v, p_rho, p_stress, p_mass, gravity, acc[t])
    end_add(acc, t, row)


@cuda.jit(device=True)
def end_start(acc, t):
    """Thread t's row of the thread block's shared ``acc`` (THREADS, END_ROW) at END_START."""
    for q in range(END_ROW):
        acc[t, q] = -math.inf if _end_is_max(q) else 0.0


@cuda.jit(device=True)
def end_add(acc, t, row):
    """The thread block's rows of ``acc`` reduced in shared memory and added into ``row`` with one atomic per
    quantity (maxima by atomic max); every thread of the block calls it (it synchronises them)."""
    cuda.syncthreads()
    stride = THREADS // 2
    while stride > 0:
        if t < stride:
            for q in range(END_ROW):
                a, b = acc[t, q], acc[t + stride, q]
                if _end_is_max(q):
                    acc[t, q] = a if a >= b else b
                else:
                    acc[t, q] = a + b
        cuda.syncthreads()
        stride //= 2
    if t == 0:
        for q in range(END_ROW):
            if _end_is_max(q):
                cuda.atomic.max(row, q, acc[0, q])
            else:
                cuda.atomic.add(row, q, acc[0, q])


@cuda.jit
def held_gate(rows, rate, box, halt, i):
    """Before step ``i`` of a held batch (engine/held_step.py), one thread: where no earlier step of the batch has
    failed and the state the previous step left (its step-end ``rows`` and largest |L_ii| ``rate[0]``) is outside
    ``box``, ``halt[0] = i``: every later kernel of the batch returns at once, and the host, when it reads the
    tally, learns that the batch took ``i`` steps."""
    if cuda.grid(1) == 0 and halt[0] == 0.0 and not _fits(rows, rate[0], box):
        halt[0] = i
