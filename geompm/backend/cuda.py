"""The CUDA backend (numba-cuda, the optional extra ``geompm[cuda]``): the step's kernels on a GPU.

The particle arrays the step changes (p_x, p_x0, p_v, p_C, p_mass, p_vol,
p_rho, p_stress, p_L and each block's state variables) live on the device;
the host ``ParticleState`` stays the canonical copy for everything else
(ids, bodies, writers, checkpoints).  ``host_state()`` copies the device
arrays into it and marks the host as current; the next kernel uploads the
host arrays again first, so whatever the host did in between (a checkpoint
restored, particles deleted by the domain check or added by a source)
reaches the device.  Between output, series and checkpoint times a step
copies one array to the host: the step's tally (backend/cuda_tally.py), every
reduction of the step in its own slots, read at the step's end (``settle``):
each stage pass's accumulator, the largest |L_ii|, and the step-end
reductions (cuda_kernels.step_end) that the next step's time step, grid
window and the health and domain checks read (``health_sums``,
``particles_outside``).

Kernels: P2G by atomics (or, with ``solver.p2g: "tiled"``, through a
shared-memory tile per thread block), the grid update and G2P
(backend/cuda_kernels.py);
one kernel per law and per stage function around the plugin's own
``@njit`` per-item function (backend/cuda_loops.py); consecutive particle
stages of one class in one launch (cuda_loops.GROUP).  A stage's ``prm`` (a
few numbers that may change between steps) goes to the device when its
values change; its ``aux`` table (an obstacle's signed-distance lattice, a
DEM) once, and again only when the stage hands a different array.

The spatial sort runs on the device (backend/cuda_sort.py), each block's
cell range taken from the step-end bounds; its permutations are composed on
the device and reach the host, for the host-only arrays, when it next reads
the state.

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
from geompm.backend.cuda_scratch import Scratch
from geompm.backend.cuda_tally import DeviceTally
from geompm.backend.base import Backend, mass_floor, relaxed_materials

#: the particle arrays that live on the device (and the scheme's own: its passes' ``device_arrays``)
DEVICE_ARRAYS = ("p_x", "p_x0", "p_v", "p_C", "p_mass", "p_vol", "p_rho", "p_stress", "p_L")
#: a node box holding every node ((first, last) per axis, as Stage.node_box gives it)
_EVERY_NODE = np.array([[-FAR_NODE], [FAR_NODE]], np.int64)
#: the particle arrays of a material block that cuda_loops.PARTICLE_STEP takes, in its order
BLOCK_ARRAYS = ("p_x", "p_x0", "p_v", "p_C", "p_L", "p_vol", "p_rho", "p_mass", "p_stress")


def _runs(pairs, joins) -> list:
    """The (stage, args) ``pairs`` whose args are not None, in runs of consecutive pairs that ``joins`` joins."""
    runs: list = []
    for pair in pairs:
        if pair[1] is None:
            continue
        if runs and joins(runs[-1][-1], pair):
            runs[-1].append(pair)
        else:
            runs.append([pair])
    return runs


def _in_window(first, last, view):
    """Node boxes (global first and last node, inclusive, (..., d)) within ``view``'s window: each box's first node
    relative to the window and its count of nodes per axis (0 where it misses the window), int64."""
    b0 = np.minimum(np.maximum(np.asarray(first) - view.lo, 0), view.nloc).astype(np.int64)
    return b0, np.maximum(np.minimum(np.asarray(last) - view.lo + 1, view.nloc) - b0, 0).astype(np.int64)


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
        self._laws = [cuda_loops.stress_kernel(type(m)) for m in scene.materials]
        #: per material: the regularised kernel where solver.viscoplastic_time applies to its law, else None
        self._joined = scene.particle_pass == "joined"  # solver.particle_pass; "separate": a kernel each
        self._relaxed = [cuda_loops.relaxed_kernel(type(m)) if on else None
                         for m, on in zip(scene.materials, relaxed_materials(scene))]
        self._old: dict = {}  # per material block: the relaxation's scratch rows on the device
        self._dev: dict = {}
        self._dev_state: list = []
        self._tables: dict = {}  # (stage, pass) -> (its aux on the host, the device copy)
        self._smalls: dict = {}  # key -> (a small array's values when uploaded, the device copy): _small
        self.material_parameters_changed()  # self._prm: each law's parameters on the device
        self._blocks: dict = {}  # (start, end) -> (the device arrays, their views of the block): _block
        self._on_host = True  # the host arrays are current; the next kernel uploads them
        #: every reduction of a step, read by the host once at its end (settle; backend/cuda_tally.py)
        self.tally = DeviceTally()
        self.tally.reserve("halt", [0.0])  # set by a held batch's check: every later kernel returns at once
        self._step = 0  # the step's place in a held batch (engine/held_step.py; 0 outside one): its tally slots
        self._handed: list = []  # (callback, tally slice, slots) of this step's stage passes, in pass order
        self._passes: dict = {}  # (stage, pass kind) -> passes so far this step: each pass its own slots
        self._rate_due = False  # a stress update wrote its largest |L_ii| into the tally
        self._moved = 0  # bumped by whatever changes the device particles (their step-end reductions lapse)
        self._end = None  # (the _moved it was taken at, its values by name): settle's step-end reductions
        self._rows_at = None  # (_moved, step) where a fused particle pass filled the step-end rows in the tally
        self._end_rows0 = None  # _end_start's array
        self._spill = {}  # slots -> a device sink for the rows of nodes another rank counts
        self._perm = None  # the device sorts' permutations since the host's arrays were last put in order
        self._scratch = Scratch()  # the sort's work arrays and each sorted array's spare (backend/cuda_scratch.py)
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
            self._moved += 1
        return self._dev

    def host_state(self):
        if not self._on_host:
            st = self.state
            for k, d in self._dev.items():
                setattr(st, k, d.copy_to_host())
            st.p_state = [d.copy_to_host() for d in self._dev_state]
            self._on_host = True
        if self._perm is not None:  # the host-only arrays (ids, bodies, reference volumes) follow the sorts
            st = self.state
            st.reorder(self._perm.copy_to_host(), skip=self.device_arrays, states=False)
            self._perm = None
        self._end = None  # the caller may change the host arrays
        return self.state

    def nbytes(self) -> int:
        return self.state.nbytes() + self.buffers.nbytes() + self.scheme_passes.nbytes() + self._scratch.nbytes()

    # -- the step ---------------------------------------------------------------------------------------
    def window(self):
        spec = self.scene.grid
        cells = self._held[1] if self._held is not None else self._cells()  # a held batch's window
        lo, nloc = window_extent(spec, cells, lambda: self.host_state().p_x)
        return self.buffers.view(lo, nloc)

    def _cells(self):
        spec, end = self.scene.grid, self._end_now()
        return cells_of_bounds(end["lo"], end["hi"], end["sum"], spec.origin, 1.0 / spec.h)

    def particle_cells(self):
        return self._cells() if self.state.n else None

    def window_at(self, lo, nloc):
        return self.buffers.view(lo, nloc)

    def p2g(self, view, f_scale: float) -> None:
        dev, st, g = self._device(), self.state, self.scene.grid
        nn = view.g_mass.shape[0]
        force = view.g_force if self.split_force else view.g_mom
        K.zero_grid[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, force, self.split_force, self.halt())
        if st.n:
            kern = K.p2g_tiled if self.scene.p2g == "tiled" else K.p2g
            kern[K.blocks(st.n), K.THREADS](
                self.S, self.mode, dev["p_x"], dev["p_v"], dev["p_C"], dev["p_mass"], dev["p_vol"], dev["p_stress"],
                self._origin, g.h, g.kind, self._small("lo", view.lo), self._small("nloc", view.nloc), self.split_force,
                f_scale, self.scene.apic_dinv, view.g_mass, view.g_mom, force, self.halt())

    def grid_update(self, view, dt: float) -> None:
        nn = view.g_mass.shape[0]
        split = self.split_force
        K.grid_update[K.blocks(nn), K.THREADS](
            view.g_mass, view.g_mom, view.g_force if split else view.g_mom, self._gravity, dt, self.mass_eps, split,
            view.g_vel, view.g_vel_old if split else view.g_vel, self.halt())

    def remap_velocity(self, view) -> None:
        nn = view.g_mass.shape[0]
        K.momentum_to_velocity[K.blocks(nn), K.THREADS](view.g_mass, view.g_mom, self.mass_eps, view.g_vel, self.halt())

    def g2p(self, view, dt: float, *, set_velocity: bool, move: bool, gradient: bool) -> None:
        dev, st, sc, g = self._device(), self.state, self.scene, self.scene.grid
        if not st.n:
            return
        g_vel_old = view.g_vel_old if self.split_force else view.g_vel
        ratio = sc.flip_ratio if sc.flip_tau is None else float(np.exp(-dt / sc.flip_tau))
        K.g2p[K.blocks(st.n), K.THREADS](
            self.S, self.mode, dev["p_x"], dev["p_v"], dev["p_C"], dev["p_L"], dev["p_vol"], dev["p_rho"],
            dev["p_mass"], view.g_vel, g_vel_old, self._origin, g.h, g.kind, self._small("lo", view.lo),
            self._small("nloc", view.nloc), dt, ratio, sc.apic_dinv, set_velocity, move, gradient, self.halt())
        self._moved += 1

    def g2p_stages_and_stress(self, view, dt: float, stages, time: float, *, set_velocity: bool) -> None:
        """G2P, the particle stages and each block's law in one launch per material block (cuda_loops.PARTICLE_STEP,
        the step-end row of the block with them): the passes ``g2p``, ``particle_stages`` and ``update_stress``
        one after the other, each thread on its own particle."""
        dev, st, sc, g = self._device(), self.state, self.scene, self.scene.grid
        if not st.n or not self._joined:
            super().g2p_stages_and_stress(view, dt, stages, time, set_velocity=set_velocity)
            return
        runs = _runs(((s, s.particle_args(dt, time)) for s in stages), self._joins)
        passes = [self._run_arrays(run) for run in runs]
        where = [self.tally.reserve(key, start) for key, start in ((("rate", self._step), [0.0]), ("halt", [0.0]),
                                                                     (("end", self._step), self._end_start()))]
        rate, halt, rows = (self.tally.view(w) for w in where)  # views once every slot is reserved
        g_vel_old = view.g_vel_old if self.split_force else view.g_vel
        ratio = sc.flip_ratio if sc.flip_tau is None else float(np.exp(-dt / sc.flip_tau))
        grid = (view.g_vel, g_vel_old, self._origin, g.h, g.kind, self._small("lo", view.lo),
                self._small("nloc", view.nloc), dt, ratio, sc.apic_dinv, set_velocity)
        specs = tuple(spec for spec, _, _, _ in passes)
        outs = [args + (self.tally.view(w).reshape(len(run), spec[2]),)
                for run, (spec, args, _, w) in zip(runs, passes)]
        for k, (mat, prm, (s, e), sv) in enumerate(zip(sc.materials, self._prm, st.blocks, self._dev_state)):
            if e <= s:
                continue
            relaxed = self._relaxed[k] is not None
            kern = cuda_loops.particle_step_kernel(type(mat), relaxed, specs,
                                                   (K.g2p_particle, K.end_start, K.end_add))
            block = self._block(dev, s, e)
            on = [arrays + (k in blocks,) for arrays, (_, _, blocks, _) in zip(outs, passes)]
            extra = (self._old_rows(k, e - s, sv), dt / sc.viscoplastic_time) if relaxed else ()
            kern[K.blocks(e - s), K.THREADS](self.S, self.mode, *block, sv, *grid, k, *(a for o in on for a in o),
                                             prm, *extra, rate, self._gravity,
                                             rows[k * K.END_ROW:(k + 1) * K.END_ROW], halt)
        self._moved += 1
        self._rows_at = (self._moved, self._step)  # the step-end rows are taken (settle launches none)
        self.max_rate, self._rate_due = None, True
        for run, (spec, _, _, where) in zip(runs, passes):
            self._hand_particles(run, where, spec[2], dt, time)

    def material_parameters_changed(self) -> None:
        self._prm = [self._small(("material", k), m.prm) for k, m in enumerate(self.scene.materials)]

    def update_stress(self, dt: float) -> None:
        dev = self._device()
        rate, halt = self.tally.slots(("rate", self._step), [0.0]), self.halt()
        self._moved += 1
        for k, (law, prm, (s, e), sv) in enumerate(zip(self._laws, self._prm, self.state.blocks, self._dev_state)):
            if e <= s:
                continue
            args = (prm, dt, dev["p_L"][s:e], dev["p_rho"][s:e], dev["p_stress"][s:e], sv)
            relaxed = self._relaxed[k]
            if relaxed is None:
                law[K.blocks(e - s), K.THREADS](*args, rate, halt)
                continue
            relaxed[K.blocks(e - s), K.THREADS](*args, self._old_rows(k, e - s, sv), dt / self.scene.viscoplastic_time,
                                                rate, halt)
        self.max_rate, self._rate_due = None, True  # read at the step's end (settle)

    def _old_rows(self, k: int, n: int, sv):
        """Material block k's scratch rows for the relaxation (its ``n`` particles' stress and state variables)."""
        old = self._old.get(k)
        if old is None or old.shape != (n, 6 + sv.shape[1]):
            old = self._old[k] = cuda.device_array((n, 6 + sv.shape[1]), np.float64)
        return old

    def dt_parts(self):
        sc, st = self.scene, self.state
        nb = len(st.blocks)
        r = self._end_now()["speed_density"]
        laws = [0.0] * nb
        for k, (mat, (s, e)) in enumerate(zip(sc.materials, st.blocks)):
            if e > s:
                wave = type(mat).particle_wave_speed
                laws[k] = max(wave(mat.prm, -r[1 + 2 * k]), wave(mat.prm, r[2 + 2 * k]))
        c = self.scheme_passes.wave_speed(laws)
        if self.max_rate is None:  # before the first step, after a restore: from the particles
            self.max_rate = max_rate(self.host_state().p_L) if st.n else 0.0
        return c, (float(r[0]) if st.n else 0.0), self.max_rate

    def each_in_turn(self, n: int, calls, moves: bool = True) -> None:
        self._moved += moves
        if n > 0:
            cuda_loops.each_kernel(tuple(fn for fn, _ in calls))[K.blocks(n), K.THREADS](
                n, *(a for _, args in calls for a in args))

    def sort_particles(self) -> None:
        """The counting sort on the device (backend/cuda_sort.py).  The arrays that live on the host (ids, bodies,
        reference volumes) follow when the host next reads the state: the permutations are composed on the
        device until then, so a sort makes the host wait for nothing."""
        st = self.state
        if not st.n:
            return
        cells = self._block_cells(self._end_now()["rows"])  # each block's cell range from the step-end bounds
        dev = self._device()
        room, first = self._scratch, self._perm is None  # the first since the host read: perm is the composition
        perm = cuda_sort.cell_order(dev["p_x"], self._origin, self.scene.grid.h, st.blocks, cells, self._small, room,
                                    room.spare("perm", (st.n,), np.int64) if first else None)
        for k in self.device_arrays:
            dev[k] = cuda_sort.gather(dev[k], perm, 0, room.spare(k, dev[k].shape, dev[k].dtype, dev[k]))
        self._dev_state = [cuda_sort.gather(sv, perm[s:e], s, room.spare(("state", b), sv.shape, sv.dtype, sv))
                           for b, (sv, (s, e)) in enumerate(zip(self._dev_state, st.blocks))]
        self._perm = perm if first else cuda_sort.gather(self._perm, perm, 0,
                                                          room.spare("perm", (st.n,), np.int64, self._perm))

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
        values = (host.shape, host.dtype.str, host.tobytes())  # bytes: a tenth of np.array_equal's time here
        held = self._smalls.get(key)
        if held is not None and held[0] == values:
            return held[1]
        if held is not None and held[0][:2] == values[:2]:  # the same shape and type: into the same array, whose
            device = held[1]  # device pointer stays; the kernels launched before the copy read the old values
            device.copy_to_device(host)  # (the stream orders them)
        else:
            device = cuda.to_device(host)
        self._smalls[key] = (values, device)
        return device

    def _block(self, dev, s: int, e: int) -> list:
        """The arrays of BLOCK_ARRAYS for particles s..e-1, as device views made again only where an array was
        replaced (an upload, a sort): the views of the last call are kept with the arrays they were cut from."""
        whole = [dev[a] for a in BLOCK_ARRAYS]
        held = self._blocks.get((s, e))
        if held is None or any(a is not b for a, b in zip(held[0], whole)):
            held = self._blocks[(s, e)] = (whole, [a[s:e] for a in whole])
        return held[1]

    def grid_stage(self, stage, view, dt: float, time: float, remap: bool) -> None:
        args = stage.grid_args(dt, time, remap)
        if args is not None:
            self._grid_pass(stage, args, view, dt, time, remap)

    def grid_stages(self, stages, view, dt: float, time: float, remap: bool) -> None:
        """Every grid stage in order, the consecutive node-rule stages of one class that share their ``aux`` (the
        walls of a box) in one launch over the nodes their boxes cover (cuda_loops.NODE_GROUP), in one process."""
        for run in self._grid_runs(stages, dt, time, remap):
            self._grid_run(run, view, dt, time, remap)

    def grid_update_and_stages(self, view, dt: float, stages, time: float) -> None:
        """The grid update joined to the first run of node-rule stages (cuda_loops.UPDATE_GROUP: one launch), then
        the other runs as ``grid_stages``; the update alone where the first stage merges nodes or the run is
        shared between processes."""
        runs = self._grid_runs(stages, dt, time, False)
        if runs and type(runs[0][0][0]).node_image is None and self.domain.size == 1:
            self._node_group(runs.pop(0), view, dt, time, False, update=True)
        else:
            self.grid_update(view, dt)
        for run in runs:
            self._grid_run(run, view, dt, time, False)

    def _grid_runs(self, stages, dt: float, time: float, remap: bool) -> list:
        """The stages with their (prm, aux) for this step (those that act), in runs of stages that join."""
        return _runs(((s, s.grid_args(dt, time, remap)) for s in stages), self._node_joins)

    def _grid_run(self, run, view, dt: float, time: float, remap: bool) -> None:
        if len(run) > 1:
            self._node_group(run, view, dt, time, remap)
        else:
            self._grid_pass(*run[0], view, dt, time, remap)

    def _node_joins(self, a, b) -> bool:
        (sa, (pa, xa)), (sb, (pb, xb)) = a, b
        return type(sa) is type(sb) and type(sa).node_image is None and xa is xb and \
            np.shape(pa) == np.shape(pb) and sa.node_reduction == sb.node_reduction and self.domain.size == 1

    def _node_group(self, run, view, dt: float, time: float, remap: bool, update: bool = False) -> None:
        """One launch for the (stage, (prm, aux)) pairs of ``run``, node-rule stages of one class, one process;
        ``update``: the grid update first, at every node of the window (cuda_loops.UPDATE_GROUP)."""
        first = run[0][0]
        cls, ids, d = type(first), tuple(id(s) for s, _ in run), self.scene.dim
        ends = np.empty((2, len(run), d), np.int64)  # each stage's first and last node (its node box)
        for g, (stage, _) in enumerate(run):
            box = stage.node_box(time)
            ends[:, g] = _EVERY_NODE if box is None else box
        boxes = np.stack(_in_window(ends[0], ends[1], view), axis=1)  # (stages, 2, d)
        held = boxes[:, 1].prod(axis=1) > 0
        slots = max(first.node_reduction, 1)
        outs, where = self._pass_slots((ids, "grid"), slots * len(run))
        prms = self._small(("grid", ids), np.stack([np.asarray(a[0], np.float64) for _, a in run]))
        wet, split = view.g_pore is not None, self.split_force
        rules = (prms, self._table(first, "grid", run[0][1][1]), dt, self._origin, self.scene.grid.h,
                 self._small("lo", view.lo), self._small("nloc", view.nloc), self._small(("boxes", ids), boxes))
        nodes = (view.g_mass, view.g_vel, view.g_vel_old if view.g_vel_old is not None else view.g_vel,
                 view.g_force if view.g_force is not None else view.g_vel, view.g_pore if wet else self._dry_node, wet,
                 outs.reshape(len(run), slots), self.halt())
        if update:
            nn = view.g_mass.shape[0]
            kern = cuda_loops.update_group_kernel(cls.node_rule, cls.node_scratch, slots, tuple(cls.node_maxima),
                                                  K.update_node)
            kern[K.blocks(nn), K.THREADS](view.g_mom, view.g_force if split else view.g_mom, self._gravity,
                                          self.mass_eps, split, view.g_vel_old if split else view.g_vel, *rules,
                                          *nodes)
        elif held.any():
            u0 = boxes[held, 0].min(axis=0)
            un = (boxes[held, 0] + boxes[held, 1]).max(axis=0) - u0
            total = int(np.prod(un))
            kern = cuda_loops.node_group_kernel(cls.node_rule, cls.node_scratch, slots, cls.node_maxima)
            kern[K.blocks(total), K.THREADS](*rules, self._small(("u0", ids), u0), self._small(("un", ids), un), total,
                                             *nodes)
        self._hand_run(run, where, slots, lambda stage: (lambda rows: stage.grid_reduced(rows, dt, time, remap),
                                                         stage.node_reduction))

    def _grid_pass(self, stage, args, view, dt: float, time: float, remap: bool) -> None:
        cls = type(stage)
        nn = view.g_mass.shape[0]
        lo, nloc = self._small("lo", view.lo), self._small("nloc", view.nloc)
        if cls.node_image is not None:
            kern = cuda_loops.merge_kernel(cls.node_image)
            fold = view.g_vel_old is not None
            kern[K.blocks(nn), K.THREADS](self._small((id(stage), "merge"), args[0]), lo, nloc, view.g_mass, view.g_vel,
                                          view.g_vel_old if fold else view.g_vel, fold, self.halt())
            return
        prm, aux = args
        d = self.scene.dim
        box = stage.node_box(time)
        first, last = (np.full(d, -FAR_NODE), np.full(d, FAR_NODE)) if box is None else box
        slots = max(stage.node_reduction, 1)
        (out, where), spill = self._pass_slots((id(stage), "grid"), slots), None
        kern = cuda_loops.node_group_kernel(cls.node_rule, cls.node_scratch, slots, cls.node_maxima)
        v_old = view.g_vel_old if view.g_vel_old is not None else view.g_vel
        f = view.g_force if view.g_force is not None else view.g_vel
        wet = view.g_pore is not None
        pore = view.g_pore if wet else self._dry_node
        prms = self._small((id(stage), "grid"), np.asarray(prm, np.float64)[None])
        for part, (f_box, l_box, counted) in enumerate(self.domain.node_parts(np.asarray(first), np.asarray(last))):
            b0, bn = _in_window(f_box, l_box, view)
            total = int(np.prod(bn))
            if not total:
                continue
            if not counted and spill is None:
                spill = self._spill.get(slots)
                if spill is None:
                    spill = self._spill[slots] = cuda.to_device(np.zeros(slots))
            # one stage's pass over one part of its box: NODE_GROUP with a group of one (its box the part's)
            kern[K.blocks(total), K.THREADS](
                prms, self._table(stage, "grid", aux), dt, self._origin, self.scene.grid.h, lo, nloc,
                self._small((id(stage), "boxes", part), np.stack([b0, bn])[None]),
                self._small((id(stage), "u0", part), b0), self._small((id(stage), "un", part), bn), total,
                view.g_mass, view.g_vel, v_old, f, pore, wet, (out if counted else spill).reshape(1, slots),
                self.halt())
        self._hand(lambda rows: stage.grid_reduced(rows, dt, time, remap), where, stage.node_reduction)

    def particle_stages(self, stages, dt: float, time: float) -> None:
        """Every particle stage in order, the consecutive stages of one class that share their ``aux`` and act on
        the same blocks (the walls of a box) in one launch per block (cuda_loops.GROUP)."""
        for run in _runs(((s, s.particle_args(dt, time)) for s in stages), self._joins):
            self._particle_pass(run, dt, time)

    def _joins(self, a, b) -> bool:
        (sa, (pa, xa)), (sb, (pb, xb)) = a, b
        n = len(self.state.blocks)
        return type(sa) is type(sb) and xa is xb and np.shape(pa) == np.shape(pb) and \
            sa.particle_reduction == sb.particle_reduction and \
            list(sa.particle_blocks(n)) == list(sb.particle_blocks(n))

    def particle_stage(self, stage, dt: float, time: float) -> None:
        args = stage.particle_args(dt, time)
        if args is not None:
            self._particle_pass([(stage, args)], dt, time)

    def _particle_pass(self, run, dt: float, time: float) -> None:
        """One launch per material block for the (stage, (prm, aux)) pairs of ``run``, stages of one class."""
        dev, st = self._device(), self.state
        spec, (prms, aux), blocks, where = self._run_arrays(run)
        outs = self.tally.view(where).reshape(len(run), spec[2])
        kern = cuda_loops.particle_kernel(*spec)
        self._moved += 1
        for k in sorted(blocks):
            s, e = st.blocks[k]
            if e > s:
                kern[K.blocks(e - s), K.THREADS](prms, aux, dt, k, s, e, dev["p_x"], dev["p_x0"], dev["p_v"],
                                                 dev["p_C"], dev["p_mass"], dev["p_stress"], outs, self.halt())
        self._hand_particles(run, where, spec[2], dt, time)

    def _run_arrays(self, run):
        """What a launch of the particle-stage ``run`` takes: ((rule, scratch, slots, maxima), (its stages'
        parameters, its table), the material blocks it acts on, the tally slice of its accumulator rows)."""
        first = run[0][0]
        cls, ids = type(first), tuple(id(s) for s, _ in run)
        prms = self._small(("particle", ids), np.stack([np.asarray(a[0], np.float64) for _, a in run]))
        aux = self._table(first, "particle", run[0][1][1])
        slots = max(first.particle_reduction, 1)
        _, where = self._pass_slots((ids, "particle"), slots * len(run))
        spec = (cls.particle_rule, max(cls.particle_scratch, 1), slots, tuple(cls.particle_maxima))
        return spec, (prms, aux), set(first.particle_blocks(len(self.state.blocks))), where

    def _hand_particles(self, run, where: slice, slots: int, dt: float, time: float) -> None:
        self._hand_run(run, where, slots, lambda stage: (lambda rows: stage.particle_reduced(rows, dt, time),
                                                         stage.particle_reduction))

    # -- the step's reductions, read once at its end -----------------------------------------------------
    def _pass_slots(self, key, slots: int):
        """(device view, slice) of the tally slots of this step's next pass of ``key`` (a stage's id and pass kind;
        a group's stage ids), zero at the step's start."""
        nth = self._passes.get(key, 0)
        self._passes[key] = nth + 1
        return self.tally.slots((key, nth), np.zeros(slots)), self.tally.reserve((key, nth), ())

    def _hand_run(self, run, where: slice, slots: int, reducer) -> None:
        """Hand each stage of ``run`` its ``slots`` of the tally's ``where``, in order; ``reducer(stage)`` gives the
        stage's ``*_reduced`` (a function of the rows) and its declared reduction."""
        for g, (stage, _) in enumerate(run):
            reduced, declared = reducer(stage)
            self._hand(reduced, slice(where.start + g * slots, where.start + (g + 1) * slots), declared)

    def _hand(self, reduced, where: slice, declared: int) -> None:
        """Hand the tally's ``where`` slots to ``reduced`` (a stage's ``*_reduced``) when the step settles."""
        self._handed.append((reduced, where, declared, self._step))

    def _end_now(self) -> dict:
        """The step-end reductions (``_end_values``): the last ``settle``'s if nothing has changed the particles
        since, else taken now (a settle that sends the host's arrays first where they are newer)."""
        end = self._end
        if end is None or end[0] != self._moved or self._on_host:
            self.settle(now=True)
            end = self._end
        return end[1]

    def halt(self):
        """The tally's halt slot (the device view every kernel of a step is handed: engine/held_step.py)."""
        return self.tally.slots("halt", [0.0])

    def _end_start(self):
        """The step-end rows' starting values, END_START for each material block (made once)."""
        if self._end_rows0 is None:
            self._end_rows0 = np.tile(K.END_START, len(self.state.blocks))
        return self._end_rows0

    def _step_end(self, step: int) -> None:
        """The step-end reductions of the particles into the tally slots of ``step`` (one launch per block)."""
        st = self.state
        dev = self._device()
        rows = self.tally.slots(("end", step), self._end_start())
        taken = self._rows_at == (self._moved, step)  # by the particle pass (g2p_stages_and_stress)
        for k, (s, e) in enumerate(st.blocks):
            if e > s and not taken:
                K.step_end[K.blocks(e - s), K.THREADS](dev["p_x"], dev["p_x0"], dev["p_v"], dev["p_rho"],
                                                       dev["p_stress"], dev["p_mass"], self._gravity, s, e,
                                                       rows[k * K.END_ROW:(k + 1) * K.END_ROW], self.halt())
        self.scheme_passes.end_reductions(self)

    def settle(self, now: bool = False) -> None:
        """One blocking copy: this step's stage accumulators and largest |L_ii|, and the step-end reductions the
        next step's time step, grid window, health and domain checks read (cuda_kernels.step_end, one launch
        per material block), all in the tally; then the stages' ``*_reduced`` in pass order, and the tally
        reset for the next step.  At a step's end the step-end reductions are skipped where the host holds the
        particles (it may change them before the next step); ``now`` takes them all the same (``_end_now``).
        In a held batch a step's end launches its step-end reductions and reads nothing (``release`` does)."""
        if self._held is not None and not now:
            self._step_end(self._step)
            return
        ended = now or not self._on_host
        if ended:
            self._step_end(0)
        if not (ended or self._handed or self._rate_due):
            return
        self._read(1, ended)

    def _read(self, launched: int, ended: bool) -> int:
        """The tally to the host and reset: how many of the ``launched`` steps since the last read were taken (all
        but those after a held batch's failed check), their stages' reductions handed in order, the largest
        |L_ii| and (``ended``) the step-end values of the last of them kept."""
        values = self.tally.read()
        self.tally.reset()
        self._rows_at = None
        steps = int(values[self.tally.where("halt")][0]) or launched
        handed, self._handed, self._passes = self._handed, [], {}
        last = steps - 1
        if self._rate_due:
            self.max_rate, self._rate_due = float(values[self.tally.reserve(("rate", last), ())][0]), False
        if ended:
            self._end = (self._moved, self._end_values(values, len(self.state.blocks), last))
        for reduced, where, declared, step in handed:
            if step < steps:
                reduced(self.joined(values[where].reshape(1, -1), declared))
        return steps

    # -- the held step (engine/held_step.py) ----------------------------------------------------------------
    def end_rows(self):
        return self._end_now()["rows"]

    def hold(self, box, cells) -> None:
        super().hold(box, cells)
        self._step = 0

    def gate(self, i: int) -> bool:
        """Launch the check of step ``i`` (cuda_kernels.held_gate) on the rows step ``i - 1`` left: the answer
        stays on the device, where it stops the batch's later kernels."""
        self._step = i
        rows = self.tally.slots(("end", i - 1), ())
        rate = self.tally.slots(("rate", i - 1), [0.0])
        K.held_gate[1, 1](rows, rate, self._small("held", self._held[0]), self.halt(), float(i))
        return True

    def release(self, launched: int) -> int:
        """One blocking copy for the batch: how many of its ``launched`` steps were taken (the halt slot), their
        reductions handed to the stages in order, the last one's step-end values kept."""
        super().release(launched)
        self._step = 0
        return self._read(launched, True)

    def _end_values(self, values, nb: int, step: int) -> dict:
        """The step-end rows of ``step`` (kernels/step_end.END_ROW per material block) combined over the blocks."""
        d = self.scene.dim
        flat = values[self.tally.reserve(("end", step), ())]
        rows = flat.reshape(nb, K.END_ROW)
        speed_density = np.empty(1 + 2 * nb)
        speed_density[0] = rows[:, 9].max()
        speed_density[1::2], speed_density[2::2] = rows[:, 10], rows[:, 11]
        return {"values": values, "rows": flat.copy(),
                "lo": -rows[:, 0:d].max(axis=0), "hi": rows[:, 3:3 + d].max(axis=0),
                "sum": rows[:, 6:6 + d].sum(axis=0), "speed_density": speed_density,
                "health": (float(rows[:, 12].sum()), float(rows[:, 13].sum()), float(rows[:, 14].sum()))}

    def _block_cells(self, flat) -> list:
        """Each material block's lowest and highest cell ((d,) int64 each) from the step-end rows ``flat``, None for
        an empty block or one with a non-finite coordinate (cuda_sort.cell_order's ``extents``)."""
        d, spec = self.scene.dim, self.scene.grid
        cells = []
        for row, (s, e) in zip(flat.reshape(-1, K.END_ROW), self.state.blocks):
            lo, hi, total = -row[0:d], row[3:3 + d], row[6:6 + d]
            finite = e > s and np.isfinite(total).all() and np.isfinite(lo).all() and np.isfinite(hi).all()
            cells.append((np.floor((lo - spec.origin) * (1.0 / spec.h)).astype(np.int64),
                          np.floor((hi - spec.origin) * (1.0 / spec.h)).astype(np.int64)) if finite else None)
        return cells

    def ended_slots(self, key):
        """The values of the tally slots ``key`` (a scheme's ``end_reductions``) of the step-end reductions."""
        return self._end_now()["values"][self.tally.where(key)]

    def health_sums(self, gravity):
        return self._end_now()["health"]

    def particles_outside(self, lo, hi) -> int:
        """0 where the step-end bounds lie inside [lo, hi] and every coordinate is finite; else counted on the
        host."""
        end = self._end_now()
        if np.isfinite(end["sum"]).all() and (end["lo"] >= lo).all() and (end["hi"] <= hi).all():
            return 0
        return super().particles_outside(lo, hi)
