"""Case -> Scene: seed particles, size the grid, instantiate the stages.

Nothing downstream of this module reads the case again; kernels only see the
arrays and scalars held by the Scene.
"""

from __future__ import annotations

import json
from pathlib import Path
from dataclasses import dataclass, field

import numpy as np

from geompm.mpm.grid import GridSpec
from geompm.mpm.state import ParticleState
from geompm.errors import CaseError
from geompm.probes.section import ProbeStage
from geompm.sources.inflow import Inflow
from geompm.setup.release import Release
from geompm.setup.release_checks import release_checks
from geompm.setup.bodies import overlap_problems, seed_body
from geompm.files.dem import read_dem
from geompm.mpm.phreatic_surface import (LatticeSurface, PolylineSurface, lattice_points, table_warnings,
                                        tin_lattice)
from geompm.mpm.seepage import SeepageSurface
from geompm.mpm.water_table import WaterTable
from geompm.schema.triggers import water_table_materials
from geompm.kernels.overburden import column_overburden
from geompm.kernels.shape import APIC_D_FACTOR, KIND
from geompm.schema.case import RunSpec
from geompm.schema.load import LoadedCase


@dataclass
class Scene:
    name: str
    dim: int
    grid: GridSpec
    gravity: np.ndarray
    state: ParticleState
    materials: list  # Material instances, index = material id
    material_names: list[str]
    end_time: float
    cfl: float
    dt_max: float | None
    dt_fixed: float | None
    transfer: str  # "pic", "apic", "flip" or "mls" (kernels/stencil.SCHEMES)
    flip_ratio: float
    flip_tau: float | None  # FLIP relaxation time [s]: ratio exp(-dt/tau) per step instead of flip_ratio
    apic_dinv: float  # APIC/MLS inertia D^-1 [1/m2]; 0 for linear hats (no D: C = L)
    nu_max: float
    run_options: RunSpec  # checkpoints, on_leave_domain
    backend: str = "cpu"  # solver.backend (backend/__init__.py)
    sort_interval: int = 100  # solver.sort_interval: steps between two spatial sorts; 0 never
    rebalance_interval: int = 100  # solver.rebalance_interval: steps between two MPI rebalancings; 0 never
    precision: str = "float64"  # solver.precision: the particle and grid arrays' dtype
    p2g: str = "atomic"  # solver.p2g: the cuda backend's P2G kernel
    particle_pass: str = "joined"  # solver.particle_pass: the cuda backend's G2P, particle stages and law
    #: solver.held_step as (steps, fraction, margin cells), or None: every step the stable one (engine/held_step.py)
    held_step: tuple | None = None
    dt_min: float = 1e-9
    base_dir: object = None  # folder of the case file: relative paths (meshes) start there
    boundaries: list = field(default_factory=list)
    obstacles: list = field(default_factory=list)
    damping: list = field(default_factory=list)
    probes: list = field(default_factory=list)  # probes/section.ProbeStage, in the case's order
    inflows: list = field(default_factory=list)  # sources/inflow.Inflow, in the case's order
    writers: list = field(default_factory=list)
    body_materials: list = field(default_factory=list)  # the material name of each body, in case order
    crs: str | None = None  # the case's coordinate reference system ("EPSG:2056"), if it states one
    #: the time step's scheme (schemes/base.Scheme, resolved from solver.update and the materials), made once
    scheme: object = None
    #: triggers.strength_reduction as (times [s], factors [-], material ids), or None (engine/triggers.py)
    strength_trigger: tuple | None = None
    #: the water table (mpm/water_table.WaterTable), or None
    water_table: object = None
    #: the gravity-loading stage's report (engine/gravity_loading.py) once it ran, else None
    loading: dict | None = None
    #: solver.viscoplastic_time [s]: the laws' Duvaut-Lions relaxation time (kernels/viscoplastic.py), or None
    viscoplastic_time: float | None = None
    case_text: str = ""  # the case as JSON, for provenance only (the HDF5 file's attribute); never parsed
    #: the id the next particle a source adds takes (p_id: the assembled particles' are 0 .. n-1)
    next_particle_id: int = 0

    @property
    def stages(self) -> list:
        """Every stage of the scene, once each, in one order: boundaries, obstacles, damping, each in the
        case's order (the scheduler sorts them by phase, stably).  Read capabilities from this list
        (``Stage.records_force``, ``supplies_energy``, ``provides_ground``), never by the section a stage
        came from."""
        return [*self.boundaries, *self.obstacles, *self.damping, *self.probes, *self.inflows]


