"""Blow-up detection: stop a run whose state has become unphysical, and say why.

Checked after every step, in one parallel pass over the particles:

- a NaN or Inf in any position, velocity or stress;
- kinetic energy beyond what the run can supply.  Energy conservation bounds
  E_k(t) <= E_k(0) + W_g(t) + U_0 + E_v, with W_g = sum max(m g . (x - x0), 0) the
  energy released by the particles that moved down (an upper bound of the work of
  gravity that a runaway particle thrown upwards cannot cancel), U_0 = sum V
  sigma:sigma / (2 E) the strain energy the
  initial stress can release, E_v = 2 M v_o^2 for obstacles moving at v_o, and
  the work of a water table's pore pressure (kernels/phreatic.pore_work).
  An explicit scheme past its stability limit grows energy exponentially, so the
  check uses a factor 2 on that bound plus a floor of 1e-6 M |g| L (L the grid
  diagonal), far above the small energy errors of a stable run;
- before each step, a stable time step below ``time.dt_min`` (viscous limits
  of stiff fluids, or runaway speeds).

Each message names the step, time, particle index, body and material and the
likely cause with a remedy.  Particles leaving the grid are caught by the grid
window (grid.py) or, with ``run.on_leave_domain = "delete"``, removed here.
"""

from __future__ import annotations

import numpy as np

from geompm.errors import SimulationError
from geompm.backend.timestep import below_dt_min, viscous_limit, wave_speed
from geompm.kernels.health import health_sums, outside_grid  # noqa: F401  (envelope.py and the tests take them here)
from geompm.parallel.comm import SERIAL


def _first_nonfinite(st) -> int:
    bad = ~(np.isfinite(st.p_x).all(axis=1) & np.isfinite(st.p_v).all(axis=1) & np.isfinite(st.p_stress).all(axis=1))
    return int(np.argmax(bad))


def _strain_energy(scene) -> float:
    st = scene.state
    u = 0.0
    for mat, (s, e) in zip(scene.materials, st.blocks):
        try:
            stiff = mat.stiffness()
        except NotImplementedError:
            continue
        sig = st.p_stress[s:e]
        u += float((st.p_vol[s:e] * ((sig[:, :3] ** 2).sum(axis=1) + 2 * (sig[:, 3:] ** 2).sum(axis=1))).sum()) / (2 * stiff)
    return u


def describe_particle(sim, p) -> str:
    st, sc = sim.state, sim.scene
    material = sc.material_names[int(st.p_material[p])]
    return (f"particle {int(st.p_id[p])} (body {int(st.p_body[p])}, material '{material}') at step "
            f"{sim.step_count}, t = {sim.time:.6g} s")


def first_message(comm, message):
    """The first rank's message, on every rank, where a check failed on some ranks (``message``: this
    rank's, or None)."""
    return next(m for m in comm.gather(message) if m)


def fastest(comm, sim):
    """(index of this rank's fastest particle or -1, whether it is the fastest of the run)."""
    st = sim.state
    v2 = (st.p_v ** 2).sum(axis=1)
    p = int(np.argmax(v2)) if st.n else -1
    best = float(v2[p]) if st.n else -1.0
    return p, best >= float(comm.max([best])[0]) and p >= 0


