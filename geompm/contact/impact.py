"""The impact quantities of a contact force history that a barrier's design reads: the force averaged over a
window of stated length, its peak, the impulse, the load left at the end, the pressures over the faces at
the filtered peak.

The instantaneous force of an explicit contact on a rigid surface carries, at first contact, the
acoustic (water-hammer) pressure p = rho c v of the flowing material's elastic stiffness, for the time a
wave crosses the flow (2 h_f / c), and step-to-step noise from single particles arriving; neither is the
surge's load (docs/impact-forces.md measures both).  Design practice reads a peak over a window of
physical time (Hubl et al. 2009; Kwan 2012, GEO Report 270): here the moving average

    F_w(t) = (J(t) - J(t - T_w)) / T_w,      J(t) = int_{t_c}^{t} F dt

with J the vector impulse since first contact t_c (J = 0 before it).  T_w is ``force_window`` [s] or, by
default, WINDOW_SHARE of the flow's travel time to the surface, t_c (0.01 of the run's end time when the
material starts in contact).  J is exact (a sum of F dt over every step); J(t - T_w) is interpolated
linearly between snapshots kept every T_w / SNAPSHOTS, so the window's length is exact and its start is
interpolated within T_w / SNAPSHOTS.

Reported: the filtered peak max |F_w| and the end of its window [s]; the impulse int |F| dt [N s; N s/m in
2D] from first contact to the current time and the vector impulse J (the momentum the surface took); the filtered force at the end (the deposit's static load);
with faces (the surfaces writer), the normal pressure on each face averaged over the filtered peak's window.
"""

from __future__ import annotations

import numpy as np

#: the default window as a share of the time from the start to first contact
WINDOW_SHARE = 0.1
#: the default window as a share of the run's end time, when contact starts at t = 0
WINDOW_SHARE_OF_END = 0.01
#: snapshots of the cumulative impulse per window
SNAPSHOTS = 20


class ImpactRecord:
    """The filtered force, its peak, the impulse of one contact surface, fed once per step with ``step``."""

    def __init__(self, dim: int, window: float | None, end_time: float, face_area=None):
        self.dim = dim
        self.window_set = window  # [s] or None (the default rule)
        self.end_time = end_time
        self.face_area = face_area  # (faces,) [m2; m in 2D], or None without faces
        self.window = window
        self.first_contact = None  # [s] the start of the first step with a force
        self.J = np.zeros(dim)  # vector impulse since first contact [N s]
        self.impulse = 0.0  # int |F| dt [N s]
        self.Jf = None if face_area is None else np.zeros(len(face_area))  # normal impulse per face [N s]
        self.snaps: list = []  # (time, J, Jf) every window / SNAPSHOTS
        self.filtered = np.zeros(dim)  # F_w at the current time [N]
        self.peak = (0.0, 0.0)  # (max |F_w|, end of its window [s])
        self.face_pressure_at_peak = None  # (faces,) [Pa], the window-mean normal pressure at the peak

    def _start(self, time: float) -> None:
        self.first_contact = time
        if self.window_set is None:
            self.window = WINDOW_SHARE * time if time > 0.0 else WINDOW_SHARE_OF_END * self.end_time
        self.snaps = [(time, self.J.copy(), None if self.Jf is None else self.Jf.copy())]

    def step(self, force, dt: float, time: float, face_force=None) -> None:
        """Add the step [time, time + dt] with the force ``force`` (d,) [N] and, with faces, the normal force on
        each face (faces,) [N]."""
        if self.first_contact is None:
            if not np.any(force):
                return
            self._start(time)
        t = time + dt
        self.J += force * dt
        self.impulse += float(np.linalg.norm(force)) * dt
        if self.Jf is not None and face_force is not None:
            self.Jf += face_force * dt
        if t - self.snaps[-1][0] >= self.window / SNAPSHOTS:
            self.snaps.append((t, self.J.copy(), None if self.Jf is None else self.Jf.copy()))
            while len(self.snaps) > 2 and self.snaps[1][0] <= t - self.window:
                self.snaps.pop(0)
        J0, Jf0 = self._at(t - self.window)
        self.filtered = (self.J - J0) / self.window
        mag = float(np.linalg.norm(self.filtered))
        if mag > self.peak[0]:
            self.peak = (mag, t)
            if self.Jf is not None and Jf0 is not None:
                self.face_pressure_at_peak = (self.Jf - Jf0) / (self.window * self.face_area)

    def _at(self, t: float):
        """(J, Jf) at time t, linear between the snapshots (the first, at first contact, holds zeros)."""
        snaps = self.snaps
        if t <= snaps[0][0]:
            return snaps[0][1], snaps[0][2]
        for (ta, Ja, Fa), (tb, Jb, Fb) in zip(snaps, snaps[1:]):
            if t <= tb:
                s = (t - ta) / (tb - ta)
                return Ja + s * (Jb - Ja), None if Fa is None else Fa + s * (Fb - Fa)
        return snaps[-1][1], snaps[-1][2]  # within the last interval: at most T_w / SNAPSHOTS short

    def report(self) -> dict:
        """status.json's impact entries (empty before first contact)."""
        if self.first_contact is None:
            return {}
        return {"force_window": self.window, "first_contact": self.first_contact,
                "filtered_peak_force": self.peak[0], "filtered_peak_time": self.peak[1],
                "impulse": self.impulse, "impulse_vector": self.J.tolist(),
                "final_force": float(np.linalg.norm(self.filtered))}

    def state_dict(self) -> dict:
        faces = None if self.Jf is None else self.Jf.tolist()
        return {"window": self.window, "first_contact": self.first_contact, "J": self.J.tolist(),
                "impulse": self.impulse, "Jf": faces, "filtered": self.filtered.tolist(), "peak": list(self.peak),
                "snaps": [(t, J.tolist(), None if F is None else F.tolist()) for t, J, F in self.snaps],
                "face_pressure_at_peak": (None if self.face_pressure_at_peak is None
                                          else self.face_pressure_at_peak.tolist())}

    def load_state(self, state: dict) -> None:
        self.window = state["window"]
        self.first_contact = state["first_contact"]
        self.J = np.asarray(state["J"], float)
        self.impulse = float(state["impulse"])
        if self.Jf is not None and state.get("Jf") is not None:
            self.Jf = np.asarray(state["Jf"], float)
        self.filtered = np.asarray(state["filtered"], float)
        self.peak = tuple(state["peak"])
        self.snaps = [(t, np.asarray(J, float), None if F is None else np.asarray(F, float))
                      for t, J, F in state["snaps"]]
        if state.get("face_pressure_at_peak") is not None:
            self.face_pressure_at_peak = np.asarray(state["face_pressure_at_peak"], float)
