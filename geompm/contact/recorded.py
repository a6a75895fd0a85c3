"""What every rigid contact surface with a force history shares (obstacles, terrain).

A ``ContactForceStage`` is a grid stage (contact on nodes) and a particle
stage (a penetration guard after G2P) whose rules accumulate, through
contact/force.contact_and_record, the momentum they remove.  This class
packs the shared parameters (contact/force.OBSTACLE), sums the threads'
rows into the force, its normal and tangential parts and the moment,
keeps the peak, writes the series columns and the checkpoint state.

Force on the surface = - sum over its nodes and corrected particles of
m (v_after - v_before) / dt; f_n = sum of the per-item components along each
item's normal (pushing into the surface is positive), f_t = |F - sum (F_i .
n_i) n_i|, the moment about ``moment_point``.  Series columns <name>_fx,
_fy(, _fz), _fn, _ft, _mz (2D) or _mx, _my, _mz (3D), in N (N/m in 2D plane
strain).
"""

from __future__ import annotations

import numpy as np

from geompm.contact.rules import CONDITIONS, ON_SURFACE
from geompm.contract.layout import pack_in_layout
from geompm.contract.stages import OBSTACLE as OBSTACLE_PHASE
from geompm.contract.stages import GridStage, ParticleStage
from geompm.contact.force import COUNT, DEPTH, FACES_GRID, FACES_GUARD, FORCE_SLOTS, OBSTACLE
from geompm.contact.face_pressure import face_pressure_step, spread_matrix
from geompm.contact.impact import ImpactRecord
from geompm.contact.voellmy_params import voellmy_density, voellmy_slots
from geompm.contact.impact_design import design_report, momentum_flux