def _body_velocity(body, pts, dim):
    v0 = np.asarray(body.velocity if body.velocity is not None else np.zeros(dim), dtype=float)
    prof = body.velocity_profile
    if prof.type == "sine":
        return v0[None, :] * np.sin(prof.wavenumber * (pts[:, prof.axis] - prof.start))[:, None]
    return np.broadcast_to(v0, pts.shape).copy()


def geostatic_stress(pts, masses, volumes, k0, gravity, h, normal=None, pore=None) -> np.ndarray:
    """Layered geostatic stress (Voigt, tension positive) from the weight of everything above.

    ``normal`` is the unit normal of the ground surface pointing out of the
    ground (default: against gravity).  Particles are binned in columns of
    width h along ``normal``; in each column the overburden per unit area w is
    the density integrated over height from the top particle (which stands for
    half a particle spacing of material above it) down to the particle, by the
    trapezoid rule between successive levels, so layered bodies carry their
    overburden and a particle lattice at any angle to the column is handled.
    The stress is that of an infinite layer (or infinite slope) in equilibrium,
    sigma n = w g on planes parallel to the surface:

        sigma = w (g n^T + n g^T - (g.n) n n^T) + K0 w (g.n) (I - n n^T),

    i.e. sigma_nn = w (g.n), the bed-parallel shear w g_t, and the lateral
    stress K0 sigma_nn with each particle's own K0.  With n = -g/|g| it reduces
    to sigma_v = -rho |g| depth, sigma_h = K0 sigma_v; for a uniform body that
    fills whole cells it is exactly rho |g| depth.

    With a pore pressure ``pore`` [Pa, compression positive] (a water table's:
    mpm/water_table.py) the stress is effective: sigma'_nn = w (g.n) + p
    takes the place of sigma_nn in the normal and the lateral (K0) parts, the
    bed-parallel shear stays that of the total weight.
    """
    n, dim = pts.shape
    out = np.zeros((n, 6))
    gnorm = float(np.linalg.norm(gravity))
    if gnorm == 0.0 or n == 0:
        return out
    up = -gravity / gnorm if normal is None else np.asarray(normal, float) / np.linalg.norm(normal)
    height = pts @ up
    trans = pts - np.outer(height, up)
    keys = np.floor(trans / h + 1e-9).astype(np.int64)
    col = _column_ids(keys)
    # particles at the same height form one level; by column, then top level first (stable: particle order)
    level = -np.round(height / (1e-9 * h))
    order = np.lexsort((level, col))
    w = np.empty(n)
    w[order] = column_overburden(col[order], level[order], height[order], (masses / volumes)[order],
                                 (volumes ** (1.0 / dim))[order])
    g3, n3 = np.zeros(3), np.zeros(3)
    g3[:dim], n3[:dim] = gravity, up
    gn = float(g3 @ n3)
    ident = np.eye(3)
    normal_stress = w * gn if pore is None else w * gn + pore
    for slot, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        shear = g3[a] * n3[b] + n3[a] * g3[b] - 2.0 * gn * n3[a] * n3[b]
        out[:, slot] = w * shear + normal_stress * (n3[a] * n3[b] + k0 * (ident[a, b] - n3[a] * n3[b]))
    return out


def _column_ids(keys: np.ndarray) -> np.ndarray:
    """One integer per row of ``keys`` (a particle's column indices), ordered as the rows are
    lexicographically: the rows flattened over their ranges, which sorts 13 million particles in a second
    where np.unique(axis=0) takes half a minute; np.unique's inverse where the ranges would overflow."""
    lo = keys.min(axis=0)
    span = keys.max(axis=0) - lo + 1
    if float(np.prod(span.astype(float))) >= 2.0 ** 62:
        return np.unique(keys, axis=0, return_inverse=True)[1].ravel()
    col = np.zeros(len(keys), np.int64)
    for a in range(keys.shape[1]):
        col = col * span[a] + (keys[:, a] - lo[a])
    return col


