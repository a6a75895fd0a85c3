"""An inflow: particles entering through a cross-section with the discharge of a hydrograph.

The gate is a cross-section of the flow at the ``section``: in 2D one point on the bed, in 3D a polyline
across the channel on the bed (points given in plan are put on the ground below them: the highest point where
no rigid solid of the scene, terrain, plane or obstacle, lies above). The flow crosses it along ``direction``
d; its depth is measured along u, the part of -g normal to d (the bed normal on a slope whose line of steepest
descent is d). With the hydrograph's Q(t) and speed v(t) (or depth h(t)), sources/hydrograph.py,

    h = Q / (v w)    or    v = Q / (h w),     w = 1 m in 2D, the polyline's width across d in 3D.

Particles of spacing s = cell / particles_per_cell and volume V_p = s^dim come in slices: a slice is n_w
particles across (the polyline resampled at s; one in 2D) times n_d = max(1, round(h / s)) along u, bottom
layer first, with n_d fixed when the slice starts. Before and after each step the particles due are added,

    N(t) = floor(V(t) / V_p),   V(t) = int_0^t Q dt   (exact for the piecewise-linear Q),

so the injected volume N V_p is never more than V(t) and never a particle's volume less: mass is conserved to
the particle at every step. A slice sits where its middle volume V_c = (first + n_w n_d / 2) V_p has travelled
since it crossed, d v (t - t(V_c)): up to half a slice spacing upstream of the section while it fills, so the
particles form a lattice of spacing about s. Each particle starts with the velocity v d, the density of its
material, its law's initial state and the stress of a layer at rest, sigma_n = -rho g_u (n_d s - z) along u
and K0 sigma_n across.
"""

from __future__ import annotations

import math

import numpy as np

from geompm.contract.stages import ParticleSource
from geompm.errors import CaseError
from geompm.sources.hydrograph import Hydrograph

#: bisection steps of the bed search (the grid's height / 2^60: exact in float64)
BED_STEPS = 60


def bed_height(stages, xy, lo: float, hi: float) -> float | None:
    """The height z in [lo, hi] of the ground below the plan point ``xy`` (2,): where the deepest of the stages'
    rigid solids (``solid_depth``) changes sign, by bisection; None where no stage has a solid at ``lo``."""
    def depth(z):
        pt = np.array([[xy[0], xy[1], z]])
        ds = [d[0] for d in (s.solid_depth(pt) for s in stages) if d is not None]
        return max(ds) if ds else None

    if depth(lo) is None or depth(lo) <= 0.0:
        return None
    a, b = lo, hi
    for _ in range(BED_STEPS):
        mid = 0.5 * (a + b)
        if depth(mid) > 0.0:
            a = mid
        else:
            b = mid
    return b


