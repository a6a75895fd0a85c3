"""Pydantic v2 models of a geompm case (the JSON file).

Only the core's keys are modelled here.  Plugin parameters (a material's
``youngs_modulus``, a wall's ``friction``, ...) are kept as extra keys on
``MaterialSpec`` / ``PluginSpec`` and validated in a second pass against the
plugin's own ``Params`` model (see ``geompm.schema.load``).

Units are SI: metres, seconds, kilograms, pascals; angles in degrees.
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

import numpy as np

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from geompm.contract.schedule import check_schedule

Vector = list[float]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class GridSpec(Strict):
    origin: Vector = Field(description="Lower corner of the background grid [m], one entry per dimension")
    extent: Vector = Field(description="Size of the grid along each axis [m]; must be positive")
    cell_size: float = Field(gt=0, description="Edge length h of the square/cubic grid cells [m]")
    shape_function: Literal["linear", "quadratic", "cubic"] = Field(
        "quadratic", description="Grid basis: linear hat, quadratic or cubic B-spline"
    )


CFL_LIMIT = 0.8  # an elastic block gains energy from cfl = 0.9 on (docs/numerical-envelope.md)


class TimeSpec(Strict):
    end: float = Field(gt=0, description="Simulated end time [s]")
    cfl: float = Field(0.4, gt=0, description=f"Courant number: dt = cfl * h / max(c_p + |v_p|), at most {CFL_LIMIT}")
    dt_max: float | None = Field(None, gt=0, description="Upper bound on the time step [s]")
    dt: float | None = Field(
        None, gt=0, description="Fixed time step [s]; overrides the adaptive CFL step (use with care)"
    )
    dt_min: float = Field(
        1e-9, gt=0, description="The run stops (exit 3) if the stable time step falls below this [s]"
    )

    @field_validator("cfl")
    @classmethod
    def _cfl_limit(cls, v):
        if v > CFL_LIMIT:
            raise ValueError(f"{v:g} is above the stable limit {CFL_LIMIT}: an elastic body gains energy from 0.9 "
                             f"on (docs/numerical-envelope.md); use 0.4 (the default) or at most {CFL_LIMIT}")
        return v


class RunSpec(Strict):
    """How a run is kept safe: checkpoints and what happens to particles that leave the grid."""

    checkpoint_interval: float | None = Field(
        None, gt=0, description="Simulated time between two checkpoints [s]; none if omitted")
    checkpoint_wall_minutes: float | None = Field(
        10.0, gt=0, description="Wall-clock minutes between two checkpoints; null: none on a timer")
    keep_checkpoints: int = Field(2, ge=1, description="How many of the newest checkpoints to keep")
    on_leave_domain: Literal["error", "delete"] = Field(
        "error", description="A particle leaving the grid stops the run (exit 3) or is deleted (warned once)")


class PressureSolverSpec(Strict):
    """The semi-implicit two-phase step's pressure solve (solver.update 'saturated_semi_implicit';
    docs/pore-water.md, The semi-implicit step): conjugate gradients with pyamg's smoothed aggregation."""

    tolerance: float = Field(1e-8, gt=0, lt=1, description="Relative residual |b - A x| / |b| the solve reaches "
                             "each step [-], in (0, 1)")
    max_iterations: int = Field(500, ge=1, le=100000, description="Conjugate-gradient iterations a solve may take "
                                "before the run stops (exit 3, naming the step and the residual)")
    rebuild_interval: int = Field(20, ge=1, le=100000, description="Steps one multigrid hierarchy serves as the "
                                  "preconditioner at most (rebuilt sooner when the unknown nodes change or the "
                                  "iterations double)")


class HeldStepSpec(Strict):
    steps: int = Field(..., ge=2, le=10_000, description="Most steps in one batch [-] (the host reads a device "
                       "backend once per batch; output times, checkpoints and spatial sorts end a batch too)")
    fraction: float = Field(0.95, gt=0.0, le=1.0, description="The held step as a fraction of the stable step at "
                            "the batch's start [-]: below 1, the room the state has to change before a step would "
                            "exceed the stable one (a step that would ends the batch, it is not taken)")
    margin_cells: int = Field(2, ge=1, le=64, description="How far the particles may move in a batch [cells]: the "
                              "batch's grid window reaches this far beyond their cells at its start")


