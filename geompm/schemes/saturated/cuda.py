"""The saturated scheme's passes on the CUDA backend: the GPU twin of schemes/saturated/cpu.py (docs/pore-water.md).

The same passes in the same order (schemes/saturated/scheme.py). The node passes (mixture, relative
velocity, fill, split), the gathers (the water's G2P, the pressure seen through the grid) and the particle
passes (total stress, drained flag, pressure increment, porosity, the stable step's terms) call the very
per-item functions of schemes/saturated/kernels.py that the CPU loops inline: one source for both backends, one
thread per node or particle. The two scatters, the water's P2G and the smoothing's P2G, add into one grid
with atomics, as the solid's P2G does (cuda_kernels.p2g), so their sums are taken in thread order: results
equal the CPU's to round-off (tests/cuda/cuda_parity.py, scene ``saturated``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import cuda, float64, int64

from geompm.backend import cuda_kernels as K
from geompm.backend.cuda_loops import simulated, simulator_call
from geompm.schemes.saturated import kernels as tp
from geompm.schemes.saturated import speeds
from geompm.kernels.stencil import AFFINE

#: the particle arrays of saturated soil that live on the device beside backend/cuda.DEVICE_ARRAYS
SATURATED_ARRAYS = ("p_vw", "p_Cw", "p_pore", "p_pore_carried", "p_n", "p_sat", "p_drained", "p_vol0",
                    "p_material")


def _device(fn):
    return simulator_call(fn) if simulated() else fn


_prepare = _device(tp.prepare_one)
_water_scalars = _device(tp.water_scalars_one)
_mixture = _device(tp.node_mixture_one)
_relative = _device(tp.node_relative_one)
_fill = _device(tp.one_node_fill)
_split = _device(tp.node_split_one)
_water_g2p = _device(tp.water_g2p_one)
_flag = _device(tp.flag_drained_one)
_increment = _device(tp.pressure_increment_one)
_add = _device(tp.add_increment_one)
_porosity = _device(tp.porosity_one)
_gather = _device(tp.smooth_gather_one)
_speed = _device(tp.speed_terms_one)


# -- particle passes -------------------------------------------------------------------------------------
@cuda.jit
def prepare(p_stress, p_pore, p_n, p_sat, p_vol, p_material, table, p_total, p_wmass, p_drag):
    p = cuda.grid(1)
    if p < p_stress.shape[0]:
        _prepare(p, p_stress, p_pore, p_n, p_sat, p_vol, p_material, table, p_total, p_wmass, p_drag)


@cuda.jit
def water_g2p(S, p_x, p_vw, p_Cw, affine, apic_dinv, p_divw, p_divs, p_fill, g_vw, g_vs, g_fill, origin, h, kind,
              lo, nloc):
    p = cuda.grid(1)
    if p < p_x.shape[0]:
        _water_g2p(p, S, p_x, p_vw, p_Cw, affine, apic_dinv, p_divw, p_divs, p_fill, g_vw, g_vs, g_fill, origin, h,
                   kind, lo, nloc)


@cuda.jit
def flag_drained(p_fill, p_sat, p_n, p_material, table, p_drained):
    p = cuda.grid(1)
    if p < p_fill.shape[0]:
        _flag(p, p_fill, p_sat, p_n, p_material, table, p_drained)


@cuda.jit
def pressure_increment(p_dp, p_divw, p_divs, p_n, p_material, table, dt):
    p = cuda.grid(1)
    if p < p_dp.shape[0]:
        _increment(p, p_dp, p_divw, p_divs, p_n, p_material, table, dt)


@cuda.jit
def add_increment(p_carried, p_pore, p_dp, p_drained):
    p = cuda.grid(1)
    if p < p_pore.shape[0]:
        _add(p, p_carried, p_pore, p_dp, p_drained)


@cuda.jit
def porosity(p_n, p_vol, p_vol0, p_material, table):
    p = cuda.grid(1)
    if p < p_n.shape[0]:
        _porosity(p, p_n, p_vol, p_vol0, p_material, table)


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


# -- scatters (atomics) ------------------------------------------------------------------------------------
@cuda.jit
def water_p2g(S, p_x, p_vw, p_Cw, affine, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material, table, origin,
              h, kind, lo, nloc, g_w):
    """The water onto the grid: rows [m_w, m_w (v_w + C_w (x_I - x_p)) (d), s n p V grad N (d), c, V] as
    kernels.water_p2g; one thread per particle, every entry added with a global atomic."""
    p = cuda.grid(1)
    if p >= p_x.shape[0]:
        return
    d = p_x.shape[1]
    w, dw = cuda.local.array((3, 4), float64), cuda.local.array((3, 4), float64)
    base, k = cuda.local.array(3, int64), cuda.local.array(3, int64)
    gw, dx = cuda.local.array(3, float64), cuda.local.array(3, float64)
    K._axes(p, p_x, origin, h, kind, w, dw, base)
    m, npv, drag, vol = _water_scalars(p, p_wmass, p_drag, p_vol, p_n, p_pore, p_sat, p_material, table)
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
def smooth_nodes(g_s, g_p):
    i = cuda.grid(1)
    if i < g_p.shape[0]:
        g_p[i] = g_s[i, 1] / g_s[i, 0] if g_s[i, 0] > 0.0 else 0.0


@cuda.jit
def smooth_gather(S, p_x, p_drained, g_p, origin, h, kind, lo, nloc, p_out):
    p = cuda.grid(1)
    if p < p_x.shape[0]:
        _gather(p, S, p_x, p_drained, g_p, origin, h, kind, lo, nloc, p_out)


@cuda.jit
def zero_rows(g):
    i = cuda.grid(1)
    if i < g.shape[0]:
        for a in range(g.shape[1]):
            g[i, a] = 0.0


# -- node passes -------------------------------------------------------------------------------------------
@cuda.jit
def node_mixture(g_mass, g_mom, g_w, mass_eps, g_rel):
    i = cuda.grid(1)
    if i < g_mom.shape[0]:
        _mixture(i, g_mass, g_mom, g_w, mass_eps, g_rel)


@cuda.jit
def node_fill(g_w, walls, origin, h, lo, nloc, cell_volume, g_fill):
    i = cuda.grid(1)
    if i < g_fill.shape[0]:
        g_fill[i] = _fill(i, g_w, walls, origin, h, lo, nloc, lo.shape[0], cell_volume)


@cuda.jit
def node_relative(g_mass, g_vel, g_vel_old, g_w, gravity, dt, mass_eps, g_rel, g_rel0, g_vpre):
    """node_relative_one, and the mixture's velocity kept in g_vpre for node_split."""
    i = cuda.grid(1)
    if i < g_vel.shape[0]:
        _relative(i, g_mass, g_vel, g_vel_old, g_w, gravity, dt, mass_eps, g_rel, g_rel0)
        for a in range(g_vel.shape[1]):
            g_vpre[i, a] = g_vel[i, a]


