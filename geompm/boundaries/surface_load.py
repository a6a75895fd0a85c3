"""Surface load: a pressure or a traction on a body's surface, constant or ramped in time.

The load acts on the body's face inside ``region``: of the particles whose initial position x0 lies in
the box, those outermost along the normal in their column (``outermost_in_box``: on a seeding lattice and
an axis-aligned normal, exactly the face row of particles; for an oblique normal, the outermost in bins one
particle spacing wide). They are chosen once, by their ids, so the loaded particles stay the same whatever
the material does later. Its total force is

    F(t) = r(t) A t_s,    r(t) = min(1, t / ramp_time)   (r = 1 when ramp_time = 0),

with ``t_s`` the traction [Pa]: ``traction`` as given, or t_s = -q n_hat for a ``pressure`` q (positive
pushes into the body) on a surface whose outward normal is ``normal``; A is the area of the box seen along
the normal, A = sum_a |n_a| prod_{b != a} (max_b - min_b) (the face area for an axis-aligned normal; per
metre of width in 2D). F is shared among the loaded particles by mass (f_p = m_p F / M_loaded) and
enters the grid as an external nodal force, f_i += sum_p w_ip f_p, before damping and the boundaries:
exactly how gravity enters, so Cundall's local damping sees the unbalanced force with the load in it.
(Adding the load to the particles' velocities instead would hide it from local damping, which then
holds the body at q / (1 + alpha): measured 0.77 q at alpha = 0.3.)

The box may reach as deep into the body as convenient: only the face row is loaded, and below it the
body carries the load. In the confined
elastic column (tests/verification/test_surface_load.py) the settlement equals q H / M,
M = E (1 - nu) / ((1 + nu)(1 - 2 nu)) (the oedometric modulus), within the errors tabled in
docs/case-format.md.

Particle-set tractions load bodies the same way in CB-Geo's MPM (Kumar et al. 2019,
arXiv:1909.13380). Detecting the free surface automatically is left to the pore-water formulation,
which needs it for drainage. Each pass checks the loaded particles' indices against their x0 (a pass
over the loaded particles only, unless a sort or a deletion moved them) and scatters their forces
serially on the host: a cost in proportion to the loaded surface, paid only by cases with a load.

The stage supplies energy: the work its force does on the material (the positive part of each step's
sum_i f_i . v_i dt) joins the health check's budget (engine/health.py), so a loaded body that
accelerates is not mistaken for a blow-up.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from geompm.parallel.comm import SERIAL
from geompm.contract.layout import param_layout
from geompm.contract.plugin import Params, nonzero_vector
from geompm.contract.stages import LOAD, GridStage
from geompm.errors import CaseError
from geompm.kernels.shape import point_stencil, support

#: packed parameters: the grid origin [m] and 1/h [1/m], the first node (global index) of the load's
#: node lattice and its node counts
LOAD_PRM = param_layout("origin_x", "origin_y", "origin_z", "inv_h", "lo_x", "lo_y", "lo_z", "n_x", "n_y", "n_z")
ORIGIN0, LO0, N0 = LOAD_PRM.origin_x, LOAD_PRM.lo_x, LOAD_PRM.n_x
#: accumulator slots: the applied force (3) [N, N/m in 2D] and its work this step [J, J/m]
APPLIED0, WORK = 0, 3


class LoadRegion(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    min: list[float] = Field(description="Lower corner of the box that selects the loaded particles [m]")
    max: list[float] = Field(description="Upper corner [m]")


class SurfaceLoadParams(Params):
    region: LoadRegion = Field(description="Box selecting the loaded particles by their initial position [m]")
    normal: list[float] = Field(description="Outward normal of the loaded surface (any length)")
    pressure: float | None = Field(None, description="Pressure q [Pa], positive pushing into the body "
                                                     "(give this or traction)")
    traction: list[float] | None = Field(None, description="Traction vector t [Pa] (give this or pressure)")
    ramp_time: float = Field(0.0, ge=0.0, description="The load grows linearly from 0 to its value over "
                                                      "this time [s] (0: applied at once)")

    _nonzero = field_validator("normal")(nonzero_vector)

    @model_validator(mode="after")
    def _one_load(self):
        if (self.pressure is None) == (self.traction is None):
            raise ValueError("give exactly one of 'pressure' [Pa] and 'traction' [Pa]")
        return self


@njit(cache=True, inline="always")
def surface_load_rule(prm, aux, dt, x, m, v, v_old, f, pw, work, out):
    """The node's share of the load, aux[3 k : 3 k + 3] for its index k in the load's lattice, added to
    its force and, as dt f / m, to its velocity; out sums the applied force and its work f . v dt."""
    d = x.shape[0]
    k = 0
    for a in range(d):
        i = int(round((x[a] - prm[ORIGIN0 + a]) * prm[LOAD_PRM.inv_h])) - int(prm[LO0 + a])
        n = int(prm[N0 + a])
        if i < 0 or i >= n:
            return
        k = k * n + i
    for a in range(d):
        fa = aux[3 * k + a]
        f[a] += fa
        v[a] += dt * fa / m
        out[APPLIED0 + a] += fa
        out[WORK] += fa * v[a] * dt


@njit(cache=True)
def scatter_load(p_x, loaded, p_mass, accel, origin, inv_h, kind, lo, n, forces):
    """forces[k] += w_ip m_p accel for each loaded particle p and node k of the lattice (first node lo,
    counts n): the nodal external force of the particles' share of the load."""
    d = p_x.shape[1]
    for q in range(loaded.shape[0]):
        p = loaded[q]
        b0, w0, b1, w1, b2, w2, s2 = point_stencil(p_x[p], origin, inv_h, kind)
        for i in range(4):
            for j in range(4):
                for l in range(s2):
                    w = w0[i] * w1[j] * w2[l]
                    if w == 0.0:
                        continue
                    k = (b0 + i - lo[0]) * n[1] + (b1 + j - lo[1])
                    if d == 3:
                        k = k * n[2] + (b2 + l - lo[2])
                    for a in range(d):
                        forces[3 * k + a] += w * p_mass[p] * accel[a]