class SolverSpec(Strict):
    transfer: Literal["apic", "pic", "flip", "mls"] = Field(
        "apic", description="Particle-grid velocity transfer: APIC (affine), PIC, FLIP/PIC blend, or MLS "
        "(APIC with the MLS-MPM force and velocity gradient L = C of Hu et al. 2018: fewer flops per step; "
        "quadratic or cubic shape functions)"
    )
    flip_ratio: float = Field(
        0.99, ge=0.0, le=1.0, description="FLIP fraction of the velocity update per step (transfer 'flip' "
        "only) [-]; the PIC share 1 - ratio dissipates per step, so more steps dissipate more"
    )
    viscoplastic_time: float | None = Field(
        None, gt=0, description="Relaxation time tau [s] of a Duvaut-Lions viscoplastic regularisation of every "
        "law with an elastic predictor (the Mohr-Coulomb and Drucker-Prager families, the critical-state sand): "
        "the stress reaches the yield surface over tau instead of at once, sigma = (sigma_trial + (dt/tau) "
        "sigma_return) / (1 + dt/tau), so a perfectly plastic non-associated soil cannot localise into bands one "
        "cell wide (docs/slope-stability.md, The cause); short against the loading, e.g. 0.0025 s for a "
        "strength-reduction trial of 2 s (geompm stability sets T/800 unless the case gives one); default off"
    )
    flip_relaxation_time: float | None = Field(
        None, gt=0, description="Transfer 'flip': relax the particle velocity towards the grid's (PIC) with "
        "this time constant tau [s] instead of a fixed ratio per step: ratio = exp(-dt / tau), a dissipation "
        "per second that does not grow when the step shrinks (docs/validation/column-collapse.md); "
        "e.g. 0.1 sqrt(H0 / g) for a granular collapse"
    )
    update: str | None = Field(
        None, description="The time step's scheme, a 'geompm.schemes' entry point: 'usl' (update stress last), "
        "'musl' (modified USL), 'saturated' (two-phase soil, explicit, docs/pore-water.md), 'saturated_musl' or "
        "'saturated_semi_implicit' (two-phase soil with the pore pressure implicit: the skeleton's step, water's "
        "real or infinite bulk modulus); left out, 'usl' for dry materials and 'saturated' where a material has "
        "'pore_water'")
    backend: Literal["cpu", "cuda"] = Field(
        "cpu", description="Where the step's kernels run: 'cpu' (numba, all cores) or 'cuda' (an NVIDIA GPU "
        "through numba-cuda: pip install 'geompm[cuda]'; NUMBA_ENABLE_CUDASIM=1 runs it on numba-cuda's "
        "simulator, slowly, for tests; docs/performance.md)")
    p2g: Literal["atomic", "tiled"] = Field(
        "atomic", description="Backend 'cuda' only: how P2G adds into the grid: 'atomic' (a global atomic per "
        "particle and node) or 'tiled' (each thread block first adds its particles into a shared-memory tile, "
        "then one atomic per node; pays where many particles of a block share nodes, i.e. once sorted by "
        "cell). Results differ at round-off only; which is faster depends on the GPU (geompm bench --set "
        "solver.p2g=tiled; docs/performance.md)")
    particle_pass: Literal["joined", "separate"] = Field(
        "joined", description="Backend 'cuda' only: how a dry scheme's G2P, particle stages and stress update "
        "run: 'joined' (one kernel per material block takes each particle through all three and its step-end "
        "reduction: fewer launches, more registers a thread) or 'separate' (a kernel each). Results differ at "
        "round-off only; which is faster depends on the GPU and the scene (geompm bench --set "
        "solver.particle_pass=separate; docs/performance.md)")
    precision: Literal["float64", "float32"] = Field(
        "float64", description="Floating-point width of the particle and grid arrays: 'float64', or "
        "'float32' (half the bytes per particle, for the GPU's bandwidth; the kernels still compute in "
        "float64 registers, the stored state is rounded to float32 each step: the errors this costs are "
        "measured in docs/performance.md). float32 positions need coordinates near the grid: refused when "
        "float32 spacing at the grid's far corner exceeds 1e-3 of a cell")
    sort_interval: int = Field(
        100, ge=0, description="Re-order the particles of each material by grid cell every this many steps "
        "(cache locality of the particle-grid transfers once a flow has mixed them; docs/performance.md); "
        "0: never. Results change only at round-off (the order of the P2G sums)")
    rebalance_interval: int = Field(
        100, ge=0, description="On several MPI ranks (docs/parallel.md): move the cuts between the ranks' slabs "
        "so that each holds about as many particles, every this many steps; 0: keep the first cuts. Results "
        "change only at round-off")

    held_step: HeldStepSpec | None = Field(
        None, description="Hold the time step for a few steps (docs/performance.md, engine/held_step.py): up to "
        "'steps' steps at 'fraction' of the stable step, each checked before it is taken, so that backend 'cuda' "
        "reads the device once per batch instead of once per step; the CPU takes the same steps. Needs one "
        "process, a dry scheme, no inflow, water table or strength trigger, and stages whose parameters follow "
        "the time alone (refused otherwise, with the reason). Default: off, every step the stable one")

    pore_pressure_smoothing: bool = Field(
        True, description="Saturated soil only: the pore pressure acts on the grid, and is reported, as the "
        "particles' own pressures seen through the grid (one cell's smoothing), and each step's increment passes "
        "through the same smoothing: impacts cannot pump up patterns of particle pressure that the grid cannot "
        "see, and the pressure exchanges no spurious energy with the flow (docs/pore-water.md); false: the "
        "particles' own pressures and increments")

    pressure_solver: PressureSolverSpec = Field(
        default_factory=PressureSolverSpec, description="Scheme 'saturated_semi_implicit' only: the pressure "
        "solve's tolerance and limits")

    @field_validator("flip_relaxation_time")
    @classmethod
    def _relaxation_needs_flip(cls, v, info):
        if v is not None and info.data.get("transfer") != "flip":
            raise ValueError(f"applies to transfer 'flip' only (transfer is '{info.data.get('transfer')}'); "
                             "set solver.transfer to \"flip\" or remove it (--set solver.flip_relaxation_time=null)")
        return v


