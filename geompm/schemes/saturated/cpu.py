"""The saturated scheme's passes on the CPU backend (schemes/saturated/kernels.py; docs/pore-water.md).

The scheme (schemes/saturated/scheme.py) runs the CPU backend's own P2G (the solids, from the total stress),
grid update, stages and G2P (the solids) with these passes around them:

    p2g (the acting pressure p = S p_carried through smooth_scatter and smooth_gather, prepare, solid P2G on
    the total stress, water P2G, the halo summed, node fill, node_mixture) -> grid update (the mixture) ->
    stages before BOUNDARY -> snapshot (node_relative) -> BOUNDARY and OBSTACLE stages -> split (node_split)
    -> water_g2p (water G2P, flag_drained, pressure_increment, its increment through the smoothing,
    add_increment to both pressures) -> solid G2P -> particle stages -> porosity (porosity_update) ->
    effective-stress update (the laws, unchanged)

``halo(arrays)`` adds the neighbouring ranks' partial sums of window arrays on the nodes they share
(parallel/slabs.py; nothing in one process): after every scatter and before anything reads its sums.
The CUDA backend runs the same passes (schemes/saturated/cuda.py) around the same per-item functions.
"""

from __future__ import annotations

import numpy as np

from geompm.schemes.saturated import kernels as tp
from geompm.kernels.stencil import AFFINE