def outermost_in_box(x0, vol0, lo, hi, n_hat) -> np.ndarray:
    """Indices of the particles inside the box [lo, hi] that are outermost along n_hat in their column:
    the box's particles binned by their coordinates across n_hat (bins of the smallest particle spacing
    V0^(1/d)), the largest x0 . n_hat in each bin. On a seeding lattice and an axis-aligned normal a
    column is one lattice line, so this is exactly the body's face row inside the box."""
    inside = np.nonzero(np.all((x0 >= lo) & (x0 <= hi), axis=1))[0]
    if len(inside) == 0:
        return inside
    d = x0.shape[1]
    pts = x0[inside]
    spacing = float(vol0[inside].min()) ** (1.0 / d)
    # an orthonormal basis whose first vector is n_hat: the other d - 1 are the coordinates across it
    basis = np.linalg.qr(np.column_stack([n_hat, np.eye(d)[:, :d - 1]]))[0]
    coords = pts @ basis[:, 1:]
    # lattice columns sit whole spacings from the first one: rounding to the nearest is far from a tie
    across = np.rint((coords - coords.min(axis=0)) / spacing).astype(np.int64)
    height = pts @ n_hat
    order = np.lexsort((-height, *across.T[::-1]))  # by column, the outermost first in each
    cols = across[order]
    first = np.ones(len(order), bool)
    first[1:] = np.any(cols[1:] != cols[:-1], axis=1)
    return inside[order[first]]


def projected_area(lo, hi, n_hat) -> float:
    """Area [m2, m in 2D] of the box [lo, hi] seen along the unit vector n_hat."""
    ext = np.asarray(hi, float) - np.asarray(lo, float)
    d = len(ext)
    return float(sum(abs(n_hat[a]) * np.prod([ext[b] for b in range(d) if b != a]) for a in range(d)))


