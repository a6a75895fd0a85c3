"""The saturated scheme's passes, one order for every backend (docs/pore-water.md; schemes/saturated/scheme.py).

    p2g: the acting pressure p = max(S p_carried, p_cav) (scatter, halo, smooth_node_one, smooth_gather_one,
         cavitation_one; without the smoothing acting_one), the total
         stress, water mass and drag (prepare_one), the solid's P2G on the total stress, the water's P2G, the
         halo summed, the nodes' fill (node_fill_one), the mixture (node_mixture_one) and the pore water the
         contact rules' friction reads (node_pore_one, on the view: mpm/grid.GridView.g_pore)
    -> grid update (the mixture) -> stages before BOUNDARY
    -> snapshot: the relative velocity, drag implicit (node_snapshot_one) -> BOUNDARY and OBSTACLE stages
    -> split: solid and water velocities (node_split_one)
    -> water_g2p: the water's G2P (water_g2p_one), the drained flag, the pressure's increment, the increment
       seen through the grid, both pressures advanced
    -> solid G2P -> particle stages -> porosity (porosity_one) -> effective-stress update (the laws)

Every pass but the two scatters is a per-item function of schemes/saturated/kernels.py run through the
backend's generated loop (``Backend.each``): one source for the CPU and the GPU.  A backend's subclass gives
what differs: where arrays live (``_zeros``, ``_on_device``, ``particles``, ``window_index``) and the scatters
(the water's P2G, the smoothing's P2G, the solid's P2G from the total stress): schemes/saturated/cpu.py,
cuda.py.

``halo(arrays)`` adds the neighbouring ranks' partial sums of window arrays on the nodes they share
(parallel/slabs.py; nothing in one process): after every scatter and before anything reads its sums.
"""

from __future__ import annotations

import math

import numpy as np

from geompm.kernels.stencil import AFFINE, FLIP, SCHEMES, stencil_tag
from geompm.schemes.saturated import kernels as tp
from geompm.schemes.saturated import head, mirror
from geompm.schemes.saturated.solids import WIDTH