class SaturatedCpu:
    #: the CPU keeps every particle array on the host
    device_arrays = ()

    def __init__(self, cpu, water):
        self.cpu = cpu
        self.scene = cpu.scene
        self.pw = water
        d = self.scene.dim
        self.width = tp.WATER_WIDTH
        self.nchunks = cpu.buffers.nchunks
        self.cap = 0
        self.n = -1
        self._grid(1024)
        self.smoothing = bool(self.pw.smoothing)
        self.affine = self.scene.transfer in AFFINE  # the water's transfer follows the solid's

    def _grid(self, cap):
        d = self.scene.dim
        self.cap = cap
        self.c_w = np.zeros((self.nchunks, cap, self.width))
        self.g_w = np.zeros((cap, self.width))
        self.g_vp = np.zeros((cap, 2))
        self.g_rel = np.zeros((cap, d))
        self.g_rel0 = np.zeros((cap, d))
        self.g_vw = np.zeros((cap, d))
        self.g_vpre = np.zeros((cap, d))
        self.g_fill = np.zeros(cap)
        self.g_p = np.zeros(cap)

    def _particles(self):
        n = self.cpu.state.n
        if n != self.n:
            self.n = n
            self.p_total = np.zeros((n, 6))
            self.p_wmass = np.zeros(n)
            self.p_drag = np.zeros(n)
            self.p_divw = np.zeros(n)
            self.p_divs = np.zeros(n)
            self.p_dp = np.zeros(n)
            self.p_fill = np.ones(n)
            self.p_dps = np.zeros(n)

    def nbytes(self) -> int:
        grid = (self.c_w, self.g_w, self.g_vp, self.g_rel, self.g_rel0, self.g_vw, self.g_vpre, self.g_fill, self.g_p)
        return sum(a.nbytes for a in grid) + (
            0 if self.n < 0 else sum(a.nbytes for a in (self.p_total, self.p_wmass, self.p_drag, self.p_divw,
                                                         self.p_divs, self.p_dp, self.p_fill,
                                                         self.p_dps)))

    def _nodes(self, view) -> int:
        nn = view.g_mass.shape[0]
        if nn > self.cap:
            self._grid(int(nn * 1.25) + 64)
        return nn

    def _smooth(self, view, halo, p_val, p_out) -> None:
        """p_out = S p_val, the field seen through the grid (kernels.smooth_scatter, smooth_gather)."""
        st, g, nn = self.cpu.state, self.scene.grid, view.g_mass.shape[0]
        tp.smooth_scatter(self.cpu.tag, st.p_x, p_val, st.p_drained, st.p_vol, g.origin, g.h, g.kind, view.lo,
                          view.nloc, self.c_w[:, :nn], self.g_vp[:nn])
        halo((self.g_vp[:nn],))
        tp.smooth_gather(self.cpu.tag, st.p_x, st.p_drained, self.g_vp[:nn], g.origin, g.h, g.kind, view.lo,
                         view.nloc, self.g_p[:nn], p_out)

    def p2g(self, view, halo) -> None:
        """Both phases onto the grid; leaves the mixture on the view (mass, momentum, internal force), the
        relative velocity w in g_rel and the nodes' fill."""
        cpu, st, g, pw = self.cpu, self.cpu.state, self.scene.grid, self.pw
        self._particles()
        nn = self._nodes(view)
        if self.smoothing:
            self._smooth(view, halo, st.p_pore_carried, st.p_pore)
        tp.prepare(st.p_stress, st.p_pore, st.p_n, st.p_sat, st.p_vol, st.p_material, pw.table, self.p_total,
                   self.p_wmass, self.p_drag)
        cpu.p2g_kernel(cpu.tag, cpu.scheme, st.p_x, st.p_v, st.p_C, st.p_mass, st.p_vol, self.p_total, g.origin,
                       g.h, g.kind, view.lo, view.nloc, cpu.buffers.c_grid, True, 1.0, self.scene.apic_dinv,
                       view.g_mass, view.g_mom, view.g_force)
        tp.water_p2g(cpu.tag, st.p_x, st.p_vw, st.p_Cw, self.affine, self.p_wmass, self.p_drag, st.p_vol, st.p_n, st.p_pore, st.p_sat,
                     st.p_material, pw.table, g.origin, g.h, g.kind, view.lo, view.nloc, self.c_w[:, :nn],
                     self.g_w[:nn])
        tp.sum_chunks(self.c_w[:, :nn], self.g_w[:nn])
        halo((view.g_mass, view.g_mom, view.g_force, self.g_w[:nn]))
        tp.node_fill(self.g_w[:nn], pw.walls, g.origin, g.h, view.lo, view.nloc, g.h ** self.scene.dim,
                     self.g_fill[:nn])
        tp.node_mixture(view.g_mass, view.g_mom, self.g_w[:nn], cpu.mass_eps, self.g_rel[:nn])

    def snapshot(self, view, dt: float) -> None:
        """Once gravity, the loads and the damping have acted on the mixture: the relative velocity after
        the step, and the mixture's velocities before the boundaries and obstacles act (node_split finds
        what they changed)."""
        nn = view.g_vel.shape[0]
        tp.node_relative(view.g_mass, view.g_vel, view.g_vel_old, self.g_w[:nn], self.scene.gravity, dt,
                         self.cpu.mass_eps, self.g_rel[:nn], self.g_rel0[:nn])
        self.g_vpre[:nn] = view.g_vel

    def split(self, view, dt: float) -> None:
        g, nn = self.scene.grid, view.g_vel.shape[0]
        tp.node_split(view.g_mass, view.g_vel, self.g_vpre[:nn], self.g_w[:nn], self.g_rel[:nn], self.g_rel0[:nn],
                      self.pw.walls, g.origin, g.h, view.lo, view.nloc, self.scene.gravity, dt, self.cpu.mass_eps,
                      self.g_vw[:nn])

    def water_g2p(self, view, dt: float, halo) -> None:
        """The water's particle velocity and the pore pressure's step, at the particles before they move."""
        st, g, nn, pw = self.cpu.state, self.scene.grid, view.g_vel.shape[0], self.pw
        tp.water_g2p(self.cpu.tag, st.p_x, st.p_vw, st.p_Cw, self.affine, self.scene.apic_dinv, self.p_divw,
                     self.p_divs, self.p_fill, self.g_vw[:nn],
                     view.g_vel, self.g_fill[:nn], g.origin, g.h, g.kind, view.lo, view.nloc)
        tp.flag_drained(self.p_fill, st.p_sat, st.p_n, st.p_material, pw.table, st.p_drained)
        tp.pressure_increment(self.p_dp, self.p_divw, self.p_divs, st.p_n, st.p_material, pw.table, dt)
        dp = self.p_dp
        if self.smoothing:
            self._smooth(view, halo, self.p_dp, self.p_dps)
            dp = self.p_dps
        tp.add_increment(st.p_pore_carried, st.p_pore, dp, st.p_drained)

    def porosity(self) -> None:
        st = self.cpu.state
        tp.porosity_update(st.p_n, st.p_vol, st.p_vol0, st.p_material, self.pw.table)
