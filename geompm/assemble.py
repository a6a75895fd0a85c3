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


def geostatic_stress(pts, rho, gravity, k0, spacing) -> np.ndarray:
    """sigma_v = -rho |g| depth, sigma_h = K0 sigma_v (Voigt, tension positive).

    depth is measured against the -g direction from the top particle of the
    same column (columns are bins one particle spacing wide across the gravity
    direction), plus half a spacing, i.e. to the body's free surface.
    """
    n, dim = pts.shape
    gnorm = float(np.linalg.norm(gravity))
    out = np.zeros((n, 6))
    if gnorm == 0.0:
        return out
    ghat = gravity / gnorm
    height = -pts @ ghat
    trans = pts - np.outer(pts @ ghat, ghat)
    keys = np.floor(trans / spacing + 1e-9).astype(np.int64)
    _, col = np.unique(keys, axis=0, return_inverse=True)
    col = col.ravel()
    top = np.full(col.max() + 1, -np.inf)
    np.maximum.at(top, col, height)
    depth = top[col] - height + 0.5 * spacing
    sv = -rho * gnorm * depth
    sh = k0 * sv
    g3 = np.zeros(3)
    g3[:dim] = ghat
    # sigma = sh I + (sv - sh) g g^T
    for slot, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))):
        out[:, slot] = (sv - sh) * g3[a] * g3[b] + (sh if a == b else 0.0)
    return out


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
    xs, vs, ms, vols, mids, bids, sigs = [], [], [], [], [], [], []
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
        if body.initial_stress == "geostatic":
            sigs.append(geostatic_stress(pts, mat.density, gravity, mat.k0(), h / ppc))
        else:
            sigs.append(np.zeros((len(pts), 6)))
    p_material = np.concatenate(mids)
    order = np.argsort(p_material, kind="stable")
    state = ParticleState(
        p_x=np.ascontiguousarray(np.concatenate(xs)[order]),
        p_v=np.ascontiguousarray(np.concatenate(vs)[order]),
        p_mass=np.concatenate(ms)[order],
        p_vol0=np.concatenate(vols)[order],
        p_material=p_material[order],
        p_body=np.concatenate(bids)[order],
        p_stress=np.ascontiguousarray(np.concatenate(sigs)[order]),
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