class PoreFluidSpec(Strict):
    """The water filling a saturated soil's pores (docs/pore-water.md)."""

    density: float = Field(1000.0, gt=0, description="Water density rho_w [kg/m3]")
    bulk_modulus: float | str = Field(
        2.2e9, description="Water bulk modulus K_w [Pa] (2.2e9 for water; a smaller value shortens an explicit "
        "run: `geompm validate` reports its effect on c_v), or \"incompressible\" (solver.update "
        "'saturated_semi_implicit' only)")

    @field_validator("bulk_modulus", mode="before")
    @classmethod
    def _modulus_or_incompressible(cls, v):
        if v == "incompressible":
            return v
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0:
            raise ValueError(f"must be a bulk modulus > 0 Pa (2.2e9 for water) or \"incompressible\", got {v!r}")
        return float(v)
    viscosity: float = Field(1.0e-3, gt=0, description="Dynamic viscosity mu_w [Pa s] (1e-3 for water at 20 C)")


class PoreWaterSpec(Strict):
    """A soil saturated with water: two phases on each particle, the law updating the effective stress
    (docs/pore-water.md)."""

    porosity: float = Field(gt=0, lt=1, description="Initial porosity n0 [-], in (0, 1)")
    hydraulic_conductivity: float | None = Field(
        None, gt=0, description="Darcy's hydraulic conductivity k [m/s] of the water in the soil at n0 "
        "(give this or intrinsic_permeability)")
    intrinsic_permeability: float | None = Field(
        None, gt=0, description="Intrinsic permeability kappa [m2] at n0 (k = kappa rho_w g / mu_w; give this or "
        "hydraulic_conductivity)")
    permeability_update: Literal["constant", "kozeny_carman"] = Field(
        "constant", description="'kozeny_carman': kappa(n) = kappa0 n^3 (1 - n0)^2 / (n0^3 (1 - n)^2) as the "
        "skeleton's porosity changes; 'constant': kappa0 throughout")
    max_porosity: float = Field(
        0.9, gt=0, lt=1, description="Where the skeleton opens beyond this porosity [-] its grains have "
        "separated: no pore pressure (drained) and no drag there (docs/pore-water.md)")
    cavitation_pressure: float = Field(
        -100e3, le=0, description="The lowest pore pressure the water sustains [Pa, gauge, compression "
        "positive]: below it the water cavitates and the pore pressure is held there (default -100 kPa, about "
        "water's vapour pressure below one atmosphere; docs/pore-water.md, Suction)")
    fluid: PoreFluidSpec = Field(default_factory=PoreFluidSpec, description="The pore water")
    drainage: Literal["coupled", "drained"] = Field(
        "coupled", description="'coupled': the pore pressure follows the water's mass balance (two-phase); "
        "'drained': it is held at its initial, steady state whatever the skeleton does (the water flows freely: "
        "a long-term analysis; `geompm stability` runs its trials so, docs/pore-water.md)")


