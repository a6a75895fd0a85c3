"""Fuzz `geompm validate` with generated STL obstacles (run as a script by tests/unit/test_mesh_fuzz.py).

Usage: python tests/support/mesh_fuzz.py FOLDER COUNT SEED.  Writes COUNT meshes and cases into FOLDER, validates
each in this process and prints one JSON line: the exit code of each case ("traceback" where geompm raised
anything but its own refusal), and the process's peak resident memory [bytes] from resource.getrusage.

The meshes: random convex hulls, cylinders (8 to 128 sections), spheres, tori, capsules, thin plates
(1e-4 to 1e-2 of the grid), open surfaces (a face removed), meshes with zero-area faces, and each at a scale
drawn from 1e-6 to 1e6, placed at the grid's centre (so that a wrong scale shows as a mesh far too large or
far too small for the grid, not as one outside it).
"""

import contextlib
import io
import json
import resource
import sys
import traceback
from pathlib import Path

import numpy as np
import trimesh

GRID = 1.0  # the cube grid's side [m]


def shapes(rng):
    """(kind, mesh) of one generated shape, about 0.3 m across before its scale."""
    kind = rng.choice(["hull", "cylinder", "sphere", "torus", "capsule", "plate", "open", "degenerate"])
    if kind == "hull":
        mesh = trimesh.convex.convex_hull(rng.normal(size=(int(rng.integers(5, 60)), 3)) * 0.1)
    elif kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=0.1, height=0.3, sections=int(rng.choice([8, 16, 32, 128])))
    elif kind == "sphere":
        mesh = trimesh.creation.icosphere(int(rng.integers(1, 5)), radius=0.15)
    elif kind == "torus":
        mesh = trimesh.creation.torus(0.12, float(rng.uniform(0.01, 0.05)))
    elif kind == "capsule":
        mesh = trimesh.creation.capsule(height=0.2, radius=0.05)
    elif kind == "plate":
        mesh = trimesh.creation.box([0.3, 0.3, 0.3 * 10 ** float(rng.uniform(-4, -2))])
    elif kind == "open":
        box = trimesh.creation.box([0.3, 0.2, 0.1])
        mesh = trimesh.Trimesh(box.vertices, box.faces[1:], process=False)
    else:
        box = trimesh.creation.box([0.3, 0.2, 0.1])
        mesh = trimesh.Trimesh(box.vertices, np.vstack([box.faces, [[0, 0, 1], [2, 3, 3]]]), process=False)
    if rng.random() < 0.3:
        mesh = mesh.subdivide()
    return kind, mesh


def case(stl: str, centre: list[float]) -> dict:
    return {
        "name": "fuzz", "dimension": 3,
        "grid": {"origin": [0.0, 0.0, 0.0], "extent": [GRID] * 3, "cell_size": 0.1},
        "time": {"end": 0.01}, "gravity": [0.0, -9.81, 0.0],
        "materials": {"soil": {"model": "linear_elastic", "density": 2000.0, "youngs_modulus": 1e6,
                               "poisson_ratio": 0.3}},
        "bodies": [{"material": "soil", "geometry": {"type": "box", "min": [0.0, 0.8, 0.0],
                                                     "max": [0.2, 1.0, 0.2]}}],
        "obstacles": [{"type": "rigid_mesh", "file": stl, "translate": centre}],
        "outputs": [],
    }


def main(folder: Path, count: int, seed: int) -> None:
    from geompm.cli import main as geompm

    rng = np.random.default_rng(seed)
    results = []
    for k in range(count):
        kind, mesh = shapes(rng)
        scale = 10 ** float(rng.choice([-6, -3, -1, 0, 0, 0, 1, 3, 6]))
        mesh.apply_scale(scale)
        mesh.apply_translation(-mesh.bounds.mean(axis=0))
        stl = folder / f"mesh{k}.stl"
        mesh.export(stl)
        path = folder / f"case{k}.json"
        path.write_text(json.dumps(case(stl.name, [0.5 * GRID, 0.45 * GRID, 0.5 * GRID])))
        out, err = io.StringIO(), io.StringIO()
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                code = geompm(["validate", str(path)])
        except BaseException:  # noqa: BLE001 - the point is to see any failure
            code = "traceback"
            err.write(traceback.format_exc())
        results.append({"case": k, "kind": kind, "scale": scale, "faces": len(mesh.faces), "code": code,
                        "said": (err.getvalue() or out.getvalue()).strip().splitlines()[-1:]})
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(json.dumps({"results": results, "peak_rss": rss}))


if __name__ == "__main__":
    main(Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]))