class HealthCheck:
    def __init__(self, scene, comm=SERIAL):
        st = scene.state
        self.scene = scene
        self.comm = comm
        mass = float(comm.sum([st.p_mass.sum()])[0])
        g = float(np.linalg.norm(scene.gravity))
        diag = float(np.linalg.norm(scene.grid.upper - scene.grid.origin))
        v_obs = max((s.supplied_speed() for s in scene.stages if s.supplies_energy), default=0.0)
        _, ek0, _ = health_sums(st.p_x, st.p_x0, st.p_v, st.p_stress, st.p_mass, scene.gravity)
        ek0, strain = (float(x) for x in comm.sum([ek0, _strain_energy(scene)]))
        self.budget0 = ek0 + strain + 2.0 * mass * v_obs ** 2
        self.floor = 1e-6 * mass * max(g, 1.0) * diag
        self.kinetic_energy = ek0
        self.released = 0.0  # energy gravity has released so far [J] (health_sums)

    def after_step(self, sim) -> None:
        """The sums come from the backend (a device backend reduces them there: no particle array is read on the
        host unless a check fails)."""
        sc = self.scene
        comm = self.comm
        mine, ek, wg = sim.backend.health_sums(sc.gravity)
        work = sim.water.work(sim.backend, sim.time)
        bad, ek, wg, work = comm.sum([mine, ek, wg, work])
        bad, ek, wg = int(round(bad)), float(ek), float(wg)
        self.kinetic_energy, self.released = ek, wg
        if bad:
            message = None
            if mine:
                st = sim.state
                p = _first_nonfinite(st)
                field = next(name for name, arr in (("position", st.p_x), ("velocity", st.p_v),
                                                    ("stress", st.p_stress)) if not np.isfinite(arr[p]).all())
                message = (f"NaN or Inf in the {field} of {describe_particle(sim, p)} ({bad} particles affected). "
                           f"Likely cause: {self._likely_cause(sim)}")
            raise SimulationError(first_message(comm, message))
        allowed = self.budget0 + max(wg, 0.0) + sum(s.supplied_work() for s in sc.stages if s.supplies_energy)
        allowed += float(work)
        if ek > 2.0 * allowed + self.floor:
            p, top = fastest(comm, sim)
            st = sim.state
            raise SimulationError(first_message(comm, None if not top else
                f"kinetic energy {ek:.4g} J exceeds what gravity, the initial stress, moving obstacles, loads and "
                f"a water table can "
                f"supply ({allowed:.4g} J) at step {sim.step_count}, t = {sim.time:.6g} s; fastest: "
                f"{describe_particle(sim, p)}, |v| = {np.linalg.norm(st.p_v[p]):.4g} m/s. Likely cause: "
                f"{self._likely_cause(sim)}"))

    def before_step(self, sim, dt) -> None:
        sc = self.scene
        if not below_dt_min(sc, dt):
            return
        st = sim.state
        p, top = fastest(self.comm, sim)
        if viscous_limit(sc) <= dt * (1 + 1e-9):
            k = int(np.argmax([m.kinematic_viscosity() for m in sc.materials]))
            cause = (f"the viscous limit h^2 / (2 d nu) with nu = {sc.nu_max:.3g} m2/s from material "
                     f"'{sc.material_names[k]}' (for 'cross' its mu_0) makes the step tiny; raise grid.cell_size "
                     f"or lower the viscosity (mu_0)")
        else:
            cause = first_message(self.comm, None if not top else
                                  f"particle speeds grew to {np.linalg.norm(st.p_v[p]):.3g} m/s "
                                  f"({describe_particle(sim, p)}); {self._likely_cause(sim)}")
        raise SimulationError(f"dt fell to {dt:.3g} s, below time.dt_min = {sc.dt_min:g} s, at step "
                              f"{sim.step_count}, t = {sim.time:.6g} s, because {cause}")

    def _likely_cause(self, sim) -> str:
        sc = self.scene
        if sc.dt_fixed is not None:
            c = wave_speed(sc, sim.state, finite_only=True)
            courant = sc.dt_fixed * c / sc.grid.h
            if courant > 1.0:
                return (f"the fixed time.dt = {sc.dt_fixed:g} s is {courant:.2g} times the wave-crossing time "
                        f"of a cell (Courant number above 1); remove time.dt or make it smaller")
        return ("a numerical instability: lower time.cfl (e.g. 0.3), check the material parameters "
                "(stiffness, viscosity) and the boundary set-up")


def check_domain(sim, delete: bool) -> int:
    """Particles more than one cell outside the grid (where their stencil leaves it): delete them and
    return how many, or stop the run naming the first one."""
    sc, comm = sim.scene, sim.domain.comm
    h = sc.grid.h
    lo, hi = sc.grid.origin - h, sc.grid.upper + h
    k = int(round(float(comm.sum([sim.backend.particles_outside(lo, hi)])[0])))
    if not k:
        return 0
    mask = outside_grid(sim.state.p_x, lo, hi)
    mine = int(mask.sum())
    if delete:
        if mine:
            sim.state.remove(mask)
        sim.backend.max_rate = None  # the deleted particles' rate no longer applies
        return k
    p = int(np.argmax(mask))
    raise SimulationError(first_message(comm, None if not mine else
        f"{describe_particle(sim, p)} left the grid at x = {np.array2string(sim.state.p_x[p], precision=4)} "
        f"m ({k} particles outside [{np.array2string(sc.grid.origin, precision=4)}, "
        f"{np.array2string(sc.grid.upper, precision=4)}] m). Enlarge grid.extent, add wall boundaries, or set "
        f"run.on_leave_domain to \"delete\""))
