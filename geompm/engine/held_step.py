"""The held step (``solver.held_step``): up to N steps at a fraction of the stable step, each checked before it
is taken, the host reading a device backend once per batch instead of once per step.

At a batch's start the host has read the step-end reductions (kernels/step_end.py) and takes the stable step
dt_s (backend/timestep.py); the batch holds

    dt_h = f dt_s                                           (f = held_step.fraction, 0 < f <= 1)

for up to N steps (shortened as ever to land on output times).  dt_h stays within the stable step while

    c(rho) + |v|_max <= cfl h / dt_h,     |L_ii|_max <= STRAIN_INCREMENT / dt_h,

the viscous limit and dt_max being constants.  The host turns this into a box the check can test without the
laws: each material block's densities within [rho_min / (1 + delta), rho_max (1 + delta)], delta the largest of
DENSITY_STEPS whose wave speeds (the law's, at the box's two ends: the speed is monotone in the density, as
the time step itself assumes) use at most half the room cfl h / dt_h - (c + |v|) left at the start, the
speed |v| below cfl h / dt_h less that wave speed, the rate below STRAIN_INCREMENT / dt_h; and the particles
within ``margin_cells`` cells of the cells they held at the start (the batch's grid window reaches that far;
a particle that leaves it, or the grid, ends the batch).  Inside the box the stable step is at least dt_h.

Before each step after the first, ``fits`` (kernels/held_box.py) tests the previous step's end rows against
the box (with no non-finite particle).  A step that fails it is not taken: the batch ends there, and the host
starts the next one from that state with a new stable step.  No step exceeds the stable step of the state it
starts from.  On a device the test runs in a one-thread kernel and every later kernel of the batch returns at
once once it has failed (backend/cuda.py); on the CPU the host tests it, so both take the same steps.

What a batch cannot do, the host needs each step: particles added by a source, migrated between MPI ranks, a
scheme's own reductions of the step (saturated soil's wave speeds), a stage whose parameters are computed
from the particles or from its reductions (``Stage.holds_step``), a water table's or strength trigger's state;
such scenes are refused with the held step before any work (schema/held_step.py; several ranks:
parallel/slabs.py).
"""

from __future__ import annotations

import numpy as np

from geompm.kernels.held_box import BLOCKS, DIM, RATE_ALLOW, RHO, V_ALLOW, X_HI, X_LO, fits  # noqa: F401
from geompm.kernels.step_end import END_ROW, RHO_MAX, RHO_MIN, SPEED

#: the density allowances tried, largest first (the box: module docstring)
DENSITY_STEPS = (0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 0.0)


def _law_speed(scene, rows, k: int, delta: float) -> float:
    r = k * END_ROW
    rho_lo, rho_hi = -rows[r + RHO_MIN], rows[r + RHO_MAX]
    if not rho_hi >= rho_lo:  # an empty block
        return 0.0
    mat = scene.materials[k]
    wave = type(mat).particle_wave_speed
    return max(wave(mat.prm, rho_lo / (1.0 + delta)), wave(mat.prm, rho_hi * (1.0 + delta)))


def limits(scene, rows, dt_hold: float, cells) -> np.ndarray:
    """The box (module docstring) within which a step ``dt_hold`` [s] is stable, from the step-end ``rows`` at
    the batch's start and the lowest and highest ``cells`` (2, d) its particles may reach (``widened``)."""
    from geompm.backend.timestep import STRAIN_INCREMENT

    d, nb, spec = scene.dim, len(scene.materials), scene.grid
    box = np.empty(RHO + 2 * nb)
    box[DIM], box[BLOCKS] = d, nb
    box[X_LO:X_HI], box[X_HI:RHO] = -np.inf, np.inf
    first, last = cells
    box[X_LO:X_LO + d] = spec.origin + first * spec.h + 1e-9 * spec.h
    box[X_HI:X_HI + d] = spec.origin + (last + 1) * spec.h - 1e-9 * spec.h
    if scene.dt_fixed is not None:  # a fixed step: only the particles' place and finiteness are checked
        box[V_ALLOW] = box[RATE_ALLOW] = np.inf
        box[RHO:RHO + nb], box[RHO + nb:] = -np.inf, np.inf
        return box
    room = scene.cfl * spec.h / dt_hold * (1.0 - 1e-12)
    speed = max((rows[k * END_ROW + SPEED] for k in range(nb)), default=0.0)
    c0 = max((_law_speed(scene, rows, k, 0.0) for k in range(nb)), default=0.0)
    delta = 0.0
    for delta in DENSITY_STEPS:
        if max((_law_speed(scene, rows, k, delta) for k in range(nb)), default=0.0) <= c0 + 0.5 * (room - c0 - speed):
            break
    c = max((_law_speed(scene, rows, k, delta) for k in range(nb)), default=0.0)
    box[V_ALLOW] = room - c
    box[RATE_ALLOW] = STRAIN_INCREMENT / dt_hold * (1.0 - 1e-12)
    for k in range(nb):
        r = k * END_ROW
        box[RHO + k], box[RHO + nb + k] = -rows[r + RHO_MIN] / (1.0 + delta), rows[r + RHO_MAX] * (1.0 + delta)
    return box


def widened(cells, margin: int, spec):
    """The particles' cells (2, d) widened by ``margin`` cells, within the grid's (the batch's window)."""
    return np.stack([np.maximum(np.asarray(cells[0]) - margin, -1),
                     np.minimum(np.asarray(cells[1]) + margin, spec.ncells)]).astype(np.int64)
