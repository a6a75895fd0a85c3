"""Load a case: read JSON, apply ``--set`` overrides, validate in two passes.

Pass 1 validates the core keys with ``geompm.schema.case.Case``.  Pass 2
resolves every plugin name through the registry and validates its parameters
with the plugin's ``Params`` model, then checks what needs the whole case
(vector lengths against ``dimension``, bodies inside the grid, material names,
mesh files).  Every problem is collected with its JSON path and raised at once
as ``CaseError``; nothing is computed before the case is valid.
"""

from __future__ import annotations

import copy
import difflib
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from pydantic import ValidationError

from geompm.contract import registry
from geompm.errors import CaseError, join_path
from geompm.files.atomic import case_relative, unreadable_file
from geompm.kernels.shape import KIND
from geompm.kernels.stencil import LINEAR_APIC, linear_apic
from geompm.mpm.memory import available_memory, grid_bytes, particle_bytes, window_nodes
from geompm.schema.case import Case, DampingSpec, MaterialSpec, OutputSpec, PluginSpec
from geompm.schema.errors import format_validation_error
from geompm.schema.held_step import held_step_problems
from geompm.schema.inflows import inflow_particles, inflow_problems
from geompm.schema.pore_water import pore_water_problems
from geompm.schema.scheme import resolve_scheme
from geompm.schema.raw_checks import TOO_DEEP, merge, raw_problems
from geompm.schema.triggers import trigger_problems


@dataclass
class Resolved:
    """One plugin entry of the case, resolved: class, validated params, JSON path."""

    cls: type
    params: object
    path: str
    label: str


@dataclass
class LoadedCase:
    case: Case
    base_dir: Path
    raw: dict
    materials: dict[str, Resolved] = field(default_factory=dict)
    boundaries: list[Resolved] = field(default_factory=list)
    obstacles: list[Resolved] = field(default_factory=list)
    damping: list[Resolved] = field(default_factory=list)
    outputs: list[Resolved] = field(default_factory=list)
    #: the time-step scheme's class (schema/scheme.py), None until resolved
    scheme: type | None = None
    #: each inflow's hydrograph (sources/hydrograph.Hydrograph; None where it cannot be read), in case order
    hydrographs: list = field(default_factory=list)
    #: (JSON path, message): settings the case gives that do nothing (ineffective_settings)
    warnings: list[tuple[str, str]] = field(default_factory=list)


