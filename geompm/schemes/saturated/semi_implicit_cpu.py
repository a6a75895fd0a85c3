"""The semi-implicit two-phase step's passes on the CPU backend (semi_implicit.py; the equations:
projection.py): the saturated scheme's passes (cpu.py, passes.py) and the projection between the split and
the water's G2P.

    project: the predictor's divergences and fill at the particles (the water's G2P into scratch), the drained
             flag, each particle's terms (projection.flux_terms_one), the system assembled (pressure_system),
             the unknown nodes (projection.node_unknown_one), the solve (pressure_solver), the increment
             interpolated to the particles (kernels.smooth_gather_one), its forces scattered
             (pressure_system.increment_forces), both phases corrected (projection.node_correct_one), joined
             (node_join_one), the boundary and obstacle stages once more (remap), the phases split again
             (kernels.node_split_one, dt = 0: the walls' water rules, nothing advanced twice)
    water_step: the water's G2P from the corrected velocities, the increment added to both pressures
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from geompm.kernels.shape import support
from geompm.kernels.stencil import APIC, SCHEMES
from geompm.schemes.saturated import kernels as tp
from geompm.schemes.saturated import pressure_system as ps
from geompm.schemes.saturated import projection as pj
from geompm.schemes.saturated.cpu import SaturatedCpu
from geompm.schemes.saturated.pressure_solver import PressureSolver


class SemiImplicitCpu(SaturatedCpu):
    def __init__(self, cpu, water):
        self.S = support(cpu.scene.grid.kind)  # the stencil's width per axis
        self.nb = (2 * self.S - 1) ** cpu.scene.dim  # a node's band: the offsets two stencils can couple
        self.p_keys = self.p_coef = self.p_store = self.p_div = None
        super().__init__(cpu, water)
        spec = water.pressure_solver
        self.solver = PressureSolver(spec.tolerance, spec.max_iterations, spec.rebuild_interval)
        #: APIC's affine matrices carry the flux divergence (affine_flux); MLS's C is the law's velocity gradient
        self.apic = SCHEMES.index(self.scene.transfer) == APIC

    def _grid(self, cap):
        super()._grid(cap)
        d = self.scene.dim
        self.g_f = np.zeros((cap, 2 * d))
        self.g_dp = np.zeros(cap)
        self.g_unknown = np.zeros(cap, np.int64)
        self.g_scratch = np.zeros((cap, d))
        self.g_scratch_w = np.zeros((cap, d))
        self.band = np.zeros((cap, self.nb))

    def _particles(self, n):
        if n != self.n:
            super()._particles(n)
            d = self.scene.dim
            self.p_keys = np.zeros(n, np.int64)
            self.p_coef, self.p_store, self.p_div = np.zeros(n), np.zeros(n), np.zeros(n)
            self.p_vw2, self.p_Cw2 = np.zeros((n, d)), np.zeros((n, d, d))

    def _arrays(self):
        extra = (self.g_f, self.g_dp, self.g_unknown, self.g_scratch, self.g_scratch_w, self.band)
        parts = () if self.p_keys is None else (self.p_keys, self.p_coef, self.p_store, self.p_div)
        return super()._arrays() + extra + parts

    def project(self, view, dt: float, stages, where: str) -> None:
        be, g, sc = self.be, self.scene.grid, self.scene
        P = self.particles()
        n, nn = self.n, view.g_mass.shape[0]
        lo, nloc = self.window_index(view)
        self._water_g2p(view, self.p_vw2, self.p_Cw2, 0.0)
        be.each(tp.flag_drained_one, n, self.p_fill, P.p_sat, P.p_n, P.p_material, self.table, P.p_drained)
        be.each(pj.flux_terms_one, n, P.p_mass, self.p_wmass, self.p_drag, P.p_vol, P.p_n, self.p_divs, self.p_divw,
                P.p_material, self.table, dt, self.p_coef, self.p_store, self.p_div)
        ps.stencil_keys(P.p_x, g.origin, g.h, g.kind, lo, nloc, self.S, self.p_keys)
        groups = ps.colour_groups(self.p_keys, nn, self.S ** sc.dim)
        band, rhs = self.band[:nn], self.g_dp[:nn]  # the right-hand side in g_dp, until the solve replaces it
        band[:] = 0.0
        rhs[:] = 0.0
        ps.assemble_band(self.tag, *groups, P.p_x, P.p_vol, self.p_coef, self.p_store, self.p_div, dt, g.origin, g.h,
                         g.kind, lo, nloc, band, rhs)
        centre = ps.band_offset(0, 0, 0, self.S, sc.dim)
        be.each(pj.node_unknown_one, nn, self.g_fill[:nn], self.g_w[:nn], band, centre, tp.FREE_SURFACE_FILL,
                be.mass_eps, g.h ** sc.dim, self.g_unknown[:nn])
        unknown = self.g_unknown[:nn]
        counts = np.zeros(nn, np.int64)
        nloc_arr = np.asarray(nloc, np.int64)
        ps.band_row_counts(band, unknown, nloc_arr, self.S, counts)
        indptr = np.zeros(nn + 1, np.int64)
        np.cumsum(counts, out=indptr[1:])
        indices = np.zeros(indptr[-1], np.int32)
        data = np.zeros(indptr[-1])
        ps.band_csr_fill(band, unknown, nloc_arr, self.S, indptr, indices, data)
        A = sp.csr_matrix((data, indices, indptr), shape=(nn, nn))
        b = rhs * unknown
        g_dp = self.g_dp[:nn]
        g_dp[:] = self.solver.solve(A, b, int(unknown.sum()), view.lo, dt, where)
        g_dp *= unknown  # the identity rows' round-off (a warm start from a step where they were unknown)
        be.each(tp.smooth_gather_one, n, self.tag, P.p_x, P.p_drained, g_dp, self._origin, g.h, g.kind, lo, nloc,
                self.p_dps)
        g_f = self.g_f[:nn]
        g_f[:] = 0.0
        ps.increment_forces(self.tag, *groups, P.p_x, P.p_vol, P.p_n, self.p_wmass, g_dp, g.origin, g.h, g.kind, lo,
                            nloc, g_f)
        be.each(pj.node_correct_one, nn, view.g_mass, self.g_w[:nn], g_f, dt, be.mass_eps, view.g_vel,
                self.g_vw[:nn])
        be.each(pj.node_join_one, nn, view.g_mass, view.g_vel, self.g_vw[:nn], self.g_w[:nn], be.mass_eps,
                self.g_rel[:nn], self.g_rel0[:nn], self.g_vpre[:nn])
        stages()
        self._split(view, 0.0, self.g_scratch[:nn], self.g_scratch_w[:nn])

    def water_step(self, view, dt: float) -> None:
        """The water's particle velocity from the corrected grid, and the solve's increment added to both
        pressures (0 where drained, the acting one held at the cavitation pressure)."""
        P = self.particles()
        self.water_velocity(view, dt)
        self.be.each(tp.add_increment_one, self.n, P.p_pore_carried, P.p_pore, self.p_dps, P.p_drained,
                     P.p_material, self.table)

    def affine_flux(self) -> None:
        """APIC only: projection.affine_flux_one on every particle."""
        if self.apic:
            P = self.particles()
            self.be.each(pj.affine_flux_one, self.n, P.p_C, P.p_Cw, P.p_n, self.p_wmass)
