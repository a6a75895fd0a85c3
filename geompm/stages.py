"""Base classes of the per-step stages that plugins provide.

- ``GridStage``: acts on grid velocities after the grid update (boundaries,
  obstacles, grid damping).  A stage that reads the nodal force or the
  pre-update velocity says so with ``needs_split_force = True``.  ``apply_grid(view, dt, time, remap)``: ``remap``
  is True when the scheduler re-applies conditions to the MUSL re-mapped
  velocities (a stage that records forces should count only the first call).
- ``ParticleStage``: acts on particles after G2P (particle damping, the
  obstacles' penetration guard).  A stage may be both: a rigid obstacle acts
  on grid nodes and then on the particles that still got inside it.

A stage may contribute columns to series.csv through ``series()``, a dict of
column name -> value at the current step.  A stage that carries state from
step to step (an obstacle's peak force) returns it from ``state_dict()`` (plain
JSON values) and takes it back in ``load_state()``, so checkpoints restore it.
Every capability the engine asks about is declared here with its default:
``phase`` (where the stage runs among the others each step), ``needs_split_force``,
``supplied_speed()`` (the health check's energy budget for moving obstacles),
``peak_force()`` (status.json).  The scheduler orders and picks stages by these,
never by plugin name and never by probing attributes.
"""

from __future__ import annotations

from typing import ClassVar

from .plugin import Plugin

#: stage phases, in the order they run each step (stable within a phase: the case's order).  Node
#: merging (periodic folding) first, then damping; boundaries and obstacles have the last word on
#: grid velocities; the same order holds for the particle passes.
MERGE, DAMPING, BOUNDARY, OBSTACLE = 0, 1, 2, 3


class Stage(Plugin):
    phase: ClassVar[int] = BOUNDARY

    def __init__(self, params, label: str, json_path: str = ""):
        self.params = params
        self.label = label
        self.json_path = json_path  # where the stage sits in the case, for error messages

    def setup(self, scene) -> None:
        """Runs once after the scene is assembled (select nodes, build fields)."""

    def series(self) -> dict[str, float]:
        return {}

    def summary(self) -> str:
        """A line for the end of a run (e.g. an obstacle's peak force), or ''."""
        return ""

    def warnings(self) -> list[str]:
        """What `geompm validate` and `geompm run` should warn about after set-up (e.g. an obstacle thinner
        than the grid resolves), each a full sentence."""
        return []

    def supplied_speed(self) -> float:
        """Largest speed [m/s] at which the stage drives material (a moving obstacle); 0 if it drives none."""
        return 0.0

    def peak_force(self) -> tuple[float, float] | None:
        """(largest |F| [N, N/m in 2D], its time [s]) for stages that take a force, else None."""
        return None

    def state_dict(self) -> dict:
        return {}

    def load_state(self, state: dict) -> None:
        pass


class GridStage(Stage):
    #: True when the stage reads ``view.g_force`` or ``view.g_vel_old``: the scheduler then
    #: keeps the nodal force apart from the momentum (engine/grid.py); otherwise P2G folds
    #: dt f into the momentum and those two arrays are None.
    needs_split_force: bool = False

    def apply_grid(self, view, dt: float, time: float, remap: bool) -> None:
        raise NotImplementedError


class ParticleStage(Stage):
    def apply_particles(self, state, dt: float, time: float) -> None:
        raise NotImplementedError