class MaterialSpec(BaseModel):
    """``{"model": <plugin name>, ...the plugin's parameters}``."""

    model_config = ConfigDict(extra="allow", allow_inf_nan=False)
    model: str = Field(description="Name of a plugin in the geompm.materials entry-point group")
    pore_water: PoreWaterSpec | None = Field(
        None, description="Saturate the material with water (two-phase MPM, docs/pore-water.md): 'density' "
        "is then the solid grains' density rho_s, the law updates the effective stress")


class PluginSpec(BaseModel):
    """A boundary/obstacle: ``{"type": <plugin name>, ...its parameters}``."""

    model_config = ConfigDict(extra="allow", allow_inf_nan=False)
    type: str = Field(description="Name of a plugin in the group of this list")
    name: str | None = Field(None, description="Optional label used in series.csv columns")


class DampingSpec(BaseModel):
    model_config = ConfigDict(extra="allow", allow_inf_nan=False)
    model: str = Field(description="Name of a plugin in the geompm.damping entry-point group")


class OutputSpec(BaseModel):
    model_config = ConfigDict(extra="allow", allow_inf_nan=False)
    writer: str = Field(description="Name of a plugin in the geompm.writers entry-point group")
    interval: float = Field(
        0.0, ge=0.0, description="Simulated time between two outputs [s]; 0 writes every step"
    )


class BoxGeometry(Strict):
    type: Literal["box"]
    min: Vector = Field(description="Lower corner [m]")
    max: Vector = Field(description="Upper corner [m]")


class PolygonGeometry(Strict):
    type: Literal["polygon"]
    vertices: list[Vector] = Field(min_length=3, description="Closed polygon in the x-y plane [m], 2D only")
    extrude: list[float] | None = Field(
        None, min_length=2, max_length=2, description="[z_min, z_max] to extrude the polygon in a 3D case [m]"
    )


class StlGeometry(Strict):
    type: Literal["stl"]
    file: str = Field(description="Watertight surface mesh (STL/OBJ/PLY), relative to the case file; 3D only")
    scale: float = Field(1.0, gt=0, description="Factor applied to the mesh coordinates (e.g. 0.001 for mm)")
    translate: Vector = Field(default_factory=lambda: [0.0, 0.0, 0.0], description="Offset after scaling [m]")


class ReleasePolygonGeometry(Strict):
    """A mapped release area: the ground's DEM surface filled upward by a vertical thickness (3D)."""

    type: Literal["release_polygon"]
    file: str = Field(description="GeoJSON of the release area (Polygon / MultiPolygon features, map "
                                  "coordinates of the case), relative to the case file")
    dem: str = Field(description="The ground's DEM (GeoTIFF / ESRI ASCII), relative to the case file")
    thickness: float | None = Field(None, gt=0, description="Uniform release thickness [m], measured vertically")
    thickness_attribute: str | None = Field(
        None, description="Name of a per-feature property holding the thickness [m] (instead of 'thickness')")


class ReleaseRasterGeometry(Strict):
    """A release thickness raster: the ground's DEM surface filled upward by the raster's value (3D)."""

    type: Literal["release_raster"]
    file: str = Field(description="Raster of release thickness [m], measured vertically; NoData or <= 0 = none")
    dem: str = Field(description="The ground's DEM (GeoTIFF / ESRI ASCII), relative to the case file")


class BetweenSurfacesGeometry(Strict):
    """The mass between a failure surface and the pre-event ground, two DEMs (3D)."""

    type: Literal["between_surfaces"]
    surface: str = Field(description="Pre-event ground DEM (the top of the mass)")
    failure_surface: str = Field(description="Failure-surface DEM (the bottom of the mass; use it as the terrain)")


Geometry = Annotated[Union[BoxGeometry, PolygonGeometry, StlGeometry, ReleasePolygonGeometry, ReleaseRasterGeometry,
                           BetweenSurfacesGeometry], Field(discriminator="type")]


class VelocityProfile(Strict):
    """Spatial profile multiplying a body's velocity vector.

    ``uniform``: v(x) = velocity.  ``sine``: v(x) = velocity * sin(k (x_axis - x0)),
    a standing-wave initial condition for verification (vibration modes).
    """

    type: Literal["uniform", "sine"] = "uniform"
    axis: int = Field(0, ge=0, le=2, description="Axis of the coordinate in the sine profile")
    wavenumber: float = Field(0.0, description="k [1/m]")
    start: float = Field(0.0, description="x0 [m]: where the sine is zero")