class SaturatedPasses:
    #: the scheme's particle arrays a device backend keeps on the device
    device_arrays: tuple[str, ...] = ()

    def __init__(self, backend, water):
        self.be = backend
        self.scene = backend.scene
        self.pw = water
        self.tag = stencil_tag(self.scene.grid.kind)
        self.smoothing = bool(water.smoothing)
        self.affine = self.scene.transfer in AFFINE  # the water's transfer follows the solid's
        self.flips = SCHEMES.index(self.scene.transfer) == FLIP  # and its FLIP blend (the solid's ratio)
        self.table = self._on_device(water.table)
        self.walls = self._on_device(water.walls)
        self.gravity = self._on_device(self.scene.gravity)
        self._origin = self._on_device(self.scene.grid.origin)
        self.cap = 0
        self.n = -1
        self._grid(1024)
        #: the periodic axes (Stage.periodic_axes): every scatter is folded onto its images (fold_one)
        self.periodic = sorted({a for st in self.scene.stages for a in st.periodic_axes()})
        self._images = (None, None, None)  # (lo, nloc, the window's image table)
        self._no_solid = None  # zeros (cap, solids.WIDTH) for a scene without a rigid solid
        self.g_old = self.p_vw2 = self.p_Cw2 = None  # MUSL's scratch: the split's old velocity, a second G2P
        self._solid_host = self._solid = self.g_solid = None
        self._time = 0.0  # the step's time (p2g), at which a held head is taken

    # -- what a backend gives --------------------------------------------------------------------------
    def _zeros(self, shape):
        raise NotImplementedError

    def _on_device(self, array):
        raise NotImplementedError

    def _on_device_int(self, array):
        """An int64 table where the kernels read it."""
        raise NotImplementedError

    def particles(self):
        """The particle arrays by attribute (p_x, p_pore, ...) where the backend's kernels read them."""
        raise NotImplementedError

    def window_index(self, view):
        """The window's first node and size per axis (lo, nloc) where the kernels read them."""
        raise NotImplementedError

    def _scatter(self, view, lo, nloc, P) -> None:
        """The solid's P2G from the total stress (P.p_total) and the water's P2G into g_w (both zeroed
        first), summed over this process's particles."""
        raise NotImplementedError

    def _smooth_scatter(self, view, lo, nloc, P, p_val) -> None:
        """g_vp[I] = (sum N V, sum N V f) over the particles that hold pressure."""
        raise NotImplementedError

    # -- arrays ------------------------------------------------------------------------------------------
    def _grid(self, cap):
        d = self.scene.dim
        self.cap = cap
        self.g_w = self._zeros((cap, tp.WATER_WIDTH))
        self.g_vp = self._zeros((cap, 2))
        self.g_p = self._zeros(cap)
        self.g_rel = self._zeros((cap, d))
        self.g_rel0 = self._zeros((cap, d))
        self.g_vw = self._zeros((cap, d))
        self.g_vwold = self._zeros((cap, d))
        self.g_vpre = self._zeros((cap, d))
        self.g_fill = self._zeros(cap)
        self.g_pore = self._zeros((cap, 7))
        self.g_image = self._zeros((cap, d))  # the velocities mirror.node_mirror_one reads

    def _particles(self, n):
        if n != self.n:
            self.n = n
            self.p_total = self._zeros((n, 6))
            self.p_wmass, self.p_drag = self._zeros(n), self._zeros(n)
            self.p_divw, self.p_divs = self._zeros(n), self._zeros(n)
            self.p_dp, self.p_dps = self._zeros(n), self._zeros(n)
            self.p_fill = self._zeros(n)

    def _arrays(self):
        grid = (self.g_w, self.g_vp, self.g_p, self.g_rel, self.g_rel0, self.g_vw, self.g_vwold, self.g_vpre,
                self.g_fill, self.g_pore, self.g_image)
        parts = () if self.n < 0 else (self.p_total, self.p_wmass, self.p_drag, self.p_divw, self.p_divs,
                                       self.p_dp, self.p_dps, self.p_fill)
        musl = tuple(a for a in (self.g_old, self.p_vw2, self.p_Cw2) if a is not None)
        return grid + parts + musl

    def nbytes(self) -> int:
        return sum(a.nbytes for a in self._arrays())

    def _nodes(self, view) -> int:
        nn = view.g_mass.shape[0]
        if nn > self.cap:
            self._grid(int(nn * 1.25) + 64)
        return nn

    # -- periodic axes ------------------------------------------------------------------------------------
    def _image_table(self, view):
        """g_image[i]: the window index of node i's periodic image where node i is a ghost (its global index
        on a periodic axis outside 0..ncells-1: node i and i + ncells are one node), else -1; made on the
        host once per window."""
        lo, nloc, table = self._images
        if lo is not None and np.array_equal(lo, view.lo) and np.array_equal(nloc, view.nloc):
            return table
        ncells = self.scene.grid.ncells
        idx = np.indices(tuple(int(k) for k in view.nloc)).reshape(len(view.nloc), -1).T + np.asarray(view.lo)
        image = idx.copy()
        for a in self.periodic:
            image[:, a] %= int(ncells[a])
        ghost = (image != idx).any(axis=1)
        local = image - np.asarray(view.lo)
        inside = ((local >= 0) & (local < np.asarray(view.nloc))).all(axis=1)
        flat = np.ravel_multi_index(tuple(np.clip(local, 0, np.asarray(view.nloc) - 1).T), tuple(view.nloc))
        host = np.where(ghost & inside, flat, -1).astype(np.int64)
        table = self._on_device_int(host)
        self._images = (np.array(view.lo), np.array(view.nloc), table)
        return table

    def fold(self, view, arrays) -> None:
        """Each (nn, width) array of sums folded over the periodic axes (nothing without one)."""
        if not self.periodic:
            return
        table = self._image_table(view)
        for rows in arrays:
            if rows is not None:
                self.be.each(tp.fold_one, view.g_mass.shape[0], table, rows)

    # -- the passes --------------------------------------------------------------------------------------
    def _smooth(self, view, lo, nloc, halo, P, p_val, p_out, then=()) -> None:
        """p_out = S p_val, the field seen through the grid; ``then``: particle passes ((fn, args) pairs) that
        read p_out only at their own particle, run in turn with the gather (Backend.each_in_turn)."""
        g, nn = self.scene.grid, view.g_mass.shape[0]
        self._smooth_scatter(view, lo, nloc, P, p_val)
        halo((self.g_vp[:nn],))
        self.fold(view, (self.g_vp[:nn],))
        self.be.each(tp.smooth_node_one, nn, self.g_vp[:nn], self.g_p[:nn])
        self.be.each_in_turn(self.n, ((tp.smooth_gather_one, (self.tag, P.p_x, P.p_drained, self.g_p[:nn],
                                                               self._origin, g.h, g.kind, lo, nloc, p_out)),) + then)

    def _solids(self, view, time):
        """The rigid solids' rows of the window's nodes (nn, solids.WIDTH): fill, drained contact mark,
        impermeable surface's normal, depth inside a fixed solid (solids.SolidFill; zeros without a solid),
        where the kernels read it."""
        nn = view.g_mass.shape[0]
        solids = self.pw.solids
        if not solids:
            if self._no_solid is None or self._no_solid.shape[0] < nn:
                self._no_solid = self._zeros((self.cap, WIDTH))
            return self._no_solid[:nn]
        rows = solids.window(view.lo, view.nloc, time)
        if rows is not self._solid_host:
            self._solid_host, self._solid = rows, self._on_device(rows)
        return self._solid

    def p2g(self, view, halo, time: float) -> None:
        """Both phases onto the grid; leaves the mixture on the view (mass, momentum, internal force), the
        relative velocity w in g_rel and the nodes' fill (the rigid solids' share added)."""
        be, g = self.be, self.scene.grid
        self._time = time
        P = self.particles()
        self._particles(self.be.state.n)
        nn = self._nodes(view)
        lo, nloc = self.window_index(view)
        # the acting pressure, then the total stress, water mass and drag from it, particle by particle
        prepare = ((tp.prepare_one, (P.p_stress, P.p_pore, P.p_n, P.p_sat, P.p_vol, P.p_material, self.table,
                                     self.p_total, self.p_wmass, self.p_drag)),)
        if self.smoothing:
            self._smooth(view, lo, nloc, halo, P, P.p_pore_carried, P.p_pore,
                         ((tp.cavitation_one, (P.p_pore, P.p_material, self.table)),) + prepare)
        else:
            be.each_in_turn(self.n, ((tp.acting_one, (P.p_pore, P.p_pore_carried, P.p_drained, P.p_material,
                                                       self.table)),) + prepare)
        self._scatter(view, lo, nloc, P)
        if self._held_heads():
            head.band_force(self.tag, P.p_x, P.p_vol, P.p_n, P.p_sat, P.p_material, self.table, self.walls,
                            self.pw.heads_at(time), self.gravity, float(np.linalg.norm(self.scene.gravity)), g.h,
                            self._origin, g.kind, lo, nloc, self.g_w[:nn])
        halo((view.g_mass, view.g_mom, view.g_force, self.g_w[:nn]))
        self.fold(view, (view.g_mass.reshape(-1, 1), view.g_mom, view.g_force, self.g_w[:nn]))
        self.g_solid = self._solids(view, time)
        # node by node (the fill reads the water's rows at mirrored nodes, which none of the three writes)
        be.each_in_turn(nn, ((tp.node_fill_one, (self.g_w[:nn], self.g_solid, self.walls, self._origin, g.h, lo,
                                                  nloc, g.h ** self.scene.dim, self.g_fill[:nn])),
                             (tp.node_mixture_one, (view.g_mass, view.g_mom, self.g_w[:nn], be.mass_eps,
                                                    self.g_rel[:nn])),
                             (tp.node_pore_one, (self.g_w[:nn], self.g_pore[:nn]))))
        view.g_pore = self.g_pore[:nn]

    def snapshot(self, view, dt: float) -> None:
        """Once gravity, the loads and the damping have acted on the mixture: the relative velocity after
        the step, and the mixture's velocities before the boundaries and obstacles act."""
        nn = view.g_vel.shape[0]
        self.be.each(tp.node_snapshot_one, nn, view.g_mass, view.g_vel, view.g_vel_old, self.g_w[:nn],
                     self.gravity, dt, self.be.mass_eps, self.g_rel[:nn], self.g_rel0[:nn], self.g_vpre[:nn])

    def mirror(self, view) -> tuple:
        """The normal velocity behind the impermeable walls and inside the fixed impermeable solids mirrored
        from the material's (mirror.py), after the stages and before the split: the velocities copied, and the
        mirror's node pass returned ((fn, args), none without a wall or solid) for the caller to run with the
        split's (the mirror reads the copy at other nodes, and writes only its own node's velocity)."""
        if self.walls.shape[0] == 0 and self._solid is None:
            return ()
        g, nn = self.scene.grid, view.g_vel.shape[0]
        lo, nloc = self.window_index(view)
        self.be.each(mirror.node_copy_one, nn, view.g_vel, self.g_image[:nn])
        return ((mirror.node_mirror_one, (self.g_image[:nn], view.g_mass, self.walls, self.g_solid, self._origin,
                                          g.h, lo, nloc, self.be.mass_eps, view.g_vel)),)

    def _split(self, view, dt: float, g_vold, g_vwold) -> None:
        """The mirror (``mirror``) and node_split_one, node by node in one pass (the split reads the velocity the
        mirror wrote only at its own node); the velocities before the step into ``g_vold`` and ``g_vwold``."""
        g, nn = self.scene.grid, view.g_vel.shape[0]
        lo, nloc = self.window_index(view)
        self.be.each_in_turn(nn, self.mirror(view) + (
            (tp.node_split_one, (view.g_mass, view.g_vel, self.g_vpre[:nn], self.g_w[:nn], self.g_rel[:nn],
                                 self.g_rel0[:nn], self.g_solid, self.walls, self._origin, g.h, lo, nloc, self.gravity,
                                 dt, self.be.mass_eps, self.g_vw[:nn], g_vold, g_vwold)),))

    def split(self, view, dt: float) -> None:
        self._split(view, dt, view.g_vel_old, self.g_vwold[:view.g_vel.shape[0]])

    def water_g2p(self, view, dt: float, halo) -> None:
        """The water's particle velocity and the pore pressure's step, at the particles before they move (the
        gather and the step's first particle passes in one: each reads the gather's fill and divergences at its
        own particle)."""
        P = self.particles()
        self.pressure_step(view, dt, halo, (self._water_g2p_call(view, P.p_vw, P.p_Cw, self._flip(dt)),))

    def _flip(self, dt: float) -> float:
        sc = self.scene
        return 0.0 if not self.flips else (sc.flip_ratio if sc.flip_tau is None else math.exp(-dt / sc.flip_tau))

    def _water_g2p_call(self, view, p_vw, p_Cw, flip: float) -> tuple:
        """(water_g2p_one, its arguments) into p_vw, p_Cw: the water's velocity and affine matrix, both
        divergences and the fill at the particles."""
        g, nn, sc = self.scene.grid, view.g_vel.shape[0], self.scene
        P = self.particles()
        lo, nloc = self.window_index(view)
        return tp.water_g2p_one, (self.tag, P.p_x, p_vw, p_Cw, self.affine, sc.apic_dinv, flip, self.p_divw,
                                  self.p_divs, self.p_fill, self.g_vw[:nn], self.g_vwold[:nn], view.g_vel,
                                  self.g_fill[:nn], self._origin, g.h, g.kind, lo, nloc)

    def _water_g2p(self, view, p_vw, p_Cw, flip: float) -> None:
        self.be.each_in_turn(self.n, (self._water_g2p_call(view, p_vw, p_Cw, flip),))

    def water_velocity(self, view, dt: float) -> None:
        """The water's particle velocity and affine matrix from the updated grid (MUSL's first G2P)."""
        P = self.particles()
        self._water_g2p(view, P.p_vw, P.p_Cw, self._flip(dt))

    def remap(self, view, halo, stages) -> None:
        """MUSL: both phases' updated particle momenta back onto the grid (halo summed, folded), the mixture's
        velocity and the relative velocity from them, ``stages()`` (the boundaries and obstacles) acting on
        the mixture again, and the solid's and water's velocities split from it as after the step (the
        walls' water rules; dt = 0: nothing advanced twice).  The divergences of the re-mapped velocities
        at the particles then feed the pressure's step (pressure_step)."""
        be, g = self.be, self.scene.grid
        P = self.particles()
        nn = view.g_mass.shape[0]
        lo, nloc = self.window_index(view)
        self._scatter(view, lo, nloc, P)
        if self._held_heads():
            head.band_force(self.tag, P.p_x, P.p_vol, P.p_n, P.p_sat, P.p_material, self.table, self.walls,
                            self.pw.heads_at(self._time), self.gravity, float(np.linalg.norm(self.scene.gravity)), g.h,
                            self._origin, g.kind, lo, nloc, self.g_w[:nn])
        halo((view.g_mass, view.g_mom, view.g_force, self.g_w[:nn]))
        self.fold(view, (view.g_mass.reshape(-1, 1), view.g_mom, view.g_force, self.g_w[:nn]))
        be.each(tp.node_remap_one, nn, view.g_mass, view.g_mom, self.g_w[:nn], be.mass_eps, view.g_vel,
                self.g_rel[:nn], self.g_rel0[:nn], self.g_vpre[:nn])
        stages()
        if self.g_old is None or self.g_old.shape[0] < self.cap:
            self.g_old = self._zeros((self.cap, self.scene.dim))
        self._split(view, 0.0, self.g_old[:nn], self.g_vwold[:nn])
        if self.p_vw2 is None or self.p_vw2.shape[0] != self.n:
            d = self.scene.dim
            self.p_vw2, self.p_Cw2 = self._zeros((self.n, d)), self._zeros((self.n, d, d))
        self._water_g2p(view, self.p_vw2, self.p_Cw2, 0.0)

    def _held_heads(self) -> bool:
        """Whether a water boundary holds a head (Stage.water_head)."""
        return any(s is not None for s in self.pw.heads)

    def _hold_heads(self, hold: int, heads) -> tuple:
        """The particles at a held head (kernels.head_one): marked drained (0) before the increment, held
        at the head's pressure (1) after it: the pass ((fn, args); none without a held head), ``heads`` the
        levels at this step's time on the backend."""
        if not self._held_heads():
            return ()
        P = self.particles()
        return ((head.head_one, (P.p_x, P.p_drained, P.p_pore_carried, P.p_pore, P.p_sat, P.p_n, P.p_material,
                                 self.table, self.walls, heads, self.gravity, float(np.linalg.norm(self.scene.gravity)),
                                 self.scene.grid.h, hold)),)

    def pressure_step(self, view, dt: float, halo, first: tuple = ()) -> None:
        """The drained flag, the pore pressure's increment from the divergences at the particles (the
        pressure seen through the grid with the smoothing) and both pressures advanced: particle by particle
        in one pass (two with the smoothing, whose gather starts the second), after ``first`` (particle passes
        whose outputs these read only at their own particle: the water's gather)."""
        n = self.n
        P = self.particles()
        lo, nloc = self.window_index(view)
        heads = self._on_device(self.pw.heads_at(self._time)) if self._held_heads() else None
        increment = first + ((tp.flag_drained_one, (self.p_fill, P.p_sat, P.p_n, P.p_material, self.table,
                                                    P.p_drained)),) + self._hold_heads(0, heads) + (
            (tp.pressure_increment_one, (self.p_dp, self.p_divw, self.p_divs, P.p_n, P.p_material, self.table, dt)),)
        dp = self.p_dps if self.smoothing else self.p_dp
        advance = ((tp.add_increment_one, (P.p_pore_carried, P.p_pore, dp, P.p_drained, P.p_material, self.table)),
                   ) + self._hold_heads(1, heads)
        if self.smoothing:
            self.be.each_in_turn(n, increment)
            self._smooth(view, lo, nloc, halo, P, self.p_dp, self.p_dps, advance)
        else:
            self.be.each_in_turn(n, increment + advance)

    def porosity(self) -> None:
        P = self.particles()
        self.be.each_in_turn(self.be.state.n, ((tp.porosity_one, (P.p_n, P.p_vol, P.p_vol0, P.p_material,
                                                                  self.table)),), moves=False)