@cuda.jit
def node_split(g_mass, g_vel, g_vpre, g_w, g_rel, g_rel0, walls, origin, h, lo, nloc, gravity, dt, mass_eps, g_vw):
    i = cuda.grid(1)
    if i < g_vel.shape[0]:
        _split(i, g_mass, g_vel, g_vpre, g_w, g_rel, g_rel0, walls, origin, h, lo, nloc, gravity, dt, mass_eps,
               g_vw)


class SaturatedCuda:
    """The saturated passes on the device (their CPU twin: schemes/saturated/cpu.SaturatedCpu)."""

    device_arrays = SATURATED_ARRAYS

    def __init__(self, backend, water):
        self.be = backend
        self.scene = backend.scene
        self.pw = water
        self.width = tp.WATER_WIDTH
        self.smoothing = bool(self.pw.smoothing)
        self.affine = self.scene.transfer in AFFINE
        self.table = cuda.to_device(np.ascontiguousarray(self.pw.table, dtype=np.float64))
        self.walls = cuda.to_device(np.ascontiguousarray(self.pw.walls, dtype=np.float64))
        self.cap = 0
        self.n = -1
        self._grid(1024)

    def _grid(self, cap):
        d, f = self.scene.dim, np.float64
        self.cap = cap
        self.g_w = cuda.device_array((cap, self.width), f)
        self.g_s = cuda.device_array((cap, 2), f)
        self.g_p = cuda.device_array(cap, f)
        self.g_rel = cuda.device_array((cap, d), f)
        self.g_rel0 = cuda.device_array((cap, d), f)
        self.g_vw = cuda.device_array((cap, d), f)
        self.g_vpre = cuda.device_array((cap, d), f)
        self.g_fill = cuda.device_array(cap, f)

    def _particles(self, n):
        if n != self.n:
            self.n = n
            f = np.float64
            self.p_total = cuda.device_array((n, 6), f)
            self.p_wmass, self.p_drag = cuda.device_array(n, f), cuda.device_array(n, f)
            self.p_divw, self.p_divs = cuda.device_array(n, f), cuda.device_array(n, f)
            self.p_dp, self.p_dps = cuda.device_array(n, f), cuda.device_array(n, f)
            self.p_fill = cuda.device_array(n, f)

    def nbytes(self) -> int:
        grid = (self.g_w, self.g_s, self.g_p, self.g_rel, self.g_rel0, self.g_vw, self.g_vpre, self.g_fill)
        parts = () if self.n < 0 else (self.p_total, self.p_wmass, self.p_drag, self.p_divw, self.p_divs,
                                       self.p_dp, self.p_dps, self.p_fill)
        return sum(a.nbytes for a in grid + parts)

    def _nodes(self, view) -> int:
        nn = view.g_mass.shape[0]
        if nn > self.cap:
            self._grid(int(nn * 1.25) + 64)
        return nn

    def _smooth(self, dev, lo, nloc, nn, p_val, p_out, view, halo):
        """p_out = S p_val (kernels.smooth_scatter, smooth_gather)."""
        be, g, n = self.be, self.scene.grid, self.n
        zero_rows[K.blocks(nn), K.THREADS](self.g_s[:nn])
        smooth_scatter[K.blocks(n), K.THREADS](be.S, dev["p_x"], p_val, dev["p_drained"], dev["p_vol"], be._origin,
                                               g.h, g.kind, lo, nloc, self.g_s[:nn])
        halo((self.g_s[:nn],))
        smooth_nodes[K.blocks(nn), K.THREADS](self.g_s[:nn], self.g_p[:nn])
        smooth_gather[K.blocks(n), K.THREADS](be.S, dev["p_x"], dev["p_drained"], self.g_p[:nn], be._origin, g.h,
                                              g.kind, lo, nloc, p_out)

    def p2g(self, view, halo) -> None:
        be, st, g = self.be, self.be.state, self.scene.grid
        dev = be._device()
        n = st.n
        self._particles(n)
        nn = self._nodes(view)
        lo, nloc = cuda.to_device(view.lo), cuda.to_device(view.nloc)
        K.zero_grid[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, view.g_force, True)
        zero_rows[K.blocks(nn), K.THREADS](self.g_w[:nn])
        if n:
            if self.smoothing:
                self._smooth(dev, lo, nloc, nn, dev["p_pore_carried"], dev["p_pore"], view, halo)
            prepare[K.blocks(n), K.THREADS](dev["p_stress"], dev["p_pore"], dev["p_n"], dev["p_sat"], dev["p_vol"],
                                            dev["p_material"], self.table, self.p_total, self.p_wmass, self.p_drag)
            K.p2g[K.blocks(n), K.THREADS](be.S, be.mode, dev["p_x"], dev["p_v"], dev["p_C"], dev["p_mass"],
                                          dev["p_vol"], self.p_total, be._origin, g.h, g.kind, lo, nloc, True, 1.0,
                                          self.scene.apic_dinv, view.g_mass, view.g_mom, view.g_force)
            water_p2g[K.blocks(n), K.THREADS](be.S, dev["p_x"], dev["p_vw"], dev["p_Cw"], self.affine, self.p_wmass,
                                              self.p_drag, dev["p_vol"], dev["p_n"], dev["p_pore"], dev["p_sat"],
                                              dev["p_material"], self.table, be._origin, g.h, g.kind, lo, nloc,
                                              self.g_w[:nn])
        halo((view.g_mass, view.g_mom, view.g_force, self.g_w[:nn]))
        node_fill[K.blocks(nn), K.THREADS](self.g_w[:nn], self.walls, be._origin, g.h, lo, nloc,
                                           g.h ** self.scene.dim, self.g_fill[:nn])
        node_mixture[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, self.g_w[:nn], be.mass_eps, self.g_rel[:nn])

    def snapshot(self, view, dt: float) -> None:
        nn = view.g_vel.shape[0]
        node_relative[K.blocks(nn), K.THREADS](view.g_mass, view.g_vel, view.g_vel_old, self.g_w[:nn],
                                               self.be._gravity, dt, self.be.mass_eps, self.g_rel[:nn],
                                               self.g_rel0[:nn], self.g_vpre[:nn])

    def split(self, view, dt: float) -> None:
        g, nn = self.scene.grid, view.g_vel.shape[0]
        node_split[K.blocks(nn), K.THREADS](view.g_mass, view.g_vel, self.g_vpre[:nn], self.g_w[:nn],
                                            self.g_rel[:nn], self.g_rel0[:nn], self.walls, self.be._origin, g.h,
                                            cuda.to_device(view.lo), cuda.to_device(view.nloc), self.be._gravity, dt,
                                            self.be.mass_eps, self.g_vw[:nn])

    def water_g2p(self, view, dt: float, halo) -> None:
        be, g, nn, n = self.be, self.scene.grid, view.g_vel.shape[0], self.n
        if n <= 0:
            return
        dev = be._device()
        lo, nloc = cuda.to_device(view.lo), cuda.to_device(view.nloc)
        blocks = K.blocks(n)
        water_g2p[blocks, K.THREADS](be.S, dev["p_x"], dev["p_vw"], dev["p_Cw"], self.affine, self.scene.apic_dinv,
                                     self.p_divw, self.p_divs, self.p_fill, self.g_vw[:nn], view.g_vel,
                                     self.g_fill[:nn], be._origin, g.h, g.kind, lo, nloc)
        flag_drained[blocks, K.THREADS](self.p_fill, dev["p_sat"], dev["p_n"], dev["p_material"], self.table,
                                        dev["p_drained"])
        pressure_increment[blocks, K.THREADS](self.p_dp, self.p_divw, self.p_divs, dev["p_n"], dev["p_material"],
                                              self.table, dt)
        dp = self.p_dp
        if self.smoothing:
            self._smooth(dev, lo, nloc, nn, self.p_dp, self.p_dps, view, halo)
            dp = self.p_dps
        add_increment[blocks, K.THREADS](dev["p_pore_carried"], dev["p_pore"], dp, dev["p_drained"])

    def porosity(self) -> None:
        n = self.be.state.n
        if n:
            dev = self.be._device()
            porosity[K.blocks(n), K.THREADS](dev["p_n"], dev["p_vol"], dev["p_vol0"], dev["p_material"], self.table)

    def wave_speed(self, law_speeds) -> float:
        """The largest of the undrained, water and skeleton wave speeds (schemes/saturated/speeds.py) from one
        reduction per material block, the blocks' extremes reduced over the ranks before they are combined;
        ``law_speeds[k]``: the law's speed over block k's densities."""
        be, st, pw = self.be, self.be.state, self.pw
        dev = be._device()
        rows = np.tile(np.array(speeds.EMPTY_ROW), (len(st.blocks), 1))
        for k, (s, e) in enumerate(st.blocks):
            if e <= s:
                continue
            out = cuda.to_device(np.array([1.0, 0.0, math.inf, 0.0]))
            speed_terms[K.blocks(e - s), K.THREADS](dev["p_v"], dev["p_vw"], dev["p_n"], dev["p_rho"], dev["p_sat"],
                                                    self.table[k], s, e, out)
            n_min, rho_d, rho_sat, v2 = out.copy_to_host()
            rows[k] = (law_speeds[k], -n_min, rho_d, -rho_sat, math.sqrt(v2))
        rows = np.asarray(be.domain.comm.max(rows.ravel())).reshape(rows.shape)
        c = speeds.combined_speeds(rows, pw)
        return max(c["undrained"], c["water"], c["skeleton"])