class PhreaticSurfaceSpec(Strict):
    """A phreatic surface from data, hydrostatic along the vertical below it (docs/slope-stability.md, "A
    phreatic surface from data")."""

    points: list[list[float]] | None = Field(
        None, min_length=2, max_length=100000, description="2D: the phreatic line's points [x, z] [m] along the "
        "section, x increasing (level beyond the ends); 3D: points [x, y, z] [m] of the surface, triangulated "
        "(a TIN; the nearest point's height beyond their hull)")
    raster: str | None = Field(None, description="3D: a GeoTIFF or ESRI ASCII grid of the surface's height [m] "
                                                 "(path relative to the case file), bilinear between pixel centres")

    @model_validator(mode="after")
    def _one_source(self):
        if (self.points is None) == (self.raster is None):
            raise ValueError("give exactly one of 'points' and 'raster'")
        if self.points is not None:
            sizes = {len(p) for p in self.points}
            if len(sizes) != 1 or sizes.pop() not in (2, 3):
                raise ValueError("every point needs the same number of coordinates: [x, z] in 2D, [x, y, z] in 3D")
            if any(not all(abs(v) < 1e12 for v in p) for p in self.points):
                raise ValueError("every coordinate must be finite")
        return self


class SideHeadSpec(Strict):
    """A hydraulic head held on a grid side (a reservoir or river against the soil there)."""

    side: Literal["x-", "x+", "y-", "y+", "z-", "z+"] = Field(description="Face of the grid")
    head: float | list[float] = Field(
        description="The head H [m] (the water level, in the vertical coordinate) held at that side's soil nodes "
                    "at or below it; above it the side is a seepage face. A list: one head per time of the "
                    "seepage's 'times' (a reservoir that rises or falls)")

    def at(self, times, time: float) -> float:
        """The head [m] at ``time`` (piecewise linear through ``times``, held beyond)."""
        return float(np.interp(time, times, self.head)) if isinstance(self.head, list) else float(self.head)

    def highest(self) -> float:
        return max(self.head) if isinstance(self.head, list) else float(self.head)


class SeepageSpec(Strict):
    """A steady seepage state solved on the grid (mpm/seepage.py): once at the start, and again as its heads
    move (quasi-steady: drained soil's pore pressure follows at once)."""

    times: list[float] = Field([0.0], min_length=1, max_length=1000,
                               description="Times [s] of the heads given as lists, non-decreasing")
    heads: list[SideHeadSpec] = Field(default_factory=list, max_length=6,
                                      description="Heads held on grid sides; every other side is impermeable")
    unsaturated: float = Field(1.0e-3, gt=0.0, le=1.0, description="k_r [-]: the conductivity of the soil above the "
                               "phreatic surface over the saturated one (a non-linear permeability: Bathe & Khoshgoftaar 1979)")

    @model_validator(mode="after")
    def _schedules(self):
        for held in self.heads:
            if isinstance(held.head, list):
                check_schedule(self.times, held.head, "head", "head")
        if any(b < a for a, b in zip(self.times, self.times[1:])) or any(t < 0.0 for t in self.times):
            raise ValueError("'times' must be >= 0 s and must not decrease")
        return self


class PorePressureSpec(Strict):
    """The initial pore pressure of a body of saturated material: hydrostatic below the water table,
    plus a uniform excess."""

    water_table: float | None = Field(
        None, description="Height of the water table along the upward direction (against gravity) [m]; the "
        "particles above it start dry. Default: the body's own surface, column by column (fully saturated, "
        "hydrostatic below its local top on a slope or terrain)")
    excess: float = Field(0.0, description="Uniform excess pore pressure at t = 0 [Pa], compression positive")
    table_normal: Vector | None = Field(
        None, description="Unit normal of a water table parallel to a slope, out of the ground (seepage parallel "
        "to the slope: p = rho_w (-g . normal)(z_wt - x . normal), the infinite slope's flow net); 'water_table' "
        "is then its height along this normal. Default: against gravity (a level table, hydrostatic)")

    surface: PhreaticSurfaceSpec | None = Field(
        None, description="A phreatic surface from data ('points': a line [[x, z], ...] in 2D, [[x, y, z], ...] in "
        "3D): hydrostatic along the vertical below it, dry above (in place of 'water_table')")
    seepage: SeepageSpec | None = Field(
        None, description="The steady seepage state through the body with heads on grid sides, solved once at the "
        "start on the grid (docs/slope-stability.md): p = rho_w |g| (H - z) where H > z, dry above (in place of "
        "'water_table' and 'surface')")
    hydrostatic: bool = Field(
        True, description="false: the body is saturated throughout at the uniform 'excess' only, its water carrying "
        "no weight at t = 0 (a bed wetted to saturation from above, tensiometers reading p near 0); then "
        "'water_table' and 'table_normal' do not apply")

    @model_validator(mode="after")
    def _normal_not_zero(self):
        if self.table_normal is not None and sum(v * v for v in self.table_normal) < 1e-12:
            raise ValueError("'table_normal' must not be zero")
        given = [k for k in ("water_table", "surface", "seepage") if getattr(self, k) is not None]
        if len(given) > 1 or (self.table_normal is not None and given and given != ["water_table"]):
            raise ValueError("give one of 'water_table' (with 'table_normal'), 'surface' and 'seepage'")
        if self.seepage is not None and not self.seepage.heads:
            raise ValueError("a body's 'seepage' state needs a head: give 'seepage.heads'")
        if self.surface is not None and self.surface.raster is not None:
            raise ValueError("a body's phreatic 'surface' takes 'points' (a raster is the water table trigger's)")
        if not self.hydrostatic and (self.water_table is not None or self.table_normal is not None
                                     or self.surface is not None or self.seepage is not None):
            raise ValueError("'hydrostatic': false saturates the whole body at the uniform 'excess'; remove "
                             "'water_table' and 'table_normal' (or set 'hydrostatic' true)")
        return self


