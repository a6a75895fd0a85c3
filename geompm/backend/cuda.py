"""The CUDA backend (numba-cuda, the optional extra ``geompm[cuda]``): the step's kernels on a GPU.

The particle arrays the step changes (p_x, p_x0, p_v, p_C, p_mass, p_vol,
p_rho, p_stress, p_L and each block's state variables) live on the device;
the host ``ParticleState`` stays the canonical copy for everything else
(ids, bodies, writers, checkpoints).  ``host_state()`` copies the device
arrays into it and marks the host as current; the next kernel uploads the
host arrays again first, so whatever the host did in between (a checkpoint
restored, particles deleted by the health check, the spatial sort) reaches
the device.  Between output, series, health and sort times a step therefore
moves only a few numbers to the host: the grid window's bounds, the time
step's speed and density extremes and largest |L_ii|, and each stage's
reduction row.

Kernels: P2G by atomics (or, with ``solver.p2g: "tiled"``, through a
shared-memory tile per thread block), the grid update and G2P
(backend/cuda_kernels.py);
one kernel per law and per stage function around the plugin's own
``@njit`` per-item function (backend/cuda_loops.py).  A stage's ``prm`` (a
few numbers that may change between steps) goes to the device at every
pass; its ``aux`` table (an obstacle's signed-distance lattice, a DEM) once,
and again only when the stage hands a different array.

The spatial sort runs on the device (backend/cuda_sort.py): only its
permutation comes to the host, for the host-only arrays.

Not built yet: kernels cached on disk (numba-cuda's cache needs a device to key on; docs/performance.md),
and a measurement on a GPU.
"""

from __future__ import annotations

import numpy as np
from numba import cuda

from geompm.mpm.grid import GridView, window_extent
from geompm.kernels.reduce import cells_of_bounds, max_rate
from geompm.kernels.shape import support
from geompm.kernels.stencil import SCHEMES
from geompm.contract.stages import DRY_NODE, FAR_NODE
from geompm.backend import cuda_kernels as K
from geompm.backend import cuda_loops, cuda_sort
from geompm.backend.base import Backend, mass_floor, relaxed_materials

#: the particle arrays that live on the device (and the scheme's own: its passes' ``device_arrays``)
DEVICE_ARRAYS = ("p_x", "p_x0", "p_v", "p_C", "p_mass", "p_vol", "p_rho", "p_stress", "p_L")


class _DeviceGrid:
    """The grid window's device arrays, grown geometrically (mpm/grid.GridBuffers on the host)."""

    nchunks = 1  # one grid: P2G adds with atomics

    def __init__(self, spec, split: bool, dtype=np.float64):
        self.spec, self.split, self.cap, self.dtype = spec, split, 0, np.dtype(dtype)
        self._alloc(1024)

    def _alloc(self, cap):
        d = self.spec.dim
        self.cap = cap
        f = self.dtype
        self.g_mass = cuda.device_array(cap, f)
        self.g_mom = cuda.device_array((cap, d), f)
        self.g_force = cuda.device_array((cap if self.split else 1, d), f)
        self.g_vel = cuda.device_array((cap, d), f)
        self.g_vel_old = cuda.device_array((cap if self.split else 1, d), f)

    def nbytes(self) -> int:
        return sum(a.nbytes for a in (self.g_mass, self.g_mom, self.g_force, self.g_vel, self.g_vel_old))

    def view(self, lo, nloc) -> GridView:
        nn = int(np.prod(nloc))
        if nn > self.cap:
            self._alloc(int(nn * 1.25) + 64)
        s = self.split
        return GridView(self.spec, lo, nloc, self.g_mass[:nn], self.g_mom[:nn], self.g_force[:nn] if s else None,
                        self.g_vel[:nn], self.g_vel_old[:nn] if s else None)


