"""The saturated scheme's passes on the CUDA backend: device arrays, and the scatters with atomics
(docs/pore-water.md).

The pass order and every pass but the scatters are schemes/saturated/passes.py's, run through the backend's
generated kernels around the per-item functions of schemes/saturated/kernels.py that the CPU loops inline:
one source for both backends, one thread per node or particle (cuda_loops.each_kernel).  The two scatters,
the water's P2G and the smoothing's P2G, add into one grid with atomics, as the solid's P2G does
(cuda_kernels.p2g), so their sums are taken in thread order: results equal the CPU's to round-off
(tests/cuda/cuda_parity.py, scene ``saturated``).  The stable step's terms are one reduction per material
block (speed_terms).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from numba import cuda, float64, int64

from geompm.backend import cuda_kernels as K
from geompm.backend.cuda_loops import simulated, simulator_call
from geompm.schemes.saturated import kernels as tp
from geompm.schemes.saturated import speeds
from geompm.schemes.saturated.passes import SaturatedPasses

#: the particle arrays of saturated soil that live on the device beside backend/cuda.DEVICE_ARRAYS
SATURATED_ARRAYS = ("p_vw", "p_Cw", "p_pore", "p_pore_carried", "p_n", "p_sat", "p_drained", "p_vol0",
                    "p_material")


def _device(fn):
    return simulator_call(fn) if simulated() else fn


_water_scalars = _device(tp.water_scalars_one)
_speed = _device(tp.speed_terms_one)


# -- scatters (atomics) and the stable step's reduction ------------------------------------------------
#: speed_terms' starting values (a minimum's start above any porosity, a maximum's at zero)
SPEED_START = (1.0, 0.0, math.inf, 0.0)


@cuda.jit
def speed_terms(p_v, p_vw, p_n, p_rho, p_sat, row, start, end, out):
    """out <- (min n of the wet particles, max dry density, min saturated density, max squared speed) over
    the particles start..end of one material (kernels.speed_bounds on the CPU)."""
    p = start + cuda.grid(1)
    if p >= end:
        return
    n, rho, sat, v2 = _speed(p, p_v, p_vw, p_n, p_rho, p_sat, row)
    cuda.atomic.min(out, 0, n)
    cuda.atomic.max(out, 1, rho)
    cuda.atomic.min(out, 2, sat)
    cuda.atomic.max(out, 3, v2)


@cuda.jit
def water_p2g(S, p_x, p_vw, p_Cw, affine, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material, table, p_total,
              origin, h, kind, lo, nloc, g_w):
    """The water onto the grid: rows [m_w, m_w (v_w + C_w (x_I - x_p)) (d), s n p V grad N (d), c, V, s p V,
    sigma V (6)] as
    kernels.water_p2g; one thread per particle, every entry added with a global atomic."""
    p = cuda.grid(1)
    if p >= p_x.shape[0]:
        return
    d = p_x.shape[1]
    w, dw = cuda.local.array((3, 4), float64), cuda.local.array((3, 4), float64)
    base, k = cuda.local.array(3, int64), cuda.local.array(3, int64)
    gw, dx = cuda.local.array(3, float64), cuda.local.array(3, float64)
    K._axes(p, p_x, origin, h, kind, w, dw, base)
    m, npv, drag, vol, spv = _water_scalars(p, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material, table)
    for s in range(S ** d):
        idx, wt = K._node(s, S, d, base, lo, nloc, w, dw, k, gw)
        for a in range(d):
            dx[a] = (base[a] + k[a]) * h + origin[a] - p_x[p, a]
        cuda.atomic.add(g_w, (idx, tp.NODE_WATER.mass), wt * m)
        for a in range(d):
            mv = p_vw[p, a]
            if affine:
                for b in range(d):
                    mv += p_Cw[p, a, b] * dx[b]
            cuda.atomic.add(g_w, (idx, tp.MOM + a), wt * m * mv)
            cuda.atomic.add(g_w, (idx, tp.FORCE + a), npv * gw[a])
        cuda.atomic.add(g_w, (idx, tp.NODE_WATER.drag), wt * drag)
        cuda.atomic.add(g_w, (idx, tp.NODE_WATER.volume), wt * vol)
        cuda.atomic.add(g_w, (idx, tp.PV), wt * spv)
        for q in range(6):
            cuda.atomic.add(g_w, (idx, tp.PV + 1 + q), wt * vol * p_total[p, q])


@cuda.jit
def smooth_scatter(S, p_x, p_val, p_drained, p_vol, origin, h, kind, lo, nloc, g_s):
    """g_s[I] += (N V, N V f) of the particles that hold pressure (kernels.smooth_scatter)."""
    p = cuda.grid(1)
    if p >= p_x.shape[0] or p_drained[p] != 0.0:
        return
    w, dw = cuda.local.array((3, 4), float64), cuda.local.array((3, 4), float64)
    base, k, gw = cuda.local.array(3, int64), cuda.local.array(3, int64), cuda.local.array(3, float64)
    K._axes(p, p_x, origin, h, kind, w, dw, base)
    d = p_x.shape[1]
    v = p_vol[p]
    vf = v * p_val[p]
    for s in range(S ** d):
        idx, wt = K._node(s, S, d, base, lo, nloc, w, dw, k, gw)
        cuda.atomic.add(g_s, (idx, 0), wt * v)
        cuda.atomic.add(g_s, (idx, 1), wt * vf)


@cuda.jit
def zero_rows(g):
    i = cuda.grid(1)
    if i < g.shape[0]:
        for a in range(g.shape[1]):
            g[i, a] = 0.0


class SaturatedCuda(SaturatedPasses):
    """The saturated passes on the device (their CPU twin: schemes/saturated/cpu.SaturatedCpu)."""

    device_arrays = SATURATED_ARRAYS

    def _zeros(self, shape):
        out = cuda.device_array(shape, np.float64)
        if out.size:
            out.copy_to_device(np.zeros(shape))
        return out

    def _on_device(self, array):
        return cuda.to_device(np.ascontiguousarray(array, dtype=np.float64))

    def _on_device_int(self, array):
        return cuda.to_device(np.ascontiguousarray(array, dtype=np.int64))

    def particles(self):
        return SimpleNamespace(**self.be._device())

    def window_index(self, view):
        """The window's corner and size on the device: the backend's copies, sent again only when they change."""
        return self.be._small("lo", view.lo), self.be._small("nloc", view.nloc)

    def _scatter(self, view, lo, nloc, P) -> None:
        be, g, n, nn = self.be, self.scene.grid, self.n, view.g_mass.shape[0]
        K.zero_grid[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, view.g_force, True, be.halt())
        zero_rows[K.blocks(nn), K.THREADS](self.g_w[:nn])
        if n:
            K.p2g[K.blocks(n), K.THREADS](be.S, be.mode, P.p_x, P.p_v, P.p_C, P.p_mass, P.p_vol, self.p_total,
                                          be._origin, g.h, g.kind, lo, nloc, True, 1.0, self.scene.apic_dinv,
                                          view.g_mass, view.g_mom, view.g_force, be.halt())
            water_p2g[K.blocks(n), K.THREADS](be.S, P.p_x, P.p_vw, P.p_Cw, self.affine, self.p_wmass, self.p_drag,
                                              P.p_vol, P.p_n, P.p_pore, P.p_sat, P.p_material, self.table, self.p_total,
                                              be._origin,
                                              g.h, g.kind, lo, nloc, self.g_w[:nn])

    def _smooth_scatter(self, view, lo, nloc, P, p_val) -> None:
        be, g, n, nn = self.be, self.scene.grid, self.n, view.g_mass.shape[0]
        zero_rows[K.blocks(nn), K.THREADS](self.g_vp[:nn])
        if n:
            smooth_scatter[K.blocks(n), K.THREADS](be.S, P.p_x, p_val, P.p_drained, P.p_vol, be._origin, g.h,
                                                   g.kind, lo, nloc, self.g_vp[:nn])

    def end_reductions(self, backend) -> None:
        """The next step's speed terms of each material block into the backend's tally (read with the step's end)."""
        dev = backend._device()
        for k, (s, e) in enumerate(backend.state.blocks):
            out = backend.tally.slots(("saturated_speed", k), SPEED_START)
            if e > s:
                speed_terms[K.blocks(e - s), K.THREADS](dev["p_v"], dev["p_vw"], dev["p_n"], dev["p_rho"],
                                                        dev["p_sat"], self.table[k], s, e, out)

    def wave_speed(self, law_speeds) -> float:
        """The largest of the undrained, water and skeleton wave speeds (schemes/saturated/speeds.py) from one
        reduction per material block, the blocks' extremes reduced over the ranks before they are combined;
        ``law_speeds[k]``: the law's speed over block k's densities."""
        be, st, pw = self.be, self.be.state, self.pw
        rows = np.tile(np.array(speeds.EMPTY_ROW), (len(st.blocks), 1))
        for k, (s, e) in enumerate(st.blocks):
            if e <= s:
                continue
            n_min, rho_d, rho_sat, v2 = be.ended_slots(("saturated_speed", k))
            rows[k] = (law_speeds[k], -n_min, rho_d, -rho_sat, math.sqrt(v2))
        rows = np.asarray(be.domain.comm.max(rows.ravel())).reshape(rows.shape)
        c = speeds.combined_speeds(rows, pw, self.scene.material_names,
                                   lambda k: speeds.out_of_range(self.scene, be.host_state(), pw, k))
        return max(c["undrained"], c["water"], c["skeleton"])