class BodySpec(Strict):
    material: str = Field(description="Key of an entry in 'materials'")
    geometry: Geometry
    particles_per_cell: int = Field(2, ge=1, le=8, description="Particles per cell along each axis")
    velocity: Vector | None = Field(None, description="Initial velocity [m/s]; zero if omitted")
    velocity_profile: VelocityProfile = Field(default_factory=VelocityProfile)
    initial_stress: Literal["none", "geostatic"] = Field(
        "none", description="'geostatic': sigma_v = rho g depth, sigma_h = K0 sigma_v (K0 from the material)"
    )
    stress_offset: list[float] | None = Field(
        None, min_length=6, max_length=6, description="A uniform stress added to the initial one (geostatic or "
        "none) [Pa], Voigt order [xx, yy, zz, xy, yz, xz], tension positive; effective stress in a saturated "
        "body (e.g. the undrained state under a load applied at t = 0)")
    pore_pressure: PorePressureSpec | None = Field(
        None, description="Initial pore pressure of a body whose material has 'pore_water' (default: "
                          "hydrostatic below the body's top)")
    surface_normal: Vector | None = Field(
        None, description="'geostatic' on a slope: unit normal of the ground surface, out of the ground; the "
                          "stress is that of an infinite slope in equilibrium (bed-parallel shear included). "
                          "Default: against gravity")


NAME_PATTERN = r"^[A-Za-z0-9_\-][A-Za-z0-9_.\-]*$"  # names a folder: never '.', '..' or hidden


class ProbeSpec(Strict):
    """A column of the flow measured every step (probes/section.py): depth, speed, discharge."""

    name: str = Field(pattern=NAME_PATTERN, description="Name: series.csv columns <name>_depth [m], <name>_speed "
                                                        "[m/s], <name>_q [m2/s]; an obstacle's 'probe' names it")
    point: Vector = Field(description="A point on the column's axis [m], e.g. on the bed upstream of a barrier")
    half_width: float = Field(gt=0, description="Half-width of the strip (2D) or radius of the cylinder (3D) "
                                                "around the axis [m]; about one or two cells")
    direction: Vector | None = Field(None, description="The axis, along which the depth is measured (e.g. the bed "
                                                       "normal); default against gravity")


class InflowSpec(Strict):
    """Particles entering through a cross-section with a hydrograph's discharge (sources/inflow.py)."""

    name: str = Field(pattern=NAME_PATTERN, description="Name: series.csv columns <name>_volume_in [m3; m2 per "
                                                        "metre in 2D] and <name>_discharge")
    material: str = Field(description="The material that flows in (a key of 'materials')")
    section: list[Vector] = Field(min_length=1, max_length=1000, description=(
        "The gate on the bed [m]: in 2D one point [x, y]; in 3D a polyline across the channel, points [x, y, z] "
        "or [x, y] on the ground below (terrain, plane or obstacle)"))
    direction: Vector = Field(description="The direction the flow crosses the gate in (e.g. down the bed); the "
                                          "depth is measured along the part of -gravity normal to it")
    hydrograph: str | None = Field(None, description=(
        "CSV file (relative to the case) with a header naming 'time' [s], 'discharge' [m3/s; m2/s per metre in "
        "2D] and 'velocity' [m/s] or 'depth' [m]; linear between rows, zero discharge outside them"))
    table: list[list[float]] | None = Field(None, min_length=2, max_length=100_000, description=(
        "The hydrograph inline instead of a file: rows [time s, discharge, velocity or depth] (see 'columns')"))
    columns: Literal["velocity", "depth"] = Field("velocity", description="What the table's third column is: the "
                                                                          "speed [m/s] or the depth [m] at the gate")
    particles_per_cell: int = Field(2, ge=1, le=8, description="Particles per cell along each axis: spacing "
                                                               "cell_size / particles_per_cell")

    @model_validator(mode="after")
    def _one_table(self):
        if (self.hydrograph is None) == (self.table is None):
            raise ValueError("give the hydrograph as a CSV file ('hydrograph') or inline ('table'), one of them")
        if self.table is not None and any(len(r) != 3 for r in self.table):
            raise ValueError("every row of 'table' has three numbers: time [s], discharge, velocity or depth")
        return self


