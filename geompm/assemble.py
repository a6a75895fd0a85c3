"""Case -> Scene: seed particles, size the grid, instantiate the stages.

Nothing downstream of this module reads the case again; kernels only see the
arrays and scalars held by the Scene.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .engine.grid import GridSpec
from .engine.state import ParticleState
from .geometry import seed_body
from .kernels.shape import APIC_D_FACTOR, KIND
from .schema.load import LoadedCase

TRANSFER_MODE = {"pic": 0, "apic": 1, "flip": 2}


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
    transfer_mode: int
    flip_ratio: float
    musl: bool
    apic_dinv: float
    nu_max: float
    base_dir: object = None  # folder of the case file: relative paths (meshes) start there
    boundaries: list = field(default_factory=list)
    obstacles: list = field(default_factory=list)
    damping: list = field(default_factory=list)
    writers: list = field(default_factory=list)
    case_raw: dict = field(default_factory=dict)


def _body_velocity(body, pts, dim):
    v0 = np.asarray(body.velocity if body.velocity is not None else np.zeros(dim), dtype=float)
    prof = body.velocity_profile
    if prof.type == "sine":
        return v0[None, :] * np.sin(prof.wavenumber * (pts[:, prof.axis] - prof.start))[:, None]
    return np.broadcast_to(v0, pts.shape).copy()


def geostatic_stress(pts, masses, k0, gravity, h) -> np.ndarray:
    """Layered geostatic stress (Voigt, tension positive) from the weight of everything above.

    Particles are binned in columns of width h across the gravity direction;
    in each column, sigma_v of a particle is minus |g| times the mass above it
    (half its own) per unit column area h^(d-1), so layered bodies carry their
    overburden; sigma_h = K0 sigma_v with each particle's own K0.  For a
    uniform body that fills whole cells this is exactly rho |g| depth.
    """
    n, dim = pts.shape
    out = np.zeros((n, 6))
    gnorm = float(np.linalg.norm(gravity))
    if gnorm == 0.0 or n == 0:
        return out
    ghat = gravity / gnorm
    height = -pts @ ghat
    trans = pts - np.outer(pts @ ghat, ghat)
    keys = np.floor(trans / h + 1e-9).astype(np.int64)
    _, col = np.unique(keys, axis=0, return_inverse=True)
    col = col.ravel()
    order = np.argsort(col, kind="stable")
    csum = np.empty(n)
    for start, stop in _runs(col[order]):
        idx = order[start:stop]
        # particles at the same height form one level; a level carries the levels above plus half itself
        levels, inv = np.unique(-np.round(height[idx] / (1e-9 * h)), return_inverse=True)
        level_mass = np.bincount(inv.ravel(), weights=masses[idx], minlength=len(levels))
        above = np.cumsum(level_mass) - level_mass
        csum[idx] = (above + 0.5 * level_mass)[inv.ravel()]
    sv = -gnorm * csum / h ** (dim - 1)
    sh = k0 * sv
    g3 = np.zeros(3)
    g3[:dim] = ghat
    for slot, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        out[:, slot] = (sv - sh) * g3[a] * g3[b] + (sh if a == b else 0.0)
    return out


def _runs(sorted_keys):
    """(start, stop) of each run of equal values in a sorted array."""
    edges = np.flatnonzero(np.diff(sorted_keys)) + 1
    bounds = np.r_[0, edges, len(sorted_keys)]
    return zip(bounds[:-1], bounds[1:])


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
    materials = [loaded.materials[k].cls(loaded.materials[k].params) for k in names]
    xs, vs, ms, vols, mids, bids, k0s, geo = [], [], [], [], [], [], [], []
    for b, body in enumerate(case.bodies):
        mid = names.index(body.material)
        mat = materials[mid]
        ppc = body.particles_per_cell
        pts = seed_body(body.geometry, dim, origin, h, ppc, loaded.base_dir, f"bodies.{b}.geometry")
        vol = (h / ppc) ** dim
        xs.append(pts)
        vs.append(_body_velocity(body, pts, dim))
        vols.append(np.full(len(pts), vol))
        ms.append(np.full(len(pts), vol * mat.density))
        mids.append(np.full(len(pts), mid, dtype=np.int32))
        bids.append(np.full(len(pts), b, dtype=np.int32))
        geostatic = body.initial_stress == "geostatic"
        geo.append(np.full(len(pts), geostatic))
        k0s.append(np.full(len(pts), mat.k0() if geostatic else 0.0))
    p_x, p_mass = np.concatenate(xs), np.concatenate(ms)
    # overburden from every body; stress only where the body asks for it
    stress = geostatic_stress(p_x, p_mass, np.concatenate(k0s), gravity, h) * np.concatenate(geo)[:, None]
    p_material = np.concatenate(mids)
    order = np.argsort(p_material, kind="stable")
    state = ParticleState(
        p_x=np.ascontiguousarray(p_x[order]),
        p_v=np.ascontiguousarray(np.concatenate(vs)[order]),
        p_mass=p_mass[order],
        p_vol0=np.concatenate(vols)[order],
        p_material=p_material[order],
        p_body=np.concatenate(bids)[order],
        p_stress=np.ascontiguousarray(stress[order]),
    )
    counts = np.bincount(state.p_material, minlength=len(materials))
    starts = np.r_[0, np.cumsum(counts)]
    state.blocks = [(int(starts[k]), int(starts[k + 1])) for k in range(len(materials))]
    state.p_state = [m.initial_state(int(counts[k])) for k, m in enumerate(materials)]

    scene = Scene(
        name=case.name, dim=dim, grid=grid, gravity=gravity, state=state,
        materials=materials, material_names=names,
        end_time=case.time.end, cfl=case.time.cfl, dt_max=case.time.dt_max, dt_fixed=case.time.dt,
        transfer_mode=TRANSFER_MODE[case.solver.transfer], flip_ratio=case.solver.flip_ratio,
        musl=case.solver.update == "musl",
        apic_dinv=(1.0 / (APIC_D_FACTOR[kind] * h * h)) if APIC_D_FACTOR[kind] > 0 else 0.0,
        nu_max=max((m.kinematic_viscosity() for m in materials), default=0.0),
        case_raw=loaded.raw,
        base_dir=loaded.base_dir,
    )
    for attr in ("boundaries", "obstacles", "damping"):
        for r in getattr(loaded, attr):
            stage = r.cls(r.params, r.label, r.path)
            stage.setup(scene)
            getattr(scene, attr).append(stage)
    for r, spec in zip(loaded.outputs, loaded.case.outputs):
        scene.writers.append(r.cls(r.params, spec.interval))
    return scene