class SurfaceLoad(GridStage):
    name = "surface_load"
    description = "Pressure or traction on a body's surface (the particles in a box), constant or ramped"
    Params = SurfaceLoadParams
    phase = LOAD
    supplies_energy = True
    #: the load is added to the nodal force that local damping reads, so the force is kept apart
    needs_split_force = True
    #: one process's communicator until the run hands the stage its own (contract/stages.py)
    comm = SERIAL
    node_rule = surface_load_rule
    node_reduction = 4

    @classmethod
    def check(cls, params, case):
        d = case.dimension
        problems = [(k, f"must have {d} entries (one per dimension)")
                    for k, vec in (("region.min", params.region.min), ("region.max", params.region.max),
                                   ("normal", params.normal), ("traction", params.traction))
                    if vec is not None and len(vec) != d]
        if not problems and any(a >= b for a, b in zip(params.region.min, params.region.max)):
            problems.append(("region", "min must be below max on every axis"))
        return problems

    def setup(self, scene):
        st = scene.state
        p = self.params
        self.state, self.grid = st, scene.grid
        self.dim = d = st.p_x.shape[1]
        lo, hi = np.asarray(p.region.min, float), np.asarray(p.region.max, float)
        n = np.asarray(p.normal, float)
        n_hat = n / np.linalg.norm(n)
        self.loaded_ids = np.sort(st.p_id[outermost_in_box(st.p_x0, st.p_vol0, lo, hi, n_hat)])
        self._idx, self.count = None, -1
        self.loaded()
        if self.count == 0:
            raise CaseError([(f"{self.json_path}.region", f"surface load '{self.label}': no particle starts "
                              f"inside the box {list(p.region.min)} to {list(p.region.max)} m; make it cover "
                              f"the loaded face")])
        self.area = projected_area(lo, hi, n_hat)
        traction = -p.pressure * n_hat if p.pressure is not None else np.asarray(p.traction, float)
        self.force = self.area * traction  # at full load [N, N/m in 2D]
        self.work = 0.0  # positive part of the load's work so far [J, J/m in 2D]
        self.applied = np.zeros(d)
        self._box = None
        self.prm = np.zeros(len(LOAD_PRM))  # the grid's origin and 1/h; the lattice's corner and size per pass
        self.prm[ORIGIN0:ORIGIN0 + d] = scene.grid.origin
        self.prm[LOAD_PRM.inv_h] = 1.0 / scene.grid.h

    def loaded(self) -> np.ndarray:
        """Indices of the loaded particles (ids ``loaded_ids``) in the current particle order. The last
        answer is kept and checked in O(loaded particles): it still holds when every index it names is a
        loaded particle and their number has not changed (a sort permutes, a deletion shrinks). Otherwise
        one pass over all particles finds them again and the loaded mass is summed anew."""
        idx = self._idx
        st = self.state
        if idx is not None and len(idx) == self.count and (len(idx) == 0 or idx[-1] < st.n) \
                and np.isin(st.p_id[idx], self.loaded_ids, assume_unique=True).all():
            return idx
        idx = np.nonzero(np.isin(st.p_id, self.loaded_ids))[0]
        self._idx, self.count = idx, len(idx)
        self.local_mass = float(st.p_mass[idx].sum())
        return idx

    def ramp(self, time: float) -> float:
        tr = self.params.ramp_time
        return 1.0 if tr <= 0.0 else min(1.0, max(time, 0.0) / tr)

    def grid_args(self, dt, time, remap):
        if remap:
            return None  # the MUSL re-mapped velocities already carry this step's load
        st, g, comm = self.state, self.grid, self.comm
        d = self.dim
        idx = self.loaded()
        x = st.p_x[idx]
        r = support(g.kind)
        # the loaded particles' box and mass over every rank, then each rank's share of the lattice summed
        lo = comm.min(x.min(axis=0) if len(idx) else np.full(d, np.inf))
        hi = comm.max(x.max(axis=0) if len(idx) else np.full(d, -np.inf))
        self.loaded_mass = float(comm.sum([self.local_mass])[0])
        first = np.floor((lo - g.origin) / g.h).astype(np.int64) - r
        last = np.floor((hi - g.origin) / g.h).astype(np.int64) + r
        n = last - first + 1
        forces = np.zeros(3 * int(np.prod(n)))
        accel = self.ramp(time + dt) * self.force / self.loaded_mass
        scatter_load(st.p_x, idx, st.p_mass, accel, g.origin, 1.0 / g.h, g.kind, first, n, forces)
        forces = comm.sum(forces)
        prm = self.prm.copy()
        prm[LO0:LO0 + d] = first
        prm[N0:N0 + d] = n
        self._box = (first, last)
        return prm, forces

    def node_box(self, time):
        return self._box

    def grid_reduced(self, out, dt, time, remap):
        total = out.sum(axis=0)
        self.applied = total[APPLIED0:APPLIED0 + self.dim].copy()
        self.work += max(float(total[WORK]), 0.0)

    def supplied_work(self) -> float:
        return self.work

    def series(self):
        row = {f"{self.label}_load_{c}": float(self.applied[a]) for a, c in enumerate("xyz"[:self.dim])}
        row[f"{self.label}_load_work"] = self.work
        return row

    def summary(self):
        unit = "N" if self.dim == 3 else "N/m"
        return (f"surface load '{self.label}': {self.count} particles, area {self.area:.4g} "
                f"{'m2' if self.dim == 3 else 'm per m'}, full force {np.linalg.norm(self.force):.4g} {unit}")

    def state_dict(self):
        return {"work": self.work}

    def load_state(self, state):
        self.work = float(state.get("work", 0.0))