class ContactForceStage(GridStage, ParticleStage):
    """Subclasses call ``start_recording(scene)`` and ``set_moment_point(default)`` in setup, pack
    their parameters with ``pack_obstacle`` and give the rules and the (prm, aux) of each pass."""

    phase = OBSTACLE_PHASE
    node_reduction = FORCE_SLOTS
    particle_reduction = DEPTH + 1
    particle_maxima = (DEPTH,)  # the deepest penetration is a maximum, not a sum (contract/stages.py)
    kind = "obstacle"  # how the run's summary names it
    records_force = True
    supplies_energy = True  # a prescribed velocity drives material (supplied_speed: 0 at rest)
    #: the surface's prescribed velocity [m/s] (zeros: at rest)
    vel: np.ndarray

    def start_recording(self, scene):
        self.dim = scene.dim
        self.grid = scene.grid
        self.vel = np.zeros(scene.dim)
        self.grid_out = np.zeros(FORCE_SLOTS)  # the grid pass of this step (MUSL's second pass is not counted)
        self.force = np.zeros(scene.dim)
        self.peak = (0.0, 0.0)  # (|F|, time)
        self.fn = self.ft = 0.0  # normal and tangential force magnitudes [N, N/m in 2D]
        self.moment = np.zeros(3)
        self.particles_put_back = 0  # by the guard, over the run
        self.max_depth = 0.0  # deepest penetration the guard corrected [m]
        self.faces = None  # the tessellate.Surface the force is spread on (start_faces), if any
        self.gravity = np.asarray(scene.gravity, float)
        self.voellmy_rho = voellmy_density(self.params, scene, self.json_path)  # the terrain offers it
        self.impact = ImpactRecord(scene.dim, self.params.force_window, scene.end_time)
        named = self.params.probe
        self.probe = next((p for p in scene.probes if p.label == named), None) if named else None
        self.approach = None  # the probe's reading of the largest momentum flux up to a window after first
        # contact: (depth [m], speed [m/s], density [kg/m3], velocity (d,))

    @staticmethod
    def faces_wanted(scene) -> bool:
        """Whether a writer of the scene needs the force per face (Writer.wants_face_forces)."""
        return any(w.wants_face_forces for w in scene.writers)

    def start_faces(self, surface, normals):
        """Spread the force onto the faces of ``surface``: each pass's rows get (faces, d) entries after the
        totals, which the rules fill through contact/force.record_on_face.  ``normals`` (faces, 3): unit,
        out of the solid (the pressure's sign)."""
        d, nf = self.dim, len(surface.cells)
        self.faces = surface
        self.face_area = surface.sizes()  # [m2; m per metre of depth in 2D]
        self.face_normal = np.ascontiguousarray(normals[:, :d])
        self.face_centre = surface.centres()
        self.spread = spread_matrix(self.face_centre, normals, self.face_area, self.grid.h)
        self.node_reduction = FACES_GRID + nf * d
        self.particle_reduction = FACES_GUARD + nf * d
        self._grid_faces = np.zeros(nf * d)
        self.face_force = np.zeros((nf, d))  # on each face, this step [N; N/m in 2D]
        self.face_pressure = np.zeros(nf)  # normal pressure, pushing in positive [Pa]
        self.face_shear = np.zeros(nf)  # magnitude of the tangential traction [Pa]
        self.face_pmax = np.zeros(nf)  # running maximum of the normal pressure [Pa]
        self.face_tmax = np.zeros(nf)  # its time [s]
        self.face_p_at_peak = np.zeros(nf)  # the normal pressure at the step of the peak |F| [Pa]
        self.impact = ImpactRecord(self.dim, self.params.force_window, self.impact.end_time, self.face_area)

    def _faces_step(self, out, time):
        """The faces' forces, pressures and running maximum of a step (particle_reduced)."""
        d, nf = self.dim, len(self.face_area)
        raw = self._grid_faces + out[:, FACES_GUARD:FACES_GUARD + nf * d].sum(axis=0)
        S = self.spread
        face_pressure_step(S.indptr, S.indices, S.data, raw, self.face_normal, self.face_area, time,
                           self.face_force, self.face_pressure, self.face_shear, self.face_pmax, self.face_tmax)

    def hot_spot(self):
        """(largest face pressure over the run [Pa], where its face centre was then [m] (3,), its time [s]),
        or None."""
        if self.faces is None or not self.face_pmax.any():
            return None
        k = int(np.argmax(self.face_pmax))
        t = float(self.face_tmax[k])
        where = self.face_centre[k].copy()
        where[:self.dim] += self.vel * t
        return float(self.face_pmax[k]), where, t

    def set_moment_point(self, default):
        mp = self.params.moment_point
        self.moment_point = np.asarray(default if mp is None else mp, float)

    def pack_obstacle(self, vectors: dict, spacing: float, extra: dict | None = None, layout=OBSTACLE):
        """The packed parameters: ``vectors`` maps lat/shape/shift/vel to (d,) values (3 slots each), the
        moment point is added; ``extra`` holds a longer layout's own entries."""
        d = self.dim
        vec = {}
        for name, value in (*vectors.items(), ("moment", self.moment_point)):
            full = np.zeros(3)
            full[:d] = value
            vec.update({f"{name}_{c}": full[k] for k, c in enumerate("xyz")})
        layer = self.params.contact_layer + ON_SURFACE * self.grid.h
        g = float(np.linalg.norm(self.gravity))
        vec.update(spacing=spacing, layer=layer, condition=CONDITIONS[self.params.condition], mu=self.params.friction,
                   **voellmy_slots(self.params, self.voellmy_rho, g, self.grid.h, d, layer), **(extra or {}))
        return pack_in_layout(layout, vec, f"stage '{self.label}'")

    def grid_reduced(self, out, dt, time, remap):
        if not remap:  # forces are those of the first application in the step; the guard's are added
            self.grid_out[:] = out[:, :FORCE_SLOTS].sum(axis=0)
            if self.faces is not None:
                self._grid_faces[:] = out[:, FACES_GRID:].sum(axis=0)

    def particle_reduced(self, out, dt, time):
        d = self.dim
        self.max_depth = max(self.max_depth, float(out[:, DEPTH].max()))
        self.particles_put_back += int(round(out[:, COUNT].sum()))
        total = self.grid_out + out[:, :FORCE_SLOTS].sum(axis=0)
        self.force = total[:d].copy()
        self.fn = total[d]
        self.ft = float(np.linalg.norm(total[:d] - total[d + 1:2 * d + 1]))
        self.moment = total[2 * d + 1:2 * d + 4].copy()
        mag = float(np.linalg.norm(self.force))
        if mag > self.peak[0]:
            self.peak = (mag, time + dt)
        if self.faces is not None:
            self._faces_step(out, time + dt)
            if self.peak[1] == time + dt:
                self.face_p_at_peak[:] = self.face_pressure
        self.impact.step(self.force, dt, time, None if self.faces is None else self.face_pressure * self.face_area)
        if self.probe is not None:
            self._read_probe(time + dt)

    def _read_probe(self, t):
        """Keep the probe's reading of the largest momentum flux rho v^2 h from the start to one force window
        after first contact: the approach flow of the design formulas (a front a few particles thin carries
        little; the flow backed up from the surface after contact is slow)."""
        first, window = self.impact.first_contact, self.impact.window
        if first is not None and t > first + window:
            return
        if self.approach is None or momentum_flux(self.probe.reading) > momentum_flux(self.approach):
            self.approach = (*self.probe.reading, self.probe.velocity.copy())

    def supplied_speed(self) -> float:
        return float(np.linalg.norm(self.vel))

    def surface_shift(self, time):
        return self.vel * time if self.vel.any() else None

    def peak_force(self):
        return self.peak

    def series(self):
        names = "xyz"[: self.dim]
        out = {f"{self.label}_f{c}": float(self.force[k]) for k, c in enumerate(names)}
        out[f"{self.label}_fn"] = float(self.fn)
        out[f"{self.label}_f_filtered"] = float(np.linalg.norm(self.impact.filtered))
        out[f"{self.label}_ft"] = float(self.ft)
        for k, c in enumerate("xyz"):
            if self.dim == 3 or c == "z":
                out[f"{self.label}_m{c}"] = float(self.moment[k])
        return out

    def summary(self) -> str:
        unit = "N" if self.dim == 3 else "N/m"
        guard = (f"; {self.particles_put_back} particle corrections by the guard (deepest {self.max_depth:.3g} m "
                 f"= {self.max_depth / self.grid.h:.2f} h before correction)" if self.particles_put_back else "")
        spot = self.hot_spot()
        where = "" if spot is None else (f"; peak face pressure {spot[0]:.4g} Pa at ({', '.join(f'{c:.3f}' for c in spot[1][:self.dim])}) m, "
                                         f"t = {spot[2]:.4g} s")
        return (f"{self.kind} '{self.label}': peak force {self.peak[0]:.4g} {unit} at t = {self.peak[1]:.4g} s{where}"
                f"{guard}")

    def impact_report(self) -> dict:
        """status.json's impact and design entries (contact/impact.py, contact/impact_design.py)."""
        return design_report(self)

    def state_dict(self) -> dict:
        faces = {} if self.faces is None else {"face_pmax": self.face_pmax.tolist(), "face_tmax": self.face_tmax.tolist(),
                                               "face_p_at_peak": self.face_p_at_peak.tolist()}
        return {"peak": list(self.peak), "force": self.force.tolist(), "fn": float(self.fn), "ft": float(self.ft),
                "moment": np.asarray(self.moment).tolist(),
                "particles_put_back": self.particles_put_back, "max_depth": self.max_depth,
                "impact": self.impact.state_dict(),
                "approach": None if self.approach is None else [*self.approach[:3], self.approach[3].tolist()],
                **faces}

    def load_state(self, state: dict) -> None:
        self.peak = tuple(state["peak"])
        self.force = np.asarray(state["force"], float)
        self.fn, self.ft = state["fn"], state["ft"]
        self.moment = np.asarray(state["moment"], float)
        self.particles_put_back = int(state.get("particles_put_back", 0))
        self.max_depth = float(state.get("max_depth", 0.0))
        if "impact" in state:
            self.impact.load_state(state["impact"])
        if state.get("approach") is not None:
            a = state["approach"]
            self.approach = (a[0], a[1], a[2], np.asarray(a[3], float))
        if self.faces is not None and "face_pmax" in state:
            self.face_pmax[:] = state["face_pmax"]
            self.face_tmax[:] = state["face_tmax"]
            self.face_p_at_peak[:] = state["face_p_at_peak"]