class CudaBackend(Backend):
    name = "cuda"

    def __init__(self, scene, split_force: bool, nchunks: int | None = None):
        self.scene = scene
        self.state = scene.state
        self.split_force = split_force
        g = scene.grid
        self.S = support(g.kind)
        self.mode = SCHEMES.index(scene.transfer)
        self.buffers = _DeviceGrid(g, split_force, self.state.dtype)
        self.mass_eps = mass_floor(scene)
        self.max_rate = None
        self._origin = cuda.to_device(np.ascontiguousarray(g.origin, dtype=np.float64))
        self._gravity = cuda.to_device(np.ascontiguousarray(scene.gravity, dtype=np.float64))
        self._dry_node = cuda.to_device(DRY_NODE)  # every node of a dry scene: friction on the total stress
        self._prm = [cuda.to_device(m.prm) for m in scene.materials]
        self._laws = [cuda_loops.stress_kernel(type(m)) for m in scene.materials]
        #: per material: the regularised kernel where solver.viscoplastic_time applies to its law, else None
        self._relaxed = [cuda_loops.relaxed_kernel(type(m)) if on else None
                         for m, on in zip(scene.materials, relaxed_materials(scene))]
        self._old: dict = {}  # per material block: the relaxation's scratch rows on the device
        self._dev: dict = {}
        self._dev_state: list = []
        self._tables: dict = {}  # (stage, pass) -> (its aux on the host, the device copy)
        self._smalls: dict = {}  # key -> (a small array's values when uploaded, the device copy): _small
        self._on_host = True  # the host arrays are current; the next kernel uploads them
        #: the scheme's own passes on this backend (schemes/base.Scheme.backend_passes)
        self.scheme_passes = scene.scheme.backend_passes(self)
        self.device_arrays = DEVICE_ARRAYS + self.scheme_passes.device_arrays

    # -- host <-> device -------------------------------------------------------------------------------
    def _device(self) -> dict:
        if self._on_host:
            st = self.state
            self._dev = {k: cuda.to_device(np.ascontiguousarray(getattr(st, k))) for k in self.device_arrays}
            self._dev_state = [cuda.to_device(np.ascontiguousarray(sv)) for sv in st.p_state]
            self._on_host = False
        return self._dev

    def host_state(self):
        if not self._on_host:
            st = self.state
            for k, d in self._dev.items():
                setattr(st, k, d.copy_to_host())
            st.p_state = [d.copy_to_host() for d in self._dev_state]
            self._on_host = True
        return self.state

    def nbytes(self) -> int:
        return self.state.nbytes() + self.buffers.nbytes() + self.scheme_passes.nbytes()

    # -- the step ---------------------------------------------------------------------------------------
    def window(self):
        spec = self.scene.grid
        lo, nloc = window_extent(spec, self._cells(), lambda: self.host_state().p_x)
        return self.buffers.view(lo, nloc)

    def _cells(self):
        dev, st, spec = self._device(), self.state, self.scene.grid
        d = spec.dim
        out = np.empty((3, d))
        out[0], out[1], out[2] = np.inf, -np.inf, 0.0
        red = cuda.to_device(out)
        if st.n:
            K.bounds[K.blocks(st.n), K.THREADS](dev["p_x"], red)
        r = red.copy_to_host()
        return cells_of_bounds(r[0], r[1], r[2], spec.origin, 1.0 / spec.h)

    def particle_cells(self):
        return self._cells() if self.state.n else None

    def window_at(self, lo, nloc):
        return self.buffers.view(lo, nloc)

    def p2g(self, view, f_scale: float) -> None:
        dev, st, g = self._device(), self.state, self.scene.grid
        nn = view.g_mass.shape[0]
        force = view.g_force if self.split_force else view.g_mom
        K.zero_grid[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, force, self.split_force)
        if st.n:
            kern = K.p2g_tiled if self.scene.p2g == "tiled" else K.p2g
            kern[K.blocks(st.n), K.THREADS](
                self.S, self.mode, dev["p_x"], dev["p_v"], dev["p_C"], dev["p_mass"], dev["p_vol"], dev["p_stress"],
                self._origin, g.h, g.kind, self._small("lo", view.lo), self._small("nloc", view.nloc), self.split_force,
                f_scale, self.scene.apic_dinv, view.g_mass, view.g_mom, force)

    def grid_update(self, view, dt: float) -> None:
        nn = view.g_mass.shape[0]
        split = self.split_force
        K.grid_update[K.blocks(nn), K.THREADS](
            view.g_mass, view.g_mom, view.g_force if split else view.g_mom, self._gravity, dt, self.mass_eps, split,
            view.g_vel, view.g_vel_old if split else view.g_vel)

    def remap_velocity(self, view) -> None:
        nn = view.g_mass.shape[0]
        K.momentum_to_velocity[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, self.mass_eps, view.g_vel)

    def g2p(self, view, dt: float, *, set_velocity: bool, move: bool, gradient: bool) -> None:
        dev, st, sc, g = self._device(), self.state, self.scene, self.scene.grid
        if not st.n:
            return
        g_vel_old = view.g_vel_old if self.split_force else view.g_vel
        ratio = sc.flip_ratio if sc.flip_tau is None else float(np.exp(-dt / sc.flip_tau))
        K.g2p[K.blocks(st.n), K.THREADS](
            self.S, self.mode, dev["p_x"], dev["p_v"], dev["p_C"], dev["p_L"], dev["p_vol"], dev["p_rho"],
            dev["p_mass"], view.g_vel, g_vel_old, self._origin, g.h, g.kind, self._small("lo", view.lo),
            self._small("nloc", view.nloc), dt, ratio, sc.apic_dinv, set_velocity, move, gradient)

    def material_parameters_changed(self) -> None:
        self._prm = [cuda.to_device(m.prm) for m in self.scene.materials]

    def update_stress(self, dt: float) -> None:
        dev = self._device()
        rate = cuda.to_device(np.zeros(1))
        for k, (law, prm, (s, e), sv) in enumerate(zip(self._laws, self._prm, self.state.blocks, self._dev_state)):
            if e <= s:
                continue
            args = (prm, dt, dev["p_L"][s:e], dev["p_rho"][s:e], dev["p_stress"][s:e], sv)
            relaxed = self._relaxed[k]
            if relaxed is None:
                law[K.blocks(e - s), K.THREADS](*args, rate)
                continue
            old = self._old.get(k)
            if old is None or old.shape != (e - s, 6 + sv.shape[1]):
                old = self._old[k] = cuda.device_array((e - s, 6 + sv.shape[1]), np.float64)
            relaxed[K.blocks(e - s), K.THREADS](*args, old, dt / self.scene.viscoplastic_time, rate)
        self.max_rate = float(rate.copy_to_host()[0])

    def dt_parts(self):
        sc, st = self.scene, self.state
        dev = self._device()
        nb = len(st.blocks)
        red = cuda.to_device(np.full(1 + 2 * nb, -np.inf))
        for k, (s, e) in enumerate(st.blocks):
            if e > s:
                K.speed_and_density[K.blocks(e - s), K.THREADS](dev["p_v"], dev["p_rho"], s, e, k, red)
        r = red.copy_to_host()
        laws = [0.0] * nb
        for k, (mat, (s, e)) in enumerate(zip(sc.materials, st.blocks)):
            if e > s:
                wave = type(mat).particle_wave_speed
                laws[k] = max(wave(mat.prm, -r[1 + 2 * k]), wave(mat.prm, r[2 + 2 * k]))
        c = self.scheme_passes.wave_speed(laws)
        if self.max_rate is None:  # before the first step, after a restore: from the particles
            self.max_rate = max_rate(self.host_state().p_L) if st.n else 0.0
        return c, (float(r[0]) if st.n else 0.0), self.max_rate

    def each(self, fn, n: int, *args) -> None:
        if n > 0:
            cuda_loops.each_kernel(fn)[K.blocks(n), K.THREADS](n, *args)

    def sort_particles(self) -> None:
        """The counting sort on the device (backend/cuda_sort.py); only the permutation comes to the host,
        for the arrays that live there (ids, bodies, reference volumes)."""
        st = self.state
        if not st.n:
            return
        dev = self._device()
        perm = cuda_sort.cell_order(dev["p_x"], self._origin, self.scene.grid.h, st.blocks)
        for k in self.device_arrays:
            dev[k] = cuda_sort.gather(dev[k], perm)
        self._dev_state = [cuda_sort.gather(sv, perm[s:e], s) for sv, (s, e) in zip(self._dev_state, st.blocks)]
        st.reorder(perm.copy_to_host(), skip=self.device_arrays, states=False)

    # -- stages ------------------------------------------------------------------------------------------
    def _table(self, stage, kind: str, aux):
        """The stage's ``aux`` on the device, uploaded once per array object: a table is read-only once
        handed over, and a stage that changes it hands a new array (contract/stages.py)."""
        key = (id(stage), kind)
        held = self._tables.get(key)
        if held is None or held[0] is not aux:
            held = self._tables[key] = (aux, cuda.to_device(np.ascontiguousarray(aux)))
        return held[1]

    def _small(self, key, host):
        """A small host array (a stage's packed parameters, a window's corner, a node box) on the device, uploaded
        again only when its values change: a wall's parameters are the same every step, a moving obstacle's
        shift changes its copy (compared value by value, a few dozen numbers)."""
        host = np.ascontiguousarray(host)
        held = self._smalls.get(key)
        if held is None or held[0].shape != host.shape or held[0].dtype != host.dtype or \
                not np.array_equal(held[0], host):
            held = self._smalls[key] = (host.copy(), cuda.to_device(host))
        return held[1]

    def grid_stage(self, stage, view, dt: float, time: float, remap: bool) -> None:
        args = stage.grid_args(dt, time, remap)
        if args is None:
            return
        cls = type(stage)
        nn = view.g_mass.shape[0]
        lo, nloc = self._small("lo", view.lo), self._small("nloc", view.nloc)
        if cls.node_image is not None:
            kern = cuda_loops.merge_kernel(cls.node_image)
            fold = view.g_vel_old is not None
            kern[K.blocks(nn), K.THREADS](self._small((id(stage), "merge"), args[0]), lo, nloc, view.g_mass, view.g_vel,
                                          view.g_vel_old if fold else view.g_vel, fold)
            return
        prm, aux = args
        d = self.scene.dim
        box = stage.node_box(time)
        first, last = (np.full(d, -FAR_NODE), np.full(d, FAR_NODE)) if box is None else box
        b0 = np.minimum(np.maximum(np.asarray(first) - view.lo, 0), view.nloc)
        bn = np.maximum(np.minimum(np.asarray(last) - view.lo + 1, view.nloc) - b0, 0)
        slots = max(stage.node_reduction, 1)
        out, spill = cuda.to_device(np.zeros(slots)), None
        kern = cuda_loops.node_kernel(cls.node_rule, cls.node_scratch, slots, cls.node_maxima)
        v_old = view.g_vel_old if view.g_vel_old is not None else view.g_vel
        f = view.g_force if view.g_force is not None else view.g_vel
        wet = view.g_pore is not None
        pore = view.g_pore if wet else self._dry_node
        for part, (f_box, l_box, counted) in enumerate(self.domain.node_parts(np.asarray(first), np.asarray(last))):
            b0 = np.minimum(np.maximum(f_box - view.lo, 0), view.nloc)
            bn = np.maximum(np.minimum(l_box - view.lo + 1, view.nloc) - b0, 0)
            total = int(np.prod(bn))
            if not total:
                continue
            if not counted and spill is None:
                spill = cuda.to_device(np.zeros(slots))
            kern[K.blocks(total), K.THREADS](
                self._small((id(stage), "grid"), prm), self._table(stage, "grid", aux), dt,
                self._origin, self.scene.grid.h, lo, nloc, self._small((id(stage), "b0", part), b0.astype(np.int64)),
                self._small((id(stage), "bn", part), bn.astype(np.int64)), total, view.g_mass, view.g_vel, v_old,
                f, pore, wet, out if counted else spill)
        stage.grid_reduced(self.joined(out.copy_to_host().reshape(1, slots), stage.node_reduction), dt, time, remap)

    def particle_stage(self, stage, dt: float, time: float) -> None:
        args = stage.particle_args(dt, time)
        if args is None:
            return
        dev, st, cls = self._device(), self.state, type(stage)
        prm, aux = self._small((id(stage), "particle"), args[0]), self._table(stage, "particle", args[1])
        slots = max(stage.particle_reduction, 1)
        out = cuda.to_device(np.zeros(slots))
        kern = cuda_loops.particle_kernel(cls.particle_rule, max(cls.particle_scratch, 1), slots,
                                          cls.particle_maxima)
        for k in stage.particle_blocks(len(st.blocks)):
            s, e = st.blocks[k]
            if e > s:
                kern[K.blocks(e - s), K.THREADS](prm, aux, dt, k, s, e, dev["p_x"], dev["p_x0"], dev["p_v"],
                                                 dev["p_C"], dev["p_mass"], dev["p_stress"], out)
        stage.particle_reduced(self.joined(out.copy_to_host().reshape(1, slots), stage.particle_reduction), dt,
                               time)