def assemble(loaded: LoadedCase) -> Scene:
    case = loaded.case
    dim = case.dimension
    h = case.grid.cell_size
    origin = np.asarray(case.grid.origin, dtype=float)
    ncells = np.ceil(np.asarray(case.grid.extent) / h - 1e-6).astype(np.int64)
    kind = KIND[case.grid.shape_function]
    grid = GridSpec(origin=origin, h=h, ncells=ncells, kind=kind)
    gravity = np.asarray(case.gravity, dtype=float)

    names = list(loaded.materials)
    scheme = loaded.scheme(case, names)
    laws = {k: loaded.materials[k].cls for k in names}
    materials = [laws[k](laws[k].at_cell_size(scheme.law_params(case, k, loaded.materials[k].params),
                                              case.grid.cell_size)) for k in names]
    xs, vs, ms, vols, mids, bids, k0s, geo, normals, tests = [], [], [], [], [], [], [], [], [], []
    extras = []  # per body: the scheme's arrays of its particles (saturated soil: flag, water table, pressure)
    for b, body in enumerate(case.bodies):
        mid = names.index(body.material)
        mat = materials[mid]
        ppc = body.particles_per_cell
        pts, contains = seed_body(body.geometry, dim, origin, h, ppc, loaded.base_dir, f"bodies.{b}.geometry",
                                  grid.upper, case.crs)
        if isinstance(contains, Release):  # a release from GIS files: its volume, depth and resolution
            bad, warn = release_checks(contains, contains.lo, contains.hi, origin, grid.upper, h,
                                       f"bodies.{b}.geometry")
            if bad:
                raise CaseError(bad, warnings=loaded.warnings)
            loaded.warnings.extend(warn)
        tests.append(contains)
        vol = (h / ppc) ** dim
        xs.append(pts)
        vs.append(_body_velocity(body, pts, dim))
        vols.append(np.full(len(pts), vol))
        ms.append(np.full(len(pts), vol * mat.density))
        extras.append(scheme.body_arrays(body, mid, pts, h, ppc))
        mids.append(np.full(len(pts), mid, dtype=np.int32))
        bids.append(np.full(len(pts), b, dtype=np.int32))
        geostatic = body.initial_stress == "geostatic"
        geo.append(np.full(len(pts), geostatic))
        normals.append(None if body.surface_normal is None else tuple(body.surface_normal))
        k0s.append(np.full(len(pts), mat.k0() if geostatic else 0.0))
    overlaps = overlap_problems(xs, tests)
    if overlaps:
        raise CaseError(overlaps)
    if not xs:  # every particle comes from the inflows
        xs, vs, ms, vols = [np.zeros((0, dim))], [np.zeros((0, dim))], [np.zeros(0)], [np.zeros(0)]
        mids, bids, k0s, geo = [np.zeros(0, np.int32)], [np.zeros(0, np.int32)], [np.zeros(0)], [np.zeros(0, bool)]
        extras = [None]
    p_x, p_mass, p_vol = np.concatenate(xs), np.concatenate(ms), np.concatenate(vols)
    # overburden from every body; stress only where the body asks for it, in its own surface frame
    k0_all, body_of = np.concatenate(k0s), np.concatenate(bids)
    p_material = np.concatenate(mids)
    extra = _joined(extras, [len(x) for x in xs], scheme.body_width)
    weight = scheme.overburden_mass(p_mass, p_vol, p_material, extra)
    table = _water_table(case, loaded, names, gravity, grid, p_x, p_material)
    pore = None
    if table is not None:
        pore = table.excess(p_x, p_material, 0.0).copy()
        weight = table.buoyant_mass(p_x, p_material, weight, p_vol)
        loaded.warnings.extend(table_warnings(table, p_x, p_material, grid.h))
    stress = np.zeros((len(p_x), 6))
    for normal in dict.fromkeys(normals):
        mine = np.isin(body_of, [b for b, nb in enumerate(normals) if nb == normal]) & np.concatenate(geo)
        if mine.any():
            stress[mine] = geostatic_stress(p_x, weight, p_vol, k0_all, gravity, h, normal, pore)[mine]
    for b, body in enumerate(case.bodies):
        if body.stress_offset is not None:
            stress[body_of == b] += np.asarray(body.stress_offset, float)
    order = np.argsort(p_material, kind="stable")
    state = ParticleState(
        p_x=np.ascontiguousarray(p_x[order]),
        p_v=np.ascontiguousarray(np.concatenate(vs)[order]),
        p_mass=p_mass[order],
        p_vol0=p_vol[order],
        p_material=p_material[order],
        p_body=np.concatenate(bids)[order],
        p_stress=np.ascontiguousarray(stress[order]),
    )
    scheme.init_fields(state, [a[order] for a in extra])
    counts = np.bincount(state.p_material, minlength=len(materials))
    starts = np.r_[0, np.cumsum(counts)]
    state.blocks = [(int(starts[k]), int(starts[k + 1])) for k in range(len(materials))]
    state.p_state = [m.initial_state(int(counts[k])) for k, m in enumerate(materials)]
    _initial_stress_checks(materials, names, state, loaded)
    state.set_precision(case.solver.precision)

    scene = Scene(
        name=case.name, dim=dim, grid=grid, gravity=gravity, state=state,
        materials=materials, material_names=names,
        end_time=case.time.end, cfl=case.time.cfl, dt_max=case.time.dt_max, dt_fixed=case.time.dt,
        dt_min=case.time.dt_min, run_options=case.run,
        transfer=case.solver.transfer, flip_ratio=case.solver.flip_ratio,
        backend=case.solver.backend, sort_interval=case.solver.sort_interval,
        rebalance_interval=case.solver.rebalance_interval, precision=case.solver.precision,
        p2g=case.solver.p2g,
        particle_pass=case.solver.particle_pass,
        held_step=None if case.solver.held_step is None else (
            case.solver.held_step.steps, case.solver.held_step.fraction, case.solver.held_step.margin_cells),
        flip_tau=case.solver.flip_relaxation_time,
        viscoplastic_time=case.solver.viscoplastic_time,
        apic_dinv=(1.0 / (APIC_D_FACTOR[kind] * h * h)) if APIC_D_FACTOR[kind] > 0 else 0.0,
        nu_max=max((m.kinematic_viscosity() for m in materials), default=0.0),
        case_text=json.dumps(loaded.raw), crs=case.crs, body_materials=[b.material for b in case.bodies],
        strength_trigger=_strength_trigger(case, materials, names), water_table=table,
        base_dir=loaded.base_dir, scheme=scheme,
    )
    for r, spec in zip(loaded.outputs, loaded.case.outputs):  # first: a stage asks what they need (face forces)
        scene.writers.append(r.cls(r.params, spec.interval))
    for i, spec in enumerate(case.probes):  # first: a contact surface reads the probe it names
        probe = ProbeStage(spec, spec.name, f"probes.{i}")
        probe.setup(scene)
        scene.probes.append(probe)
    for attr in ("boundaries", "obstacles", "damping"):
        for r in getattr(loaded, attr):
            stage = r.cls(r.params, r.label, r.path)
            stage.setup(scene)
            getattr(scene, attr).append(stage)
    scene.next_particle_id = state.n
    for i, (spec, hg) in enumerate(zip(case.inflows, loaded.hydrographs)):  # last: a gate lies on the solids
        inflow = Inflow(spec, spec.name, f"inflows.{i}", hg)
        inflow.setup(scene)
        scene.inflows.append(inflow)
    _check_bodies_clear(scene)
    scheme.after_stages(scene)
    return scene