class StrengthReductionSpec(Strict):
    times: list[float] = Field(min_length=1, max_length=1000,
                               description="Times [s] of the schedule's points, non-decreasing")
    factors: list[float] = Field(min_length=1, max_length=1000,
                                 description="Strength reduction factor F [-] at each time (F > 1 weakens: c / F, "
                                             "tan(phi) / F); between two times F is linear")
    materials: list[str] | None = Field(None, description="The materials whose strength is reduced (default every "
                                                           "material with a strength to reduce)")

    @model_validator(mode="after")
    def _schedule(self):
        check_schedule(self.times, self.factors, "factors", "factor")
        if any(not 0.05 <= f <= 20.0 for f in self.factors):
            raise ValueError("every factor must lie in [0.05, 20] (F = 1: the soil as given)")
        return self


class PondSpec(Strict):
    """Free water outside the soil at level z_p(t) [m] along the vertical (a reservoir, a river, a pond)."""

    times: list[float] = Field(min_length=1, max_length=1000,
                               description="Times [s] of the schedule's points, non-decreasing")
    levels: list[float] = Field(min_length=1, max_length=1000,
                                description="The free water's level z_p [m] (the vertical coordinate: y in 2D, z in "
                                            "3D) at each time; between two times linear (a drawdown)")

    @model_validator(mode="after")
    def _schedule(self):
        check_schedule(self.times, self.levels, "levels", "level")
        return self


class WaterTableSpec(Strict):
    """A phreatic surface that sets the pore pressure of drained soil: a plane, p = rho_w (-g . n) (z_wt(t) -
    x . n) below it, or a surface from data, and free water ponded outside the soil (docs/slope-stability.md,
    "Water table")."""

    times: list[float] = Field([0.0], min_length=1, max_length=1000,
                               description="Times [s] of the schedule's points, non-decreasing")
    heights: list[float] | None = Field(
        None, min_length=1, max_length=1000, description="A plane: its height z_wt along 'normal' [m] at each "
        "time. With 'surface': the surface's rise [m] at each time (default 0). Between two times linear")
    normal: list[float] | None = Field(
        None, min_length=2, max_length=3, description="Unit normal of the (planar) water table, out of the "
        "ground; its pore pressure is that of seepage parallel to the table. Default: against gravity "
        "(a horizontal table, hydrostatic pressure)")
    surface: PhreaticSurfaceSpec | None = Field(
        None, description="A phreatic surface from data (a line in 2D, points or a raster in 3D) in place of the "
                          "plane: hydrostatic along the vertical below it")
    pond: PondSpec | None = Field(
        None, description="Free water outside the soil: its pressure on every face below its level and in the "
                          "soil's pores below it (the water in the soil stands at least at the pond's level)")
    seepage: SeepageSpec | None = Field(
        None, description="In place of 'heights' or 'surface': the steady seepage state through the soil with heads "
                          "on grid sides and the pond on its faces, solved at the start and again as its heads move "
                          "(docs/slope-stability.md)")
    fluid_density: float = Field(1000.0, gt=0.0, description="rho_w [kg/m3] of the pore water")
    materials: list[str] | None = Field(None, description="The soils under the table's pore pressure (default "
                                                           "every dry soil: not a fluid, no 'pore_water')")

    @model_validator(mode="after")
    def _schedule(self):
        if self.seepage is not None:
            if self.surface is not None or self.heights is not None or self.normal is not None:
                raise ValueError("a 'seepage' state is solved from its heads: remove 'heights', 'surface' and 'normal'")
            if len(self.times) != 1:
                raise ValueError("a 'seepage' state's heads carry their own schedule ('seepage.times'): give the "
                                 "water table one time")
            if not self.seepage.heads and self.pond is None:
                raise ValueError("a 'seepage' state needs a head somewhere: give 'seepage.heads' or a 'pond'")
        if self.surface is None and self.heights is None and self.pond is None and self.seepage is None:
            raise ValueError("give 'heights' (a plane), a 'surface', a 'seepage' state or a 'pond'")
        if self.surface is not None and self.normal is not None:
            raise ValueError("a 'surface' is hydrostatic along the vertical: remove 'normal'")
        if self.heights is not None:
            check_schedule(self.times, self.heights, "heights", "height")
        elif len(self.times) != 1:
            raise ValueError("'times' schedules 'heights': give 'heights' (with a 'surface': its rise) one per time")
        if self.normal is not None and sum(v * v for v in self.normal) < 1e-12:
            raise ValueError("'normal' must not be zero")
        return self