class Inflow(ParticleSource):
    """The inflow ``params`` (schema/case.InflowSpec) with its ``hydrograph`` (sources/hydrograph.Hydrograph)."""

    supplies_energy = True  # the kinetic energy its particles bring in (supplied_work: the health check's budget)

    def __init__(self, params, label: str, json_path: str, hydrograph: Hydrograph):
        super().__init__(params, label, json_path)
        self.hydrograph = hydrograph

    def setup(self, scene):
        p, d = self.params, scene.dim
        self.dim = d
        self.mid = scene.material_names.index(p.material)
        mat = scene.materials[self.mid]
        self.density, self.k0 = mat.density, mat.k0()
        self.material = mat
        self.s = scene.grid.h / p.particles_per_cell
        self.vp = self.s ** d
        g = np.asarray(scene.gravity, float)
        self.direction = np.asarray(p.direction, float) / np.linalg.norm(p.direction)
        up = -g - float(-g @ self.direction) * self.direction
        self.up = up / np.linalg.norm(up)
        self.g_up = float(-g @ self.up)  # > 0: gravity's part against which the layer stands
        self.base, self.width = self._gate(scene)
        self.body = len(scene.body_materials)
        scene.body_materials.append(p.material)
        self.first_id = scene.next_particle_id
        self.total = int(math.floor(self.hydrograph.total / self.vp * (1 + 1e-12)))
        scene.next_particle_id += self.total
        self.count = 0  # particles added so far
        self.brought = 0.0  # kinetic energy of the particles added so far [J; J/m in 2D]
        self.slice = (0, 1, 0.0)  # the filling slice: (particles in it so far, layers n_d, its middle's time t_c)

    def _gate(self, scene):
        """The base points (n_w, d) of a slice on the bed, and the gate's width across the flow w [m]."""
        d, pts = self.dim, [np.asarray(q, float) for q in self.params.section]
        if d == 2:
            return pts[0][None, :], 1.0
        grid = scene.grid
        full = []
        for i, q in enumerate(pts):
            if len(q) == 3:
                full.append(q)
                continue
            z = bed_height(scene.stages, q, float(grid.origin[2]), float(grid.upper[2]))
            if z is None:
                raise CaseError([(f"{self.json_path}.section.{i}", f"no ground (terrain, plane or obstacle) below "
                                  f"({q[0]:g}, {q[1]:g}) inside the grid: give the point's height as a third "
                                  "coordinate")])
            full.append(np.array([q[0], q[1], z]))
        seg = np.diff(np.asarray(full), axis=0)
        lengths = np.linalg.norm(seg, axis=1)
        across = seg - np.outer(seg @ self.direction, self.direction) - np.outer(seg @ self.up, self.up)
        width = float(np.linalg.norm(across, axis=1).sum())
        nw = max(1, int(round(lengths.sum() / self.s)))
        arc = (np.arange(nw) + 0.5) * lengths.sum() / nw
        cum = np.r_[0.0, np.cumsum(lengths)]
        base = np.empty((nw, 3))
        for a in range(3):
            base[:, a] = np.interp(arc, cum, np.asarray(full)[:, a])
        return base, width

    # -- the hydrograph at the gate -------------------------------------------------------------------------
    def speed_and_depth(self, time: float) -> tuple[float, float]:
        """(v [m/s], h [m]) at the gate at ``time``."""
        hg = self.hydrograph
        q, c = hg.discharge(time), hg.column(time)
        if hg.kind == "velocity":
            return c, (q / (c * self.width) if c > 0 else 0.0)
        return (q / (c * self.width) if c > 0 else 0.0), c

    def warnings(self) -> list[str]:
        hg = self.hydrograph
        k = int(np.argmax(hg.q))
        v, h = self.speed_and_depth(float(hg.t[k]))
        out = []
        if h < 2.0 * self.s:
            out.append(f"{self.json_path}: at the peak discharge ({hg.q[k]:g} at t = {hg.t[k]:g} s) the inflow is "
                       f"{h:.3g} m deep, {h / self.s:.2g} particle spacings ({self.s:.3g} m): the flow is barely "
                       f"resolved; a grid.cell_size of {h * self.params.particles_per_cell / 4:.3g} m or less gives "
                       "it 4 spacings")
        return out

    # -- the particles ------------------------------------------------------------------------------------
    def supply(self, state, time: float):
        self._time = time
        due = min(self.total, int(math.floor(self.hydrograph.volume(time) / self.vp * (1 + 1e-12))))
        new = due - self.count
        if new <= 0:
            return None
        d, nw = self.dim, len(self.base)
        v, h = self.speed_and_depth(time)
        pos = np.empty((new, d))
        height = np.empty(new)
        top = np.empty(new)
        filled, nd, tc = self.slice
        for k in range(new):
            if filled == 0:  # a slice starts: its layers from the depth now, its middle's crossing time
                nd = max(1, int(round(h / self.s)))
                tc = self.hydrograph.time_of((self.count + k + 0.5 * nw * nd) * self.vp)
                if not math.isfinite(tc):
                    tc = self.hydrograph.end
            layer, across = divmod(filled, nw)
            height[k] = (layer + 0.5) * self.s
            top[k] = nd * self.s
            pos[k] = self.base[across] + height[k] * self.up + v * (time - tc) * self.direction
            filled = (filled + 1) % (nw * nd)
        self.slice = (filled, nd, tc)
        first = self.first_id + self.count
        self.count = due
        self.brought += 0.5 * new * self.vp * self.density * v * v
        return self._packet(state, pos, v, height, top, first)

    def _packet(self, state, pos, v, height, top, first):
        n, d = pos.shape
        sn = -self.density * self.g_up * (top - height)  # sigma_n [Pa]
        u3 = np.zeros(3)
        u3[:d] = self.up
        ident = np.eye(3)
        stress = np.zeros((n, 6))
        for slot, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
            stress[:, slot] = sn * (u3[a] * u3[b] + self.k0 * (ident[a, b] - u3[a] * u3[b]))
        values = {
            "p_x": pos, "p_x0": pos, "p_v": np.tile(v * self.direction, (n, 1)),
            "p_C": np.zeros((n, d, d)), "p_L": np.zeros((n, 3, 3)), "p_stress": stress,
            "p_mass": np.full(n, self.vp * self.density), "p_vol0": np.full(n, self.vp),
            "p_vol": np.full(n, self.vp), "p_rho": np.full(n, self.density),
            "p_material": np.full(n, self.mid), "p_body": np.full(n, self.body),
            "p_id": first + np.arange(n),
        }
        arrays = {}
        for name, arr in state.arrays().items():
            if name not in values:
                raise RuntimeError(f"{self.json_path}: the particle array '{name}' of the scheme has no value for "
                                   "added particles")
            arrays[name] = np.ascontiguousarray(values[name], dtype=arr.dtype)
        counts = [0] * len(state.blocks)
        counts[self.mid] = n
        states = [np.zeros((0, sv.shape[1]), sv.dtype) for sv in state.p_state]
        states[self.mid] = np.ascontiguousarray(self.material.initial_state(n), dtype=state.p_state[self.mid].dtype)
        return {"counts": counts, "arrays": arrays, "states": states}

    def supplied_work(self) -> float:
        return self.brought

    def supplied_speed(self) -> float:
        return 0.0  # it drives nothing after the particles are in: their energy is supplied_work

    def pending(self, time: float) -> bool:
        return self.count < self.total

    def particles_total(self) -> int:
        return self.total

    def describe(self) -> str:
        hg = self.hydrograph
        k = int(np.argmax(hg.q))
        v, h = self.speed_and_depth(float(hg.t[k]))
        unit, flux = ("m3", "m3/s") if self.dim == 3 else ("m2 per metre", "m2/s per metre")
        return (f"inflow '{self.label}' ({self.json_path}): {hg.total:.6g} {unit} from t = {hg.t[0]:g} to "
                f"{hg.end:g} s in {self.total} particles of {self.vp:.3g} {unit.split()[0]} (spacing {self.s:.3g} m, "
                f"{len(self.base)} across a gate {self.width:.4g} m wide); peak {hg.q[k]:.4g} {flux} at "
                f"t = {hg.t[k]:g} s: {v:.3g} m/s, {h:.3g} m deep ({h / self.s:.2g} particle spacings)")

    def entering(self):
        speeds = [self.speed_and_depth(float(t))[0] for t in self.hydrograph.t]
        return self.mid, max(speeds, default=0.0)

    def particle_mass(self) -> float:
        return self.vp * self.density

    def series(self):
        return {f"{self.label}_volume_in": self.count * self.vp,
                f"{self.label}_discharge": self.hydrograph.discharge(self._time)}

    _time = 0.0  # the time of the last supply: the step's start, at which series.csv reads the discharge

    def summary(self) -> str:
        unit = "m3" if self.dim == 3 else "m2 per metre"
        return (f"inflow '{self.label}': {self.count} particles, {self.count * self.vp:.6g} {unit} of "
                f"{self.hydrograph.total:.6g} {unit} in the hydrograph")

    def state_dict(self):
        filled, nd, tc = self.slice
        return {"count": self.count, "slice": [filled, nd, tc], "brought": self.brought}

    def load_state(self, state):
        self.count = int(state.get("count", 0))
        self.brought = float(state.get("brought", 0.0))
        filled, nd, tc = state.get("slice", (0, 1, 0.0))
        self.slice = (int(filled), int(nd), float(tc))