def _initial_stress_checks(materials, names, state, loaded) -> None:
    """Each law's word on its particles' initial effective stress (Material.initial_stress_checks): problems
    refused, warnings added to the case's, before any step."""
    problems = []
    for k, (m, (a, b)) in enumerate(zip(materials, state.blocks)):
        bad, warn = m.initial_stress_checks(state.p_stress[a:b])
        problems += [(f"materials.{names[k]}.{field}", text) for field, text in bad]
        loaded.warnings.extend((f"materials.{names[k]}.{field}", text) for field, text in warn)
    if problems:
        raise CaseError(problems, warnings=loaded.warnings)


def _joined(per_body: list, sizes: list[int], width: int) -> list[np.ndarray]:
    """The scheme's ``width`` per-body arrays joined over the bodies, zeros for a body that has none (a dry
    body of a saturated scene)."""
    return [np.concatenate([np.zeros(n) if a is None else a[k] for a, n in zip(per_body, sizes)])
            for k in range(width)]


#: a particle deeper than this fraction of its spacing inside a rigid solid starts inside it (those on the
#: surface, half a spacing out, do not)
INSIDE_FRACTION = 0.25


def _check_bodies_clear(scene: Scene) -> None:
    """Refuse bodies whose particles start inside an obstacle, a plane or the terrain (a stage's
    solid_depth): both JSON paths, the particles, the volume and the depth."""
    st = scene.state
    spacing = st.p_vol0 ** (1.0 / scene.dim)
    problems = []
    for stage in scene.stages:
        depth = stage.solid_depth(st.p_x)
        if depth is None:
            continue
        inside = depth > INSIDE_FRACTION * spacing
        for b in np.unique(st.p_body[inside]):
            mine = inside & (st.p_body == b)
            unit = "m3" if scene.dim == 3 else "m2 (per metre of depth)"
            problems.append((f"bodies.{b}.geometry",
                             f"{int(mine.sum())} particles ({float(st.p_vol0[mine].sum()):.4g} {unit}) start "
                             f"inside {stage.json_path} ('{stage.label}'), up to {float(depth[mine].max()):.3g} m "
                             f"deep: move or trim the body so that it starts clear of it (the contact would "
                             f"expel them in the first steps with a spurious force)"))
    if problems:
        raise CaseError(problems)