class GravityLoadingSpec(Strict):
    """A gravity-loading stage before the event (engine/gravity_loading.py)."""

    tolerance: float = Field(1.0e-5, gt=0.0, lt=1.0, description="The unbalanced-force ratio at which the stage ends: "
                             "the particles' mass-weighted RMS acceleration over |g| [-]")
    max_time: float = Field(5.0, gt=0.0, le=1.0e4, description="The most simulated time [s] the stage may take; a "
                            "case still out of balance then stops with exit 3 (raise it, or check the case's supports)")
    alpha: float = Field(0.7, gt=0.0, lt=1.0, description="Cundall's local damping coefficient of the stage [-]")


class TriggersSpec(Strict):
    strength_reduction: StrengthReductionSpec | None = Field(
        None, description="Divide the soils' shear strength by a factor F(t) (a strength ramp to failure)")
    water_table: WaterTableSpec | None = Field(
        None, description="A water table z_wt(t) whose pore pressure acts on drained soil (a rising table)")


class Case(Strict):
    """A geompm case.  Every length in m, time in s, density kg/m3, stress Pa."""

    name: str = Field(pattern=NAME_PATTERN, description="Run name; default output folder runs/<name>. Letters, "
                      "digits, '_', '-' and '.', not starting with '.'")
    description: str = ""
    dimension: Literal[2, 3] = Field(description="2 = plane strain, 3 = three-dimensional")
    grid: GridSpec
    time: TimeSpec
    gravity: Vector = Field(description="Body acceleration [m/s2], one entry per dimension")
    crs: str | None = Field(None, description="Coordinate reference system of every coordinate in the case "
                                              "(e.g. 'EPSG:2056'): geometry in map coordinates [m]; a DEM in another "
                                              "CRS is refused")
    solver: SolverSpec = Field(default_factory=SolverSpec)
    materials: dict[str, MaterialSpec] = Field(min_length=1)
    bodies: list[BodySpec] = Field(default_factory=list, description="The bodies of material at the start "
                                                                     "(none: every particle comes from 'inflows')")
    boundaries: list[PluginSpec] = Field(default_factory=list)
    obstacles: list[PluginSpec] = Field(default_factory=list)
    damping: list[DampingSpec] = Field(default_factory=list)
    probes: list[ProbeSpec] = Field(default_factory=list, description="Columns of the flow measured every step "
                                                                       "(depth, speed, discharge)")
    inflows: list[InflowSpec] = Field(default_factory=list, max_length=100, description=(
        "Cross-sections through which material enters with a hydrograph's discharge (sources/inflow.py)"))
    outputs: list[OutputSpec] = Field(default_factory=list)
    run: RunSpec = Field(default_factory=RunSpec)
    triggers: TriggersSpec | None = Field(None, description="What changes over the run to take a slope to failure "
                                                            "(docs/slope-stability.md)")
    gravity_loading: GravityLoadingSpec | None = Field(
        None, description="Bring the case to equilibrium under its own weight before the event: drained, under "
                          "Cundall's local damping, at t = 0, until the unbalanced force falls below the tolerance; "
                          "then the displacements and velocities are reset (docs/slope-stability.md)")

    @field_validator("crs")
    @classmethod
    def _known_crs(cls, v):
        if v is None:
            return v
        from rasterio.crs import CRS
        from rasterio.errors import CRSError

        try:
            CRS.from_user_input(v)
        except CRSError:
            raise ValueError(f"'{v}' is not a coordinate reference system GDAL knows; give e.g. 'EPSG:2056'") from None
        return v

    @model_validator(mode="after")
    def _some_material(self):
        if not self.bodies and not self.inflows:
            raise ValueError("the case has no material: give at least one body in 'bodies' or an inflow in "
                             "'inflows'")
        return self
