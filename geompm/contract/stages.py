"""Base classes of the per-step stages that plugins provide.

- ``GridStage``: acts on grid velocities after the grid update (boundaries,
  obstacles, grid damping) through a per-node function;
- ``ParticleStage``: acts on particles after G2P (particle damping, the
  obstacles' penetration guard) through a per-particle function;
- ``ParticleSource``: adds particles between steps (an inflow hydrograph), on the host.
A stage may be both: a rigid obstacle acts on grid nodes and then on the
particles that still got inside it.  The stage gives the functions, its
packed parameters and a host-side hook for what its pass accumulated (a
force); the backend owns the loops (backend/cpu_stage_loops.py), so the same
functions can run on another machine.

A stage may contribute columns to series.csv through ``series()``, a dict of
column name -> value at the current step.  A stage that carries state from
step to step (an obstacle's peak force) returns it from ``state_dict()`` (plain
JSON values) and takes it back in ``load_state()``, so checkpoints restore it.
Every capability the engine asks about is declared here with its default:
``phase`` (where the stage runs among the others each step), the per-item functions and
their scratch and accumulator sizes, ``needs_split_force``,
``supplied_speed()`` (the health check's energy budget for moving obstacles),
``peak_force()`` (status.json).  The scheduler orders and picks stages by these,
never by plugin name and never by probing attributes.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from geompm.contract.plugin import Plugin

#: stage phases, in the order they run each step (stable within a phase: the case's order).  Node
#: merging (periodic folding) first, then external loads (which damping must see in the nodal force, as
#: it sees gravity), then damping; boundaries and obstacles have the last word on grid velocities; the
#: same order holds for the particle passes.
MERGE, LOAD, DAMPING, BOUNDARY, OBSTACLE = 0, 1, 2, 3, 4


class Stage(Plugin):
    phase: ClassVar[int] = BOUNDARY
    #: the backends whose compilation of this stage's rules has been checked (as Material.backends)
    backends: ClassVar[tuple[str, ...]] = ("cpu",)
    #: capabilities, read by the engine, writers and commands from every stage of a scene (never by name):
    #: it drives material or loads it and may add kinetic energy (``supplied_speed``, ``supplied_work``: the
    #: health check's budget)
    supplies_energy: ClassVar[bool] = False
    #: it records the contact force it exerts (``peak_force``, ``hot_spot``, ``series`` columns
    #: <label>_fx ...; status.json's force entries, `geompm info`, `study --metric peak_force:LABEL`)
    records_force: ClassVar[bool] = False
    #: it is the ground of a DEM (``ground_dem()``): hazard maps are drawn on that raster
    provides_ground: ClassVar[bool] = False
    #: its rules and reductions give the same answers when the particles are shared between MPI ranks
    #: (parallel/slabs.py): every reduction it makes goes through its pass's accumulator rows, which the
    #: ranks stack, or through ``comm``; a stage that sums particles itself on the host without ``comm``
    #: says False and a run on several ranks refuses it
    splits_over_ranks: ClassVar[bool] = True
    #: its ``*_args`` for a step depend on nothing but the step, the time and its set-up (not on the particles,
    #: nor on what its ``*_reduced`` were handed), and asking them for a step that is then not taken changes
    #: nothing: the held step (engine/held_step.py) computes a batch's parameters ahead and may end it early
    holds_step: ClassVar[bool] = False
    #: the run's processes (parallel/comm.py), handed to every stage when the run is made (schemes/base.py's
    #: StepContext): a stage that sums particles outside its pass (a surface load's loaded mass) sums them
    #: over the ranks through it; None before
    comm = None

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

    def supplied_work(self) -> float:
        """Work [J, J/m in 2D] the stage's applied force has done on the material so far (the positive part;
        a surface load), 0 for a stage that applies none."""
        return 0.0

    def peak_force(self) -> tuple[float, float] | None:
        """(largest |F| [N, N/m in 2D], its time [s]) for stages that take a force, else None."""
        return None

    def refines_with_the_grid(self) -> str:
        """A sentence when the stage's physics itself changes with the cell size (a rate tied to h), for a
        study that varies grid.cell_size to warn about; '' otherwise."""
        return ""

    def impact_report(self) -> dict:
        """status.json's impact entries (filtered peak, impulse, design coefficients: contact/impact.py) of a
        stage that records a force, else {}."""
        return {}

    #: the faces its force is spread on (recorded.ContactForceStage.start_faces), None for every other stage
    faces = None

    def hot_spot(self):
        """(largest face pressure [Pa], its face centre [m] (3,), its time [s]) for a stage that spreads its
        force on its faces (recorded.ContactForceStage), else None."""
        return None

    def ground_dem(self):
        """(the DEM file of the ground this stage is [path], its JSON path) for a stage that
        ``provides_ground``, else None."""
        return None

    def surface(self):
        """The stage's rigid surface for output (obstacles/tessellate.Surface, in the case's frame at t = 0),
        or None for a stage without one (damping, periodic)."""
        return None

    def solid_depth(self, pts):
        """Depth [m] of points (n, d) inside the stage's rigid solid at t = 0 (positive inside, negative
        outside), or None for a stage that occupies no space: set-up refuses a body that starts inside
        (setup/assemble.py)."""
        return None

    def water_boundary(self):
        """For a stage that bounds saturated soil as a rigid half-space: (point [m] (d,), unit normal into the
        material (d,), layer [m]: nodes within it are the boundary's, drained: bool); None for every other
        stage. Drained: water flows freely across and the particles at it have p = 0; impermeable: no
        relative flow across it (docs/pore-water.md)."""
        return None

    def water_head(self):
        """For a water boundary (water_boundary) that holds the pore pressure at a head: (times [s], heads [m])
        of the water level's elevation H, linear between times; the saturated particles it drains hold
        p = rho_w |g| (H - z) instead of 0.  None for every other stage."""
        return None

    def drained_layer(self):
        """For a rigid solid that lets pore water through (a drained obstacle: a permeable or slit dam): the
        layer [m] outside its surface within which its contact acts, where the water keeps its velocity
        relative to the held grains and leaves (schemes/saturated/solids.py); None for every other stage
        (an impermeable solid counts as filled for the saturated soil's free surface)."""
        return None

    def node_box(self, time: float):
        """(first, last) global node indices (d,) int64, inclusive, outside which the stage's rule
        changes nothing at ``time``, or None for every node (the backend may skip the nodes outside)."""
        return None

    def periodic_axes(self) -> tuple[int, ...]:
        """The axes along which the stage makes the grid periodic (a slab decomposition cannot cut along
        them, parallel/partition.py); () for every other stage."""
        return ()

    def surface_shift(self, time: float):
        """Displacement [m] of the surface at ``time`` (a prescribed velocity), or None if it does not move."""
        return None

    def state_dict(self) -> dict:
        return {}

    def load_state(self, state: dict) -> None:
        pass


class GridStage(Stage):
    """A stage on grid nodes, after the grid update: one ``@njit`` function per node, run by the backend.

    Either a rule on one node (boundaries, obstacles, grid damping)::

        node_rule(prm, aux, dt, x, m, v, v_old, f, pw, work, out)

    ``prm`` the stage's packed parameters (float64, 1-D, contract/layout.py), ``aux`` its lookup
    table (a signed-distance lattice; any float64 array; read-only once handed to the backend,
    which may keep a copy on a device: to change it, hand a new array), ``x`` (d,) the node's position [m],
    ``m`` its mass [kg], ``v`` (d,) its velocity after the update [m/s], changed in place,
    ``v_old`` and ``f`` (d,) its velocity before the update [m/s] and its force [N] (defined only
    when the stage declares ``needs_split_force``; otherwise aliases of ``v``), ``pw`` (7,) the node's
    pore water (``NODE_PORE``: zeros in a dry scene; read only), ``work``
    (node_scratch,) float64 scratch, ``out`` (node_reduction,) this thread's accumulator.  The
    backend calls it on the nodes with mass (every one, or those in ``node_box``), in parallel: it
    must write only this node and ``out``, allocate nothing and call no Python.  The backend sums
    the threads' ``out`` rows for ``grid_reduced``.

    Or a node merge (periodic folding, ``phase = MERGE``)::

        node_image(prm, axis, i) -> j

    the global index along ``axis`` of the node that global index ``i`` is the same node as (``i``
    itself when it is not a ghost); the backend merges every node with its image (summed mass,
    mass-weighted velocity).  Images must be nodes that are not ghosts themselves.
    """

    #: True when the rule reads ``v_old`` or ``f``: the scheduler then keeps the nodal force apart
    #: from the momentum (mpm/grid.py); otherwise P2G folds dt f into the momentum
    needs_split_force: ClassVar[bool] = False
    node_rule: ClassVar = None
    node_image: ClassVar = None
    node_scratch: ClassVar[int] = 0  # float64 scratch entries per thread
    #: accumulator entries per thread; a stage may set its own in setup (an obstacle's per-face forces),
    #: before the backend plans its passes
    node_reduction: int = 0
    #: the ``out`` slots that hold a maximum over the nodes (``out[k] = max(out[k], ...)``) rather than a
    #: sum: a backend whose threads each hold one node (cuda) combines these with a maximum
    node_maxima: ClassVar[tuple[int, ...]] = ()

    def grid_args(self, dt: float, time: float, remap: bool):
        """(prm, aux) for this pass, or None to skip it.  ``remap`` is True when the scheduler
        re-applies the conditions to the MUSL re-mapped velocities."""
        raise NotImplementedError

    def grid_reduced(self, out, dt: float, time: float, remap: bool) -> None:
        """The pass's accumulator rows (threads, node_reduction), on the host (reused by the next pass).  A backend
        may hand them at the step's end rather than after the pass (the CUDA backend reads a step's reductions
        at once: backend/cuda_tally.py), always in pass order and before anything reads the stage; so a pass's
        arguments must not depend on a reduction of the same step."""


class ParticleStage(Stage):
    """A stage on particles, after G2P: one ``@njit`` function per particle, run by the backend::

        particle_rule(prm, aux, dt, k, x, x0, v, C, m, s, work, out)

    ``k`` the particle's material block, ``x`` and ``x0`` (d,) its position and initial position
    [m], ``v`` (d,) its velocity [m/s], ``C`` (d, d) its affine velocity matrix [1/s], all in
    place; ``m`` its mass [kg]; ``s`` (6,) its stress [Pa] (read); ``prm``, ``aux``, ``work``,
    ``out`` as for ``GridStage.node_rule``.  The backend runs it over the blocks of
    ``particle_blocks()`` in parallel and hands the summed rows to ``particle_reduced``.
    """

    particle_rule: ClassVar = None
    particle_scratch: ClassVar[int] = 0
    particle_reduction: int = 0  # as node_reduction
    particle_maxima: ClassVar[tuple[int, ...]] = ()  # as node_maxima

    def particle_args(self, dt: float, time: float):
        """(prm, aux) for this pass, or None to skip it."""
        raise NotImplementedError

    def particle_blocks(self, nblocks: int):
        """The material blocks the rule acts on (default: all)."""
        return range(nblocks)

    def particle_reach(self, prm, lo, hi):
        """What this pass, with parameters ``prm`` (``particle_args``' first item), can do when every
        particle lies in the box [lo, hi] ((d,) arrays [m], the moved particles' bounds that the
        backend's G2P finds): None when the rule would change no particle in the box and add nothing to
        the reduction (the backend may then skip the pass and hand ``particle_reduced`` zero rows), else
        (lo, hi) of a box holding every particle after the pass.  The default: the pass runs, and
        afterwards the particles may be anywhere (an unbounded box)."""
        return np.full(len(lo), -np.inf), np.full(len(hi), np.inf)

    def particle_reduced(self, out, dt: float, time: float) -> None:
        """The pass's accumulator rows (threads, particle_reduction), on the host (reused by the next pass); handed
        when ``grid_reduced`` says."""


class ParticleSource(Stage):
    """A stage that adds particles between steps (an inflow hydrograph), on the host, before the particles go
    to their ranks: ``supply(time)`` gives the particles due by ``time`` as a packet of parallel/migrate.py
    (arrays by name, each material's state variables, counts per material block), or None.  It runs on every
    rank with the same arguments and gives the same count everywhere; the engine merges the root rank's
    packet only (the next migration sends each particle to its rank)."""

    def supply(self, state, time: float):
        """The packet of the particles due by ``time`` [s] in the dtypes of ``state``, or None.  Read only the
        state's array names, dtypes, shapes and blocks: on a device backend its values are not current."""
        return None

    def pending(self, time: float) -> bool:
        """Whether particles are still to come after ``time`` (a run whose particles have all left does not end
        while they are)."""
        return False

    def particles_total(self) -> int:
        """How many particles the source adds over the whole run (the memory check before any work)."""
        return 0

    def describe(self) -> str:
        """What `geompm validate` prints about the source (its volume, particles, depth and speed), or ''."""
        return ""

    def entering(self) -> tuple[int, float] | None:
        """(material id, largest speed [m/s]) of the particles the source adds: the first step's estimate counts
        them (backend/timestep.stable_dt); None for a source that adds none."""
        return None

    def particle_mass(self) -> float:
        """The mass [kg] of one added particle (the grid's smallest mass of note in a scene that starts empty)."""
        return 0.0


#: the ``aux`` of a stage that has no lookup table
NO_AUX = np.zeros(1)
#: a node's pore water as a node rule sees it (``pw``): its pore pressure p_b and total stress (Voigt,
#: kernels/voigt.py; tension positive) [Pa], the particles' volume-weighted averages around the node, that
#: a scheme with pore water leaves on the grid (mpm/grid.GridView.g_pore); contact rules bound friction
#: by the effective normal force with it (contact/rules.effective_mu)
NODE_PORE = ("p", "s_xx", "s_yy", "s_zz", "s_xy", "s_yz", "s_xz")
#: the one row every node of a dry scene shares: zeros, friction on the total stress
DRY_NODE = np.zeros((1, len(NODE_PORE)))
#: a node index beyond any grid (an open side of a ``node_box``)
FAR_NODE = 1 << 40
