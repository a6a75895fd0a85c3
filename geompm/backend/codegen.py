"""Backend loops generated around a plugin's per-item functions, written as modules so numba caches them.

A plugin gives ``@njit`` functions for one item (a particle's stress update,
a node's contact rule: materials/base.py, contract/stages.py); the backend owns the
loops that run them (backend/cpu_loops.py for laws, backend/cpu_stage_loops.py
for stages).  ``loops(kind, functions, body, names)`` returns those loops:

- ``functions`` maps an alias to a plugin's dispatcher; the loop module imports
  each one and compiles it into the loops as ``alias`` with
  ``inline="always"`` and the plugin's own fastmath flags (a call per item
  would reference-count the per-item views across the call: the
  Drucker-Prager update ran at 27 ns per particle against 13 ns inlined);
- ``body`` is the loops' source text; ``{fm_<alias>}`` in it stands for that
  function's fastmath option (a loop that takes the law's flags);
- ``names`` are the loops returned, in order.

The loops are written as a small module per plugin function set in geompm's
kernel folder and imported from there, because numba caches compiled code
only for functions defined in a source file, and a loop made by a closure
over the plugin would be compiled afresh in every process (a closure's cache
key includes the plugin object, whose identity changes from process to
process).  The file's name carries a hash of the functions' modules, names
and source files, of every geompm source file (the helpers the functions
inline live there, and numba's cache checks only the loop file itself: an
edited helper once ran stale compiled code) and of the loop source, so
editing a plugin or geompm writes a new loop file and numba compiles it
again; unchanged sources reuse the cache.

Functions defined where they cannot be imported by name (inside a function,
in ``__main__``) get the same loops as closures, compiled in-process without
the cache.

The folder is ``$GEOMPM_KERNEL_DIR``, else ``geompm-loops`` under
``$NUMBA_CACHE_DIR`` when that is set, else ``$XDG_CACHE_HOME/geompm/loops``
(``~/.cache/geompm/loops``); if none can be written, a fresh temporary folder.
geompm writes only files it names ``loop_*.py`` whose first line is its own
header, and replaces one only if that header is there (atomic replace
through a temporary file of its own).
"""

from __future__ import annotations

import hashlib
import importlib.util
import inspect
import os
import sys
import tempfile
from pathlib import Path

from geompm.files.atomic import user_mode

HEADER = "# geompm generated kernel loop: do not edit (geompm/backend/codegen.py)\n"

_CACHE: dict = {}
_FOLDER: list = []
_DIGEST: list = []


def kernel_folder() -> Path:
    if _FOLDER:
        return _FOLDER[0]
    env = os.environ
    if env.get("GEOMPM_KERNEL_DIR"):
        candidates = [Path(env["GEOMPM_KERNEL_DIR"])]
    elif env.get("NUMBA_CACHE_DIR"):
        candidates = [Path(env["NUMBA_CACHE_DIR"]) / "geompm-loops"]
    else:
        base = Path(env.get("XDG_CACHE_HOME") or Path.home() / ".cache")
        candidates = [base / "geompm" / "loops"]
    for folder in candidates:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if os.access(folder, os.W_OK | os.X_OK):
            _FOLDER.append(folder)
            return folder
    _FOLDER.append(Path(tempfile.mkdtemp(prefix="geompm-loops-")))
    return _FOLDER[0]


def importable(fn) -> bool:
    py = getattr(fn, "py_func", fn)
    mod = sys.modules.get(py.__module__)
    return (mod is not None and py.__module__ != "__main__" and "<locals>" not in py.__qualname__
            and getattr(mod, py.__name__, None) is fn and getattr(mod, "__file__", None) is not None)


def fastmath_source(fn) -> str:
    """A dispatcher's fastmath option as source text (False, True or a set of LLVM flags)."""
    flags = fn.targetoptions.get("fastmath", False)
    if isinstance(flags, (set, frozenset)) or (hasattr(flags, "flags") and not isinstance(flags, bool)):
        return repr(set(getattr(flags, "flags", flags)))
    return repr(bool(flags))


