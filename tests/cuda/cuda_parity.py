"""CPU against CUDA backend on tiny scenes, for every built-in law and stage (issue 21, point 4).

    NUMBA_ENABLE_CUDASIM=1 python tests/cuda/cuda_parity.py [--steps 3] [SCENE ...]

Each scene runs ``--steps`` steps on ``solver.backend`` "cpu" and on "cuda" (numba-cuda's simulator
when NUMBA_ENABLE_CUDASIM=1, a GPU otherwise) from the same case; it prints one JSON line per scene:
the largest difference of positions, velocities, stresses and densities (particles matched by p_id)
relative to the largest magnitude of that field, of every series.csv column (the stages' forces,
relative to the column's largest magnitude), and the step counts and times.  tests/cuda/test_cuda_backend.py
runs it and asserts the differences.  The scenes cover every law (7 built-in, the EVP integration of
the yield fluids), every transfer (PIC, APIC, FLIP with a relaxation time, MLS), all three shape
functions, USL and MUSL, 2D and 3D, and every built-in stage: walls (slip, fixed, friction), a plane,
periodic x, artificial and local damping, box, sphere, cylinder, STL and terrain obstacles with their
recorded forces and the penetration guard.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from geompm.contract import registry  # noqa: E402
from geompm.api import scene_from_dict  # noqa: E402
from geompm.engine.scheduler import Simulation  # noqa: E402


def law(name: str, **over) -> dict:
    params = registry.get("materials", name, "").example_params().model_dump(exclude_none=True)
    params.pop("from_bingham", None)
    params.update(over)
    return dict(model=name, **params)


def case2d(material: dict, solver=None, shape="quadratic", boundaries=None, obstacles=None, damping=None,
           box=((0.3, 0.0), (0.6, 0.3)), velocity=None) -> dict:
    body = {"material": "m", "geometry": {"type": "box", "min": list(box[0]), "max": list(box[1])},
            "particles_per_cell": 2}
    if velocity is not None:
        body["velocity"] = velocity
    return {
        "name": "parity", "dimension": 2,
        "grid": {"origin": [0.0, 0.0], "extent": [1.0, 0.8], "cell_size": 0.1, "shape_function": shape},
        "time": {"end": 1.0, "cfl": 0.4}, "gravity": [0.0, -9.81],
        "materials": {"m": material}, "bodies": [body],
        "boundaries": boundaries if boundaries is not None else [
            {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.4},
            {"type": "wall", "side": "x-", "condition": "slip"}],
        "obstacles": obstacles or [], "damping": damping or [],
        "solver": solver or {}, "outputs": [],
    }


def case3d(material: dict, folder: Path, obstacles=None, damping=None, solver=None, terrain=False) -> dict:
    lift = 0.22 if terrain else 0.0  # the block rests on the floor, or starts just above the terrain
    c = {
        "name": "parity3d", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [0.6, 0.4, 0.5], "cell_size": 0.1},
        "time": {"end": 1.0, "cfl": 0.4}, "gravity": [0.0, 0.0, -9.81],
        "materials": {"m": material},
        "bodies": [{"material": "m", "geometry": {"type": "box", "min": [0.1, 0.1, lift], "max": [0.3, 0.3, lift + 0.2]},
                    "velocity": [0.5, 0.0, -1.5] if terrain else [2.0, 0.0, -0.5]}],
        "boundaries": [] if terrain else [{"type": "wall", "side": "z-", "condition": "friction", "friction": 0.3}],
        "obstacles": obstacles or [], "damping": damping or [], "solver": solver or {}, "outputs": [],
    }
    return c


def stl_block(folder: Path) -> str:
    import trimesh

    box = trimesh.creation.box(extents=[0.2, 0.4, 0.2])
    box.apply_translation([0.4, 0.2, 0.1])
    box.export(folder / "dam.stl")
    return "dam.stl"


def terrain_dem(folder: Path) -> str:
    """A 20 deg incline falling along x, as a GeoTIFF (rasterio)."""
    import rasterio
    from rasterio.transform import Affine

    dx, nx, ny = 0.05, 16, 12
    xs = -0.1 + (np.arange(nx) + 0.5) * dx
    z = np.tile(0.25 - np.tan(np.radians(20.0)) * xs, (ny, 1))
    with rasterio.open(folder / "dem.tif", "w", driver="GTiff", height=ny, width=nx, count=1, dtype="float64",
                       crs="EPSG:2056", transform=Affine(dx, 0.0, -0.1, 0.0, -dx, -0.1 + ny * dx)) as dst:
        dst.write(z, 1)
    return "dem.tif"


def scenes(folder: Path) -> dict:
    """name -> case: each law, transfer, shape, update order and stage at least once."""
    wall_fixed = [{"type": "wall", "side": "y-", "condition": "fixed"}]
    return {
        "elastic_apic_quadratic_usl": case2d(law("linear_elastic"), velocity=[1.0, 0.0]),
        # two walls: MUSL's second stage pass runs them as one group (cuda_loops.NODE_GROUP), its first joins them
        # to the grid update (UPDATE_GROUP)
        "elastic_pic_linear_musl": case2d(law("linear_elastic"), {"transfer": "pic", "update": "musl"}, "linear",
                                          wall_fixed + [{"type": "wall", "side": "x-", "condition": "slip"}]),
        "newtonian_flip_tau_cubic_local_damping": case2d(
            law("newtonian"), {"transfer": "flip", "flip_relaxation_time": 0.1}, "cubic",
            damping=[{"model": "local", "alpha": 0.3}]),
        "bingham_mls_artificial_damping": case2d(law("bingham"), {"transfer": "mls"},
                                                 damping=[{"model": "artificial", "xi": 0.002}]),
        "bingham_evp_plane": case2d(law("bingham", integration="elastoviscoplastic"), boundaries=[
            {"type": "plane", "point": [0.0, 0.05], "normal": [0.2, 1.0], "condition": "friction", "friction": 0.3}]),
        "cross_explicit_flip_ratio": case2d(law("cross"), {"transfer": "flip", "flip_ratio": 0.95}),
        "cross_evp_periodic": case2d(law("cross", integration="elastoviscoplastic"), boundaries=[
            {"type": "wall", "side": "y-", "condition": "slip"}, {"type": "periodic", "axis": "x"}],
            velocity=[-1.0, 0.0], box=((0.0, 0.0), (0.3, 0.3))),
        "herschel_bulkley_explicit_and_box_guard": dict(case2d(
            law("herschel_bulkley"), obstacles=[{"type": "box", "name": "dam", "min": [0.7, 0.0], "max": [0.75, 0.3],
                                  "friction": 0.3}],
            velocity=[2.0, 0.0]), parity_place=[0.71, 0.125]),
        "herschel_bulkley_evp_sphere": case2d(
            law("herschel_bulkley", integration="elastoviscoplastic"),
            obstacles=[{"type": "sphere", "name": "rock", "center": [0.45, 0.42], "radius": 0.12, "condition": "slip"}],
            velocity=[0.0, 1.0]),
        "drucker_prager_cylinder_sorted": case2d(
            law("drucker_prager"), {"sort_interval": 1}, obstacles=[{"type": "cylinder", "name": "pier", "center": [0.75, 0.1],
                                               "radius": 0.08, "friction": 0.3}], velocity=[2.0, 0.0]),
        **({"mu_i_plugin_2d": case2d(law("mu_i"), velocity=[1.0, 0.0])} if "mu_i" in registry.available("materials")
           else {}),
        "mohr_coulomb_2d": case2d(law("mohr_coulomb"), {"transfer": "flip", "flip_relaxation_time": 0.05},
                                  velocity=[0.5, 0.0]),
        "drucker_prager_3d_stl": case3d(law("drucker_prager"), folder, obstacles=[
            {"type": "rigid_mesh", "name": "dam", "file": stl_block(folder), "friction": 0.3}],
            damping=[{"model": "artificial", "xi": 0.002}], solver={"sort_interval": 1}),
        # float32 in 2D: the CPU side's float32 transfers are those tests/unit/test_precision.py compiled (cached)
        "drucker_prager_2d_float32": case2d(law("drucker_prager"), {"precision": "float32"}, velocity=[2.0, 0.0]),
        # the first scene again through the tiled P2G: the CPU side is compiled once (same part, see --part)
        "elastic_apic_quadratic_usl_tiled_p2g": case2d(law("linear_elastic"), {"p2g": "tiled"}, velocity=[1.0, 0.0]),
        # and through G2P, the walls' particle rules and the law as three kernels (solver.particle_pass)
        "elastic_apic_quadratic_usl_particle_pass_separate": case2d(law("linear_elastic"), {"particle_pass": "separate"},
                                                                    velocity=[1.0, 0.0]),
        "elastic_apic_quadratic_usl_tiled_p2g_float32": case2d(law("linear_elastic"), {"p2g": "tiled",
                                                                                     "precision": "float32"},
                                                             velocity=[1.0, 0.0]),
        # saturated soil (schemes/saturated/cuda.py): an impermeable friction floor, a drained slip wall, the
        # pressure seen through the grid, the water's APIC matrix, the device sort of its arrays
        "saturated_drucker_prager": case2d(
            law("drucker_prager", pore_water={"porosity": 0.4, "hydraulic_conductivity": 1e-3,
                                              "fluid": {"bulk_modulus": 2e7}}),
            {"sort_interval": 1}, boundaries=[
                {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.4},
                {"type": "wall", "side": "x-", "condition": "slip", "drainage": "drained"}],
            velocity=[-1.0, 0.0], box=((0.0, 0.0), (0.3, 0.3))),
        # the same in MUSL order (schemes/saturated/musl.py: the remap's scatters and second split)
        "saturated_drucker_prager_musl": case2d(
            law("drucker_prager", pore_water={"porosity": 0.4, "hydraulic_conductivity": 1e-3,
                                              "fluid": {"bulk_modulus": 2e7}}),
            {"update": "saturated_musl"}, boundaries=[
                {"type": "wall", "side": "y-", "condition": "friction", "friction": 0.4},
                {"type": "wall", "side": "x-", "condition": "slip", "drainage": "drained"}],
            velocity=[-1.0, 0.0], box=((0.0, 0.0), (0.3, 0.3))),
        # softening laws: MC under a strength-reduction ramp (the parameters re-uploaded each step), DP plain
        "mohr_coulomb_softening_trigger": dict(case2d(law("mohr_coulomb_softening"), velocity=[0.5, 0.0]),
                                               triggers={"strength_reduction": {"times": [0.0, 0.01],
                                                                                "factors": [1.0, 1.5]}}),
        "drucker_prager_softening_2d": case2d(law("drucker_prager_softening", dilation_angle=0.0,
                                                  softening={"start": 0.0, "end": 0.02, "shape": "exponential"}),
                                              velocity=[1.0, 0.0]),
        # the critical-state laws: the sand's cone from its density (a stretched, contracting block), the clay's
        # implicit return from a geostatic start on a floor
        # the laws' Duvaut-Lions regularisation (solver.viscoplastic_time: cuda_loops.relaxed_kernel)
        # (phi 5 deg, no cohesion: it yields in the first step; the regularised stress differs from the inviscid
        # by a quarter of its magnitude after 3 steps)
        "mohr_coulomb_viscoplastic_2d": case2d(law("mohr_coulomb", friction_angle=5.0, dilation_angle=0.0,
                                                   cohesion=0.0), {"viscoplastic_time": 0.002}, velocity=[0.5, 0.0]),
        # Voellmy basal friction (contact/voellmy.py): the turbulent drag on the first node layer of a wall and a plane
        "drucker_prager_voellmy_wall_plane": case2d(law("drucker_prager"), boundaries=[
            {"type": "wall", "side": "y-", "condition": "voellmy", "friction": 0.3, "xi": 50.0},
            {"type": "plane", "point": [0.9, 0.0], "normal": [-1.0, 0.3], "condition": "voellmy", "friction": 0.2,
             "xi": 200.0}], velocity=[1.5, 0.0]),
        "critical_state_sand_2d": case2d(law("critical_state_sand", youngs_modulus=2e6), velocity=[1.0, 0.0]),
        "modified_cam_clay_2d": dict(case2d(law("modified_cam_clay", preconsolidation_pressure=5e3),
                                            boundaries=[{"type": "wall", "side": "y-", "condition": "friction",
                                                         "friction": 0.4}], velocity=[0.5, 0.0])),
        # the terrain needs rasterio (a device machine may be given the lean wheels: fetch_wheels.sh LEAN=1)
        **({"newtonian_3d_terrain_guard": dict(case3d(law("newtonian"), folder, obstacles=[
            {"type": "terrain", "name": "ground", "dem": terrain_dem(folder), "friction": 0.3}], terrain=True),
            parity_place=[0.35, 0.2, 0.10])} if importlib.util.find_spec("rasterio") else {}),
    }


def compare(a, b, floor: float = 0.0) -> float:
    """max |a - b| / max(max |a|, floor): relative to the field's largest magnitude, or to a physical
    floor where the field is nearly zero (a stress of 1e-12 Pa in a free-falling block is round-off)."""
    scale = max(float(np.abs(a).max()) if a.size else 0.0, floor)
    diff = float(np.abs(a - b).max()) if a.size else 0.0
    return diff / scale if scale > 0 else diff


def floors(case: dict) -> dict:
    """Physical scales of each field: the cell size [m], g t for a velocity [m/s], the weight stress
    of one cell rho g h [Pa], the density rho [kg/m3] (the densest material's)."""
    h = case["grid"]["cell_size"]
    g = float(np.linalg.norm(case["gravity"]))
    rho = max(m["density"] for m in case["materials"].values())
    return {"p_x": h, "p_v": g * 0.01, "p_stress": rho * g * h, "p_rho": rho, "p_pore": 1000.0 * g * h,
            "p_vw": g * 0.01}


def run(case: dict, backend: str, steps: int, folder: Path):
    c = json.loads(json.dumps(case))
    c["solver"]["backend"] = backend
    place = c.pop("parity_place", None)
    sim = Simulation(scene_from_dict(c, base_dir=folder))
    if place is not None:  # the furthest particle put inside an obstacle: its guard must act (host first)
        st = sim.state
        st.p_x[int(np.argmax(st.p_x[:, 0]))] = place
    rows = []
    t0 = time.perf_counter()
    for k in range(steps):
        sim.step(sim.stable_dt())
        if k in (0, steps - 1):  # between these no host read: the device keeps the particles, and the next step's
            # time step and window come from the tally the last step settled (backend/cuda_tally.py)
            bad, ek, wg = sim.backend.health_sums(sim.scene.gravity)
            rows.append({**sim.series_row(), "health_bad": bad, "health_kinetic": ek, "health_released": wg})
    wall = time.perf_counter() - t0
    rows[-1].update({f"{s.label}_max_depth": s.max_depth for s in sim.particle_stages if hasattr(s, "max_depth")})
    st = sim.state
    order = np.argsort(st.p_id)
    names = ("p_x", "p_v", "p_stress", "p_rho") + tuple(f.name for f in sim.scheme.fields if f.name in ("p_pore", "p_vw"))
    fields = {k: getattr(st, k)[order].astype(np.float64) for k in names}
    return fields, rows, sim, wall


def sort_check() -> dict:
    """The device's counting sort (backend/cuda_sort.py) against the CPU's (kernels/sort.cell_order), on
    crowded random particles (tens per cell, negative cells, two blocks, 2D and 3D), and its prefix sum
    against numpy's on an array long enough for three levels of blocks."""
    from numba import cuda

    from geompm.backend import cuda_sort
    from geompm.kernels.sort import cell_order

    rng = np.random.default_rng(7)
    equal = []
    for d, n, blocks in ((2, 400, [(0, 250), (250, 400)]), (3, 300, [(0, 0), (0, 300)])):
        p_x = rng.uniform(-0.25, 0.35, size=(n, d))
        p_x[:40] = p_x[40:80]  # particles at the same place keep their order
        origin, h = np.full(d, -0.3), 0.1
        want = np.concatenate([cell_order(p_x, origin, h, s, e) for s, e in blocks])
        got = cuda_sort.cell_order(cuda.to_device(p_x), cuda.to_device(origin), h, blocks).copy_to_host()
        equal.append(bool(np.array_equal(want, got)))
        moved = cuda_sort.gather(cuda.to_device(p_x), cuda.to_device(got)).copy_to_host()
        equal.append(bool(np.array_equal(moved, p_x[want])))
    a = rng.integers(0, 5, size=cuda_sort.SCAN ** 2 + 77)
    dev = cuda.to_device(a)
    cuda_sort.scan(dev)
    return {"check": "sort", "sort_equal": equal, "scan_equal": bool(np.array_equal(dev.copy_to_host(), np.cumsum(a))),
            "scan_length": int(a.size)}


HELD_SCENES = (("elastic_apic_quadratic_usl", 1.0, 5), ("herschel_bulkley_explicit_and_box_guard", 0.9, 8))


def held_run(case: dict, backend: str, fraction: float, steps: int, folder: Path):
    """``steps`` steps of ``case`` on ``backend`` in held batches of up to 4 at ``fraction`` (engine/held_step.py),
    as `geompm run` takes them: (step count and time after each batch, series rows, particles by p_id, batches)."""
    import math

    from geompm.engine.runner import Runner

    c = json.loads(json.dumps(case))
    c.pop("parity_place", None)
    c["solver"].update(backend=backend, held_step={"steps": 4, "fraction": fraction})
    sim = Simulation(scene_from_dict(c, base_dir=folder))
    runner = Runner(sim, folder, [], progress=False)
    runner.start()
    clock, rows = [], []
    while sim.step_count < steps:
        runner.advance(math.inf)
        clock.append((sim.step_count, sim.time))
        rows.append(sim.series_row())
    st = sim.state
    order = np.argsort(st.p_id)
    return clock, rows, {k: getattr(st, k)[order].copy() for k in ("p_x", "p_v", "p_stress")}, runner.held_batches


def held_check(names=None) -> dict:
    """The held step on both backends (HELD_SCENES: fraction 1 ends every batch at the device's first check,
    0.9 runs them whole with an obstacle's recorded forces): the steps after each batch, the largest difference of
    the clock, of each particle field (relative to its largest magnitude) and of the series (relative to each
    column's largest magnitude)."""
    folder = Path(tempfile.mkdtemp(prefix="geompm-held-"))
    out = {"check": "held"}
    for name, fraction, steps in HELD_SCENES:
        if names is not None and name not in names:
            continue
        (ca, ra, fa, ba), (cb, rb, fb, bb) = (held_run(scenes(folder)[name], b, fraction, steps, folder)
                                              for b in ("cpu", "cuda"))
        cols = [k for k in ra[-1] if isinstance(ra[-1][k], float)]
        out[name] = {"steps_cpu": [s for s, _ in ca], "steps_cuda": [s for s, _ in cb], "batches": [ba, bb],
                     "clock": max(abs(a[1] - b[1]) for a, b in zip(ca, cb)),
                     "fields": max(compare(fa[k], fb[k]) for k in fa),
                     "series": max((compare(np.array([r[k] for r in ra]), np.array([r[k] for r in rb])) for k in cols),
                                   default=0.0),
                     "force_columns": [k for k in cols if k.startswith("dam_f")]}
    return out


def tiled_check() -> dict:
    """p2g_tiled (shared-memory tile per block) against p2g (global atomics) on the same particles: a
    compact sorted 2D block whose blocks fit the tile, folded and split, and a spread 3D cloud whose
    blocks do not (the fallback); each case reports how many blocks took the tile (from the same
    bounding boxes, on the host) and the grids' largest difference relative to each array's largest."""
    from numba import cuda

    from geompm.backend import cuda_kernels as K

    rng = np.random.default_rng(3)
    out = {"check": "tiled"}
    for name, d, n, span, split in (("2d_folded", 2, 100, 0.3, False), ("2d_split", 2, 100, 0.3, True),
                                    ("3d_spread", 3, 64, 0.4, True)):
        h, S = 0.1, 3
        p_x = 0.2 + rng.uniform(0.0, span, size=(n, d))
        if d == 2:
            p_x = p_x[np.lexsort(np.floor(p_x / h).T[::-1])]  # sorted by cell, x-major
        args = [rng.normal(size=(n, d)), rng.normal(size=(n, d, d)), rng.uniform(1, 2, n), rng.uniform(1, 2, n) * 1e-3,
                rng.normal(size=(n, 6)) * 1e3]
        lo, nloc = np.zeros(d, np.int64), np.full(d, 12, np.int64)
        base = np.floor(p_x / h - 0.5).astype(np.int64)  # the quadratic stencil's first node
        tiles = [int(np.prod(base[b:b + K.THREADS].max(0) - base[b:b + K.THREADS].min(0) + S) <= K.TILE)
                 for b in range(0, n, K.THREADS)]
        grids = []
        for kern in (K.p2g, K.p2g_tiled):
            nn = int(np.prod(nloc))
            g = [cuda.to_device(np.zeros(nn)), cuda.to_device(np.zeros((nn, d))), cuda.to_device(np.zeros((nn, d)))]
            kern[K.blocks(n), K.THREADS](S, 1, cuda.to_device(p_x), *[cuda.to_device(a) for a in args],
                                         cuda.to_device(np.zeros(d)), h, 1, cuda.to_device(lo), cuda.to_device(nloc),
                                         split, 1.0, 4.0 / h ** 2, *g, cuda.to_device(np.zeros(1)))
            grids.append([a.copy_to_host() for a in g])
        out[name] = {"blocks_tiled": sum(tiles), "blocks": len(tiles),
                     "diff": max(compare(a, b) for a, b in zip(*grids)), "mass": float(grids[1][0].sum())}
    return out


def resume_check(case: dict, folder: Path) -> dict:
    """Checkpoints across backends (issue 21, point 2): 2 steps on one backend, a checkpoint
    (engine/checkpoint.py), then the third step on the other backend, against 3 steps on the CPU."""
    from geompm.engine import checkpoint

    full, _, _, _ = run(case, "cpu", 3, folder)
    out = {"check": "resume"}
    for first, second in (("cuda", "cpu"), ("cpu", "cuda")):
        c = json.loads(json.dumps(case))
        c.pop("parity_place", None)
        c["solver"]["backend"] = first
        sim = Simulation(scene_from_dict(c, base_dir=folder))
        for _ in range(2):
            sim.step(sim.stable_dt())
        run_dir = Path(tempfile.mkdtemp(prefix="geompm-resume-"))
        checkpoint.save(run_dir, sim, {}, [])
        c["solver"]["backend"] = second
        sim2 = Simulation(scene_from_dict(c, base_dir=folder))
        checkpoint.restore(sim2, *checkpoint.load(run_dir))
        sim2.step(sim2.stable_dt())
        st = sim2.state
        order = np.argsort(st.p_id)
        flo = floors(case)
        out[f"{first}_then_{second}"] = {k: compare(full[k], getattr(st, k)[order], flo[k]) for k in full}
        out[f"{first}_then_{second}_steps"] = sim2.step_count
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("names", nargs="*")
    ap.add_argument("--steps", type=int, default=3)
    ap.add_argument("--case", action="append", default=[], metavar="FILE",
                    help="a case file to compare instead of the tiny scenes (e.g. cases/dam_break.json on a GPU)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override in every --case (a coarser grid.cell_size for the simulator)")
    ap.add_argument("--part", default="1/1", metavar="K/N",
                    help="run every N-th tiny scene from the K-th (and the checks in the last part): N processes "
                         "share the scenes (tests/cuda/test_cuda_backend.py runs 2, one per CI core)")
    ap.add_argument("--record", metavar="FILE",
                    help="write every distinct kernel launch and its argument types to FILE (simulator only), for "
                         "tests/cuda/cuda_compile.py to compile them for a GPU without one")
    a = ap.parse_args(argv)
    if a.record:
        from geompm.backend.cuda_ptx import record

        launches = record(lambda: compare_all(a))
        Path(a.record).write_text(json.dumps(launches))
        return 0
    compare_all(a)
    return 0


def compare_all(a) -> None:
    k, n = (int(v) for v in a.part.split("/"))
    folder = Path(tempfile.mkdtemp(prefix="geompm-parity-"))
    all_scenes = scenes(folder)
    for path in a.case:  # shipped cases, read from their own folder (meshes, DEMs)
        from geompm.schema.load import apply_overrides

        case = apply_overrides(json.loads(Path(path).read_text()), list(a.set))
        case.setdefault("solver", {})
        case["outputs"] = []
        all_scenes[Path(path).stem] = case
        folder = Path(path).resolve().parent
    if a.case:
        a.names = a.names or [Path(p).stem for p in a.case]
    if not a.case and not a.names and k == n:
        print(json.dumps(sort_check()), flush=True)
        print(json.dumps(resume_check(all_scenes["drucker_prager_cylinder_sorted"], folder)), flush=True)
        print(json.dumps(tiled_check()), flush=True)
        print(json.dumps(held_check(names=("elastic_apic_quadratic_usl",))), flush=True)
    for name in a.names or list(all_scenes)[k - 1::n]:
        case = all_scenes[name]
        fa, ra, sa, wa = run(case, "cpu", a.steps, folder)
        fb, rb, sb, wb = run(case, "cuda", a.steps, folder)
        series, values = {}, {}
        cols = {key: (np.array([r[key] for r in ra if key in r], float), np.array([r[key] for r in rb if key in r], float))
                for key in ra[-1]}
        for key, (col_a, col_b) in cols.items():
            # a stage's columns (label_fx, label_fn, ...) share one scale: a zero component is compared
            # against the stage's largest force, not against its own round-off
            stage = [c for k, (c, _) in cols.items() if k.rsplit("_", 1)[0] == key.rsplit("_", 1)[0]]
            series[key] = compare(col_a, col_b, max(float(np.abs(c).max()) for c in stage))
            values[key] = float(col_a[-1])
        flo = floors(case)
        out = {"scene": name, "particles": int(sa.state.n), "steps": [sa.step_count, sb.step_count],
               "time": [sa.time, sb.time], "wall_s": [round(wa, 2), round(wb, 2)],
               "fields": {k: compare(fa[k], fb[k], flo[k]) for k in fa}, "series": series, "last_row": values,
               "dtype": [str(sa.state.p_x.dtype), str(sb.state.p_x.dtype)],
               "same_order": bool(np.array_equal(sa.state.p_id, sb.state.p_id)),
               "max_displacement": float(np.abs(fa["p_x"] - sa.state.p_x0[np.argsort(sa.state.p_id)]).max())}
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    sys.exit(main())