def _strength_trigger(case, materials: list, names: list[str]) -> tuple | None:
    """(times, factors, material ids) of ``triggers.strength_reduction``: the named materials, or every one
    whose law has a strength to reduce."""
    spec = case.triggers.strength_reduction if case.triggers is not None else None
    if spec is None:
        return None
    wanted = spec.materials if spec.materials is not None else [n for n, m in zip(names, materials)
                                                                 if type(m).strength_reduction]
    return tuple(spec.times), tuple(spec.factors), tuple(names.index(n) for n in wanted)


def _water_table(case, loaded, names: list[str], gravity, grid, p_x, p_material) -> WaterTable | None:
    """The water table of ``triggers.water_table`` (schema/triggers.py checked it), or None: a plane, a
    surface from data (mpm/phreatic_surface.py), a steady seepage state solved through the particles of its
    soils (mpm/seepage.py) or a pond alone, with the pond if any."""
    spec = case.triggers.water_table if case.triggers is not None else None
    if spec is None:
        return None
    wanted = water_table_materials(case, loaded)
    acts = np.array([1.0 if n in wanted else 0.0 for n in names])
    g_abs = float(np.linalg.norm(gravity))
    up = len(gravity) - 1
    pond = None if spec.pond is None else (tuple(spec.pond.times), tuple(spec.pond.levels))
    common = dict(pond=pond, up=up, weight=spec.fluid_density * g_abs, rho_w=spec.fluid_density)
    if spec.seepage is not None:
        surface = seepage_state(spec, grid, p_x[acts[p_material] > 0.0])
        r = surface.report
        if not r["settled"]:
            loaded.warnings.append(("triggers.water_table.seepage", f"the seepage state did not settle in "
                                    f"{r['iterations']} iterations (its head still moved {r['change']:.2g} cell): "
                                    "the phreatic surface is approximate; a finer or coarser grid may settle"))
        return WaterTable(tuple(spec.times), (0.0,), None, spec.fluid_density * g_abs, acts, surface=surface,
                          **common)
    if spec.surface is not None or spec.heights is None:
        surface = None if spec.surface is None else phreatic_surface(spec.surface, case, grid, loaded.base_dir)
        rises = tuple(spec.heights) if spec.heights is not None else (0.0,)
        return WaterTable(tuple(spec.times), rises if surface is not None else None, None, spec.fluid_density * g_abs,
                          acts, surface=surface, **common)
    normal = -gravity / np.linalg.norm(gravity) if spec.normal is None else np.asarray(spec.normal, float)
    normal = normal / np.linalg.norm(normal)
    return WaterTable(tuple(spec.times), tuple(spec.heights), normal, -spec.fluid_density * float(gravity @ normal),
                      acts, **common)


def seepage_state(spec, grid, points) -> SeepageSurface:
    """The steady seepage state of ``spec`` (schema WaterTableSpec with ``seepage``) through the cells that hold
    ``points`` (the soils' particles), its pond at t = 0, solved again as its heads move."""
    sp = spec.seepage
    pond = None if spec.pond is None else spec.pond.levels[0]

    def schedule(time):
        return [("xyz".index(s.side[0]), s.side[1] == "+", s.at(sp.times, time)) for s in sp.heads]

    try:
        return SeepageSurface(schedule, pond, grid, sp.unsaturated, points)
    except ValueError as exc:
        raise CaseError([("triggers.water_table.seepage", str(exc))]) from None


#: the most lattice points a 3D phreatic surface from points is sampled on (8 bytes each)
MAX_LATTICE_POINTS = 50_000_000


def phreatic_surface(spec, case, grid, base_dir):
    """The phreatic surface of ``spec`` (schema PhreaticSurfaceSpec) over the grid's plan."""
    where = "triggers.water_table.surface"
    if case.dimension == 2:
        pts = np.asarray(spec.points, float)
        return PolylineSurface(pts[:, 0], pts[:, 1])
    lo = np.asarray(case.grid.origin, float)[:2]
    hi = lo + np.asarray(case.grid.extent, float)[:2]
    if spec.raster is not None:
        path = Path(base_dir) / spec.raster
        return LatticeSurface(read_dem(path, f"{where}.raster", region=(tuple(lo), tuple(hi))), str(spec.raster))
    count = lattice_points(lo, hi, grid.h)
    if count > MAX_LATTICE_POINTS:
        raise CaseError([(f"{where}.points", f"the surface's lattice over the grid's plan would hold {count:,} points "
                                             f"(a quarter cell apart); at most {MAX_LATTICE_POINTS:,}: give a raster "
                                             "instead")])
    return LatticeSurface(tin_lattice(spec.points, lo, hi, grid.h), f"{len(spec.points)} points (a TIN)")