def read_json(path: str | Path) -> dict:
    """The JSON object in a case file; CaseError with one clear line for anything else.

    UTF-8 (with or without a byte-order mark), UTF-16 and UTF-32 are read;
    an empty file, malformed JSON, deep nesting, an integer literal too long to
    convert, another encoding or a folder given as the file are refused."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise CaseError([("", f"cannot read case file '{path}': {exc.strerror or exc}")]) from None
    if not data.strip():
        raise CaseError([("", f"{path}: the case file is empty; a case is a JSON object {{...}}")])
    try:
        raw = json.loads(data)
    except json.JSONDecodeError as exc:
        raise CaseError([("", f"{path}: malformed JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}")]) from None
    except UnicodeDecodeError as exc:
        raise CaseError([("", f"{path}: not UTF-8 text (byte {data[exc.start]:#04x} at offset {exc.start}); "
                              "save the case as UTF-8")]) from None
    except RecursionError:
        raise CaseError([("", f"{path}: the JSON is nested too deeply to read; a geompm case needs at most "
                              "about 6 levels")]) from None
    except ValueError:  # an integer literal of more than 4300 digits
        raise CaseError([("", f"{path}: a number with thousands of digits; give numbers within "
                              "+/-1.8e308")]) from None
    if not isinstance(raw, dict):
        raise CaseError([("", f"{path}: the case must be a JSON object {{...}}, not {type(raw).__name__}")])
    return raw


def _override_value(key: str, text: str):
    """A --set value: JSON if it parses, else the text itself."""
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text
    except (RecursionError, ValueError):
        raise CaseError([(key, f"--set {key}: the value cannot be read (nested too deeply or too long)")]) from None


def _existing_keys(node) -> str:
    """'; it has: a, b, c' (the keys or indices the case has at the level where a --set path failed)."""
    if isinstance(node, dict) and node:
        return "; it has: " + ", ".join(sorted(str(k) for k in node))
    if isinstance(node, list) and node:
        return f"; it has indices 0 to {len(node) - 1}"
    return ""


def apply_overrides(raw: dict, sets: list[str] | tuple[str, ...]) -> dict:
    """Apply ``dotted.key=value`` overrides; value parsed as JSON, else kept as text."""
    raw = copy.deepcopy(raw)
    for item in sets:
        if "=" not in item:
            raise CaseError([(item, "a --set must look like dotted.key=value")])
        key, text = item.split("=", 1)
        parts = key.split(".")
        if not key or any(not part for part in parts):
            raise CaseError([(key, f"--set {item}: the key must be a dotted path like grid.cell_size")])
        value = _override_value(key, text)
        node = raw
        for i, part in enumerate(parts[:-1]):
            nxt = int(part) if isinstance(node, list) and part.isdigit() else part
            try:
                node = node[nxt]
            except (KeyError, IndexError, TypeError):
                raise CaseError([(join_path(*parts[: i + 1]), f"--set {key}: no such key in the case"
                                  + _existing_keys(node))]) from None
        last = parts[-1]
        if isinstance(node, list):
            if not last.isdigit() or int(last) >= len(node):
                raise CaseError([(key, f"--set {key}: index out of range (the list has {len(node)} entries)")])
            node[int(last)] = value
        elif isinstance(node, dict):
            node[last] = value
        else:
            raise CaseError([(key, f"--set {key}: '{join_path(*parts[:-1])}' is a {type(node).__name__}, "
                                   "not an object or a list")])
    return raw


def _plugin_params(kind, key, spec, path, case, problems) -> Resolved | None:
    name = getattr(spec, key)
    try:
        cls = registry.get(kind, name, join_path(path, key))
    except CaseError as exc:
        problems.extend(exc.problems)
        return None
    if case is not None and kind in BACKEND_KINDS and case.solver.backend not in cls.backends:
        problems.append((join_path(path, key), f"plugin '{name}' runs on the {' and '.join(cls.backends)} backend(s), "
                                               f"not on solver.backend '{case.solver.backend}': its per-item "
                                               "functions have not been checked on it (the class attribute "
                                               "'backends'); use solver.backend \"cpu\""))
    extra = dict(spec.model_extra or {})
    try:
        params = cls.Params.model_validate(extra)
    except ValidationError as exc:
        problems.extend(format_validation_error(exc, cls.Params, prefix=path.split(".")))
        return None
    if case is not None:
        for sub, msg in cls.check(params, case):
            problems.append((join_path(path, sub), msg))
    label = getattr(spec, "name", None) or f"{name}{path.rsplit('.', 1)[-1]}"
    return Resolved(cls, params, path, label)


def _check_vec(vec, dim, path, problems, positive=False):
    if vec is None:
        return
    if len(vec) != dim:
        problems.append((path, f"must have {dim} entries (one per dimension), got {len(vec)}"))
    elif positive and any(v <= 0 for v in vec):
        problems.append((path, "every entry must be > 0"))


MAX_CELLS_PER_AXIS = 2**31 - 1  # node indices are int32-safe
MAX_COORD_PER_CELL = 1e9  # |x| / h: beyond it a double resolves a cell to fewer than ~7 digits


def _check_grid_size(grid, problems) -> None:
    """Cells per axis within index range, and coordinates that a double resolves inside a cell."""
    h = grid.cell_size
    if any(e < 2 * h for e in grid.extent):
        problems.append(("grid.cell_size", "must be at most half of every grid extent"))
    cells = max(e / h for e in grid.extent)
    if not cells <= MAX_CELLS_PER_AXIS:
        problems.append(("grid.cell_size", f"gives {cells:.3g} cells along one axis (at most "
                                           f"{MAX_CELLS_PER_AXIS}); check the units of cell_size and extent [m]"))
    reach = max(max(abs(o), abs(o + e)) for o, e in zip(grid.origin, grid.extent))
    if not reach / h <= MAX_COORD_PER_CELL:
        problems.append(("grid.origin", f"coordinates up to {reach:.3g} m with cells of {h:g} m cannot be resolved "
                                        "in double precision; shift the scene so the grid lies near the origin"))


def _check_body(i, body, case: Case, base_dir: Path, problems):
    dim = case.dimension
    path = f"bodies.{i}"
    if body.material not in case.materials:
        close = difflib.get_close_matches(body.material, list(case.materials), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        problems.append((f"{path}.material", f"no material named '{body.material}' in 'materials'{hint}"))
    _check_vec(body.velocity, dim, f"{path}.velocity", problems)
    _check_vec(body.surface_normal, dim, f"{path}.surface_normal", problems)
    if body.surface_normal is not None and len(body.surface_normal) == dim == len(case.gravity):
        if body.initial_stress != "geostatic":
            problems.append((f"{path}.surface_normal", "only used with \"initial_stress\": \"geostatic\"; "
                                                       "remove it or set initial_stress"))
        elif sum(n * g for n, g in zip(body.surface_normal, case.gravity)) >= 0.0:
            problems.append((f"{path}.surface_normal", "must point out of the ground (against gravity): "
                                                       "its dot product with 'gravity' must be negative"))
    if body.velocity_profile.axis >= dim:
        problems.append((f"{path}.velocity_profile.axis", f"must be < {dim} in a {dim}D case"))
    geom = body.geometry
    gpath = f"{path}.geometry"
    lo = case.grid.origin
    hi = [o + e for o, e in zip(case.grid.origin, case.grid.extent)]
    if geom.type == "box":
        _check_vec(geom.min, dim, f"{gpath}.min", problems)
        _check_vec(geom.max, dim, f"{gpath}.max", problems)
        if len(geom.min) == dim == len(geom.max) and len(lo) == dim:
            if any(a >= b for a, b in zip(geom.min, geom.max)):
                problems.append((gpath, "every entry of 'min' must be below the same entry of 'max'"))
            if any(a < l or b > h for a, b, l, h in zip(geom.min, geom.max, lo, hi)):
                problems.append((gpath, f"box {geom.min}..{geom.max} lies outside the grid {lo}..{hi}"))
    elif geom.type == "polygon":
        if dim == 3 and geom.extrude is None:
            problems.append((f"{gpath}.extrude", "a polygon in a 3D case needs 'extrude': [z_min, z_max]"))
        elif dim == 3 and not lo[2] <= geom.extrude[0] < geom.extrude[1] <= hi[2]:
            problems.append((f"{gpath}.extrude", f"[z_min, z_max] = {geom.extrude} must be increasing and lie "
                                                 f"inside the grid's z range {lo[2]:g}..{hi[2]:g}"))
        for j, v in enumerate(geom.vertices):
            if len(v) != 2:
                problems.append((f"{gpath}.vertices.{j}", "a polygon vertex has 2 entries (x, y)"))
            elif len(lo) >= 2 and not (lo[0] <= v[0] <= hi[0] and lo[1] <= v[1] <= hi[1]):
                problems.append((f"{gpath}.vertices.{j}", f"vertex {v} lies outside the grid"))
    elif geom.type == "stl":
        if dim != 3:
            problems.append((f"{gpath}.type", "an 'stl' body needs a 3D case; use 'polygon' in 2D"))
        problem = unreadable_file(case_relative(base_dir, geom.file), geom.file)
        if problem:
            problems.append((f"{gpath}.file", f"mesh {problem}"))
    else:  # release bodies from GIS files (setup/release.py)
        if dim != 3:
            problems.append((f"{gpath}.type", f"a '{geom.type}' body needs a 3D case (it fills a DEM surface)"))
        if geom.type == "release_polygon" and (geom.thickness is None) == (geom.thickness_attribute is None):
            problems.append((gpath, "give exactly one of 'thickness' [m] and 'thickness_attribute'"))
        keys = ("surface", "failure_surface") if geom.type == "between_surfaces" else ("file", "dem")
        for key in keys:
            name = getattr(geom, key)
            problem = unreadable_file(case_relative(base_dir, name), name)
            if problem:
                problems.append((f"{gpath}.{key}", problem))


_PLUGIN_LISTS = (
    ("boundaries", "boundaries", "type", PluginSpec),
    ("obstacles", "obstacles", "type", PluginSpec),
    ("damping", "damping", "model", DampingSpec),
    ("outputs", "writers", "writer", OutputSpec),
)


#: the plugin kinds whose functions a backend compiles (writers run on the host)
BACKEND_KINDS = ("materials", "boundaries", "obstacles", "damping")


#: float32 spacing at a coordinate X is at most X * 2^-23; positions must resolve this fraction of a cell
FLOAT32_CELL_FRACTION = 1.0e-3


def _check_precision(case: Case, problems) -> None:
    """float32 positions only where float32 resolves 1e-3 of a cell everywhere on the grid."""
    if case.solver.precision != "float32":
        return
    o, e = np.asarray(case.grid.origin, float), np.asarray(case.grid.extent, float)
    far = float(np.max(np.maximum(np.abs(o), np.abs(o + e))))
    ulp = far * 2.0 ** -23
    h = case.grid.cell_size
    if ulp > FLOAT32_CELL_FRACTION * h:
        problems.append(("solver.precision", f"float32 positions are spaced up to {ulp:.3g} m at the grid's far "
                         f"corner ({far:.4g} m from the coordinate origin), more than {FLOAT32_CELL_FRACTION:g} of "
                         f"the {h:g} m cell; use \"float64\", or a grid within {FLOAT32_CELL_FRACTION * h * 2**23:.4g} "
                         "m of the origin"))


def _backend_problem(case: Case) -> str | None:
    """Why solver.backend cannot run here, or None."""
    if case.solver.backend != "cuda":
        return None
    import importlib.util

    if importlib.util.find_spec("numba_cuda") is None:
        return "needs numba-cuda, which is not installed: pip install 'geompm[cuda]'"
    from geompm.backend.cuda_loops import simulated

    if simulated():
        return None
    from numba import cuda

    if not cuda.is_available():
        return ("no CUDA GPU or driver found (numba.cuda.is_available() is False); use solver.backend \"cpu\", "
                "or set NUMBA_ENABLE_CUDASIM=1 to run on numba-cuda's simulator (slow: for tests)")
    return None


def _plugin_pass(raw: dict, case, loaded, problems) -> None:
    """Resolve and validate every plugin entry that is well formed in ``raw``.

    Runs even when pass 1 failed (``case`` is None then), so a user sees the
    plugin-parameter problems together with the core ones.
    """
    mats = raw.get("materials")
    for name, entry in (mats.items() if isinstance(mats, dict) else ()):
        try:
            spec = MaterialSpec.model_validate(entry)
        except ValidationError:
            continue  # already reported by pass 1
        r = _plugin_params("materials", "model", spec, f"materials.{name}", case, problems)
        if r is not None and loaded is not None:
            r.label = name
            loaded.materials[name] = r
    for attr, kind, key, model in _PLUGIN_LISTS:
        items = raw.get(attr)
        for i, entry in enumerate(items if isinstance(items, list) else ()):
            try:
                spec = model.model_validate(entry)
            except ValidationError:
                continue
            r = _plugin_params(kind, key, spec, f"{attr}.{i}", case, problems)
            if r is not None and loaded is not None:
                getattr(loaded, attr).append(r)


def parse_case(raw: dict, base_dir: str | Path = ".") -> LoadedCase:
    """Validate a raw case dict (both passes); CaseError lists every problem."""
    pre = raw_problems(raw)
    if pre:  # nothing numeric runs on NaN, Infinity or a runaway nesting: report them and the schema's problems
        if not any(m.startswith(TOO_DEEP) for _, m in pre):
            try:
                Case.model_validate(raw)
            except ValidationError as exc:
                pre = merge(pre, format_validation_error(exc, Case))
        raise CaseError(pre)
    return _parse_valid_numbers(raw, Path(base_dir))


def _parse_valid_numbers(raw: dict, base_dir: Path) -> LoadedCase:
    try:
        case = Case.model_validate(raw)
    except ValidationError as exc:
        problems = format_validation_error(exc, Case)
        _plugin_pass(raw, None, None, problems)
        raise CaseError(problems) from None

    problems: list[tuple[str, str]] = []
    dim = case.dimension
    _check_vec(case.grid.origin, dim, "grid.origin", problems)
    _check_vec(case.grid.extent, dim, "grid.extent", problems, positive=True)
    _check_vec(case.gravity, dim, "gravity", problems)
    if problems:  # the body and plugin checks below need grid vectors of the right length
        raise CaseError(problems)
    _check_grid_size(case.grid, problems)
    if case.time.dt_max is not None and case.time.dt is not None:
        problems.append(("time.dt", "give either a fixed 'dt' or 'dt_max', not both"))
    if case.solver.transfer == "mls" and case.grid.shape_function == "linear":
        problems.append(("solver.transfer", "'mls' needs a constant APIC inertia D, i.e. grid.shape_function "
                                            "'quadratic' or 'cubic'; use 'flip' or 'pic' with 'linear'"))
    for i, body in enumerate(case.bodies):
        _check_body(i, body, case, base_dir, problems)
    _check_precision(case, problems)
    why = _backend_problem(case)
    if why:
        problems.append(("solver.backend", why))
    loaded = LoadedCase(case=case, base_dir=base_dir, raw=raw, warnings=ineffective_settings(raw, case))
    _plugin_pass(raw, case, loaded, problems)
    problems.extend(duplicate_labels(loaded))
    problems.extend(probe_problems(case, loaded))
    problems.extend(inflow_problems(case, loaded))
    problems.extend(pore_water_problems(case, loaded))
    problems.extend(trigger_problems(case, loaded))
    loaded.scheme, why = resolve_scheme(case)
    problems.extend(why)
    if loaded.scheme is not None:
        if case.inflows and loaded.scheme.fields:
            problems.append(("inflows", f"the '{loaded.scheme.name}' step carries particle fields of its own "
                                        f"({', '.join(f.name for f in loaded.scheme.fields)}) that an inflow does "
                                        "not set: inflows take dry or fluid materials"))
        problems.extend(loaded.scheme.problems(case, loaded))
        problems.extend(held_step_problems(case, loaded))
        loaded.warnings.extend(loaded.scheme.warnings(case))
    loaded.warnings.extend(plausibility_warnings(loaded))
    if not problems:
        _check_memory(case, problems, loaded.scheme, inflow_particles(case, loaded))
    if problems:
        raise CaseError(problems, warnings=loaded.warnings)
    return loaded


def plausibility_warnings(loaded) -> list[tuple[str, str]]:
    """(JSON path, sentence) for every material parameter outside the range its law declares plausible
    (materials/plausible.py): a value that is valid but looks like a wrong unit."""
    from geompm.materials.plausible import warnings_for

    return [(f"materials.{name}.{field}", text) for name, r in loaded.materials.items()
            for field, text in warnings_for(getattr(r.cls, "plausible", ()), r.params)]


def ineffective_settings(raw: dict, case: Case) -> list[tuple[str, str]]:
    """Settings the case gives explicitly that would do nothing, and APIC with linear hats in a dry case
    (unstable in motion, stencil.LINEAR_APIC), as (path, message): `geompm validate`
    and `geompm run` warn, so a user never believes a parameter acts when it does not.  Warned, not
    refused: a study that varies time.dt or solver.transfer over a case legitimately produces them."""
    out = []
    solver, time = raw.get("solver") or {}, raw.get("time") or {}
    if "flip_ratio" in solver and case.solver.transfer != "flip":
        out.append(("solver.flip_ratio", f"applies to transfer 'flip' only (transfer is '{case.solver.transfer}'); "
                                         "set solver.transfer to \"flip\" or remove flip_ratio"))
    if "p2g" in solver and case.solver.backend != "cuda":
        out.append(("solver.p2g", f"applies to solver.backend 'cuda' only (backend is '{case.solver.backend}': "
                                  "the CPU adds into private grids per thread); remove it"))
    if "particle_pass" in solver and case.solver.backend != "cuda":
        out.append(("solver.particle_pass", f"applies to solver.backend 'cuda' only (backend is "
                                            f"'{case.solver.backend}': the CPU runs the passes apart); remove it"))
    if "pore_pressure_smoothing" in solver and all(m.pore_water is None for m in case.materials.values()):
        out.append(("solver.pore_pressure_smoothing", "applies to saturated materials only (none has 'pore_water'); "
                                                      "remove it"))
    if "cfl" in time and case.time.dt is not None:
        out.append(("time.cfl", f"has no effect with a fixed time.dt = {case.time.dt:g} s; remove one of them "
                                "(the adaptive step uses cfl, a fixed dt replaces it)"))
    dry = all(m.pore_water is None for m in case.materials.values())  # saturated: refused (the scheme's check)
    if dry and linear_apic(case):
        out.append(("solver.transfer", LINEAR_APIC + " (a quasi-static run, a slope's strength reduction, is "
                                                     "verified with it)"))
    if case.dimension == 2:
        for i, body in enumerate(raw.get("bodies") or []):
            geo = body.get("geometry") if isinstance(body, dict) else None
            if isinstance(geo, dict) and geo.get("type") == "polygon" and "extrude" in geo:
                out.append((f"bodies.{i}.geometry.extrude", "applies to 3D cases only (a 2D polygon is the "
                                                            "plane-strain section itself); remove it"))
    return out


def duplicate_labels(loaded) -> list[tuple[str, str]]:
    """Two stages with one label would write the same series.csv columns and checkpoint state."""
    out, seen = [], {}
    for r in loaded.boundaries + loaded.obstacles + loaded.damping:
        if r.label in seen:
            out.append((f"{r.path}.name" if r.path.startswith("obstacles") else r.path,
                        f"the label '{r.label}' is already used by {seen[r.label]}: their series columns and "
                        "checkpoint state would overwrite each other; give each a distinct \"name\""))
        else:
            seen[r.label] = r.path
    return out


def probe_problems(case: Case, loaded) -> list[tuple[str, str]]:
    """Probes' vectors, names (distinct from each other and from every stage's label) and the probes that
    contact surfaces name."""
    out = []
    labels = {r.label: r.path for r in loaded.boundaries + loaded.obstacles + loaded.damping}
    names = {}
    for i, pr in enumerate(case.probes):
        path = f"probes.{i}"
        for key in ("point", "direction"):
            v = getattr(pr, key)
            if v is not None and len(v) != case.dimension:
                out.append((f"{path}.{key}", f"must have {case.dimension} entries (one per dimension)"))
        if pr.direction is not None and not any(abs(c) > 0 for c in pr.direction):
            out.append((f"{path}.direction", "must not be the zero vector"))
        if pr.direction is None and not any(abs(c) > 0 for c in case.gravity):
            out.append((f"{path}.direction", "gravity is zero: give the column's axis, e.g. the bed normal"))
        if pr.name in names or pr.name in labels:
            out.append((f"{path}.name", f"'{pr.name}' is already used by {names.get(pr.name) or labels[pr.name]}: "
                                        "series columns would overwrite each other; give the probe a distinct name"))
        names.setdefault(pr.name, path)
    for r in loaded.obstacles:
        want = getattr(r.params, "probe", None)
        if want is not None and want not in names:
            known = ", ".join(f"'{n}'" for n in names) or "none"
            out.append((f"{r.path}.probe", f"no probe named '{want}' (probes: {known}); add it to \"probes\" "
                                           "or remove \"probe\""))
    if case.probes and case.solver.backend != "cpu":
        out.append(("probes", f"probes run on the CPU backend only (solver.backend is '{case.solver.backend}'); "
                              "remove them or use \"cpu\""))
    return out


def _check_memory(case: Case, problems, scheme=None, added: float = 0.0) -> None:
    """Refuse a case whose particles and grid window would not fit in the available memory.

    Particle counts come from each body's bounding box (an upper bound), before
    anything is seeded, and ``added`` the inflows add over the run (their window: the whole grid)."""
    dim, h = case.dimension, case.grid.cell_size
    particles, lo, hi = added, None, None
    if added:
        lo = np.asarray(case.grid.origin, float)
        hi = lo + np.asarray(case.grid.extent, float)
    for body in case.bodies:
        g = body.geometry
        if g.type == "box":
            blo, bhi = np.asarray(g.min, float), np.asarray(g.max, float)
        elif g.type == "polygon":
            v = np.asarray(g.vertices, float)
            blo, bhi = v.min(axis=0), v.max(axis=0)
            if dim == 3:
                blo, bhi = np.r_[blo, g.extrude[0]], np.r_[bhi, g.extrude[1]]
        else:
            continue  # a mesh body: its size is known only after loading it
        particles += float(np.prod(np.maximum(bhi - blo, 0.0) / h * body.particles_per_cell + 1))
        lo = blo if lo is None else np.minimum(lo, blo)
        hi = bhi if hi is None else np.maximum(hi, bhi)
    if lo is None:
        return
    nodes = window_nodes(lo, hi, h)
    extra = scheme.node_bytes(dim, KIND[case.grid.shape_function]) if scheme is not None else 0
    need = particles * particle_bytes(dim) + grid_bytes(nodes, dim) + nodes * extra
    have = available_memory()
    if have is not None and need > have:
        problems.append(("grid.cell_size", f"the case needs about {need / 2**30:.1f} GiB "
                                           f"({particles:.3g} particles) but {have / 2**30:.1f} GiB is available; "
                                           "raise cell_size or lower particles_per_cell"))


def load_case(path: str | Path, sets=()) -> LoadedCase:
    """Read, override and validate a case file."""
    path = Path(path)
    raw = apply_overrides(read_json(path), list(sets))
    return parse_case(raw, base_dir=path.resolve().parent)