def _preamble(functions: dict) -> str:
    """Each plugin function compiled into the loops, as ``alias``."""
    return "".join(f'{alias} = njit(inline="always", fastmath={fastmath_source(fn)})(_src_{alias}.py_func)\n'
                   for alias, fn in functions.items())


def _source(functions: dict, body: str) -> str:
    return "\n" + _preamble(functions) + body.format(**{f"fm_{a}": fastmath_source(f) for a, f in functions.items()})


def _closure(functions: dict, body: str, names):
    """The loops for functions that cannot be imported by name: compiled here, not cached (numba
    caches only functions of a source file)."""
    import numpy as np
    from numba import njit, prange

    namespace = {"np": np, "njit": njit, "prange": prange}
    namespace.update({f"_src_{a}": fn for a, fn in functions.items()})
    exec(_source(functions, body).replace(", cache=True", ""), namespace)
    return tuple(namespace[n] for n in names)


def write_if_changed(path: Path, text: str) -> None:
    if path.is_file():
        old = path.read_text()
        if old == text:
            return
        if not old.startswith(HEADER):
            raise RuntimeError(f"{path} exists and was not written by geompm: remove it or set GEOMPM_KERNEL_DIR")
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".loop-", suffix=".py")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.chmod(tmp, user_mode())
    os.replace(tmp, path)  # our own temporary file onto our own loop file


def loops(kind: str, functions: dict, body: str, names: tuple[str, ...]):
    """The named loops of ``body`` compiled around ``functions`` (alias -> dispatcher)."""
    key = (kind, tuple(functions.items()))
    if key in _CACHE:
        return _CACHE[key]
    if all(importable(fn) for fn in functions.values()):
        out = _module(kind, functions, body, names)
    else:
        out = _closure(functions, body, names)
    _CACHE[key] = out
    return out


def _geompm_digest() -> bytes:
    """sha256 of every source file of the geompm package: the helpers a plugin's function inlines
    (contact rules, the Jaumann increment, the Tait EOS) live there, and numba's cache checks only the
    loop file itself, so an edited helper must change the loop file's name too."""
    if not _DIGEST:
        root = Path(__file__).resolve().parents[1]
        h = hashlib.sha256()
        for f in sorted(root.rglob("*.py")):
            h.update(f.read_bytes())
        _DIGEST.append(h.digest())
    return _DIGEST[0]


def _module(kind, functions, body, names):
    pys = {a: fn.py_func for a, fn in functions.items()}
    files = sorted({inspect.getsourcefile(p) for p in pys.values()})
    digest = hashlib.sha256(b"".join(Path(f).read_bytes() for f in files) + _geompm_digest()).hexdigest()[:16]
    idents = [f"{p.__module__}.{p.__name__}" for p in pys.values()]
    head = (HEADER + f"# {kind}: {', '.join(idents)}; plugin source sha256 {digest}\n"
            "import numpy as np\nfrom numba import njit, prange\n\n"
            + "".join(f"from {p.__module__} import {p.__name__} as _src_{a}\n" for a, p in pys.items()))
    text = head + _source(functions, body)
    # the name carries the functions' identity, their source digest and the loop source: two installs of
    # different sources never write the same file, and an edit gets a new file (so a fresh compilation)
    ident = "|".join(idents) + f"|{digest}|" + hashlib.sha256(body.encode()).hexdigest()
    first = pys[next(iter(pys))]
    stem = (f"loop_{kind}_{first.__module__.replace('.', '_')}_{first.__name__}_"
            f"{hashlib.sha256(ident.encode()).hexdigest()[:12]}")
    path = kernel_folder() / f"{stem}.py"
    write_if_changed(path, text)
    name = f"geompm_loops.{stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # numba's cache rebuilds the loop's environment by module name
    spec.loader.exec_module(module)
    return tuple(getattr(module, n) for n in names)
