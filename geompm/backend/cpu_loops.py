"""The CPU backend's loops over a material block, generated from the law's per-particle functions.

A law gives two ``@njit`` functions for one particle (materials/base.py):

    particle_stress(prm, dt, L, rho, s, state)   # L (3, 3), s (6,), state (k,) views; in place
    particle_wave_speed(prm, rho) -> float        # [m/s]

and the backend owns the loops that run them over a block:

    stress_block(prm, dt, p_L, p_rho, p_stress, p_state) -> max |L_ii| over the block
    wave_speed_block(prm, p_rho) -> float     the law's speed at the block's lowest and highest
                                              density, the larger of the two

The stress loop returns the largest stretching rate |L_ii| of the block as a
by-product (the particles' L is in cache there), for the next step's
strain-increment limit (engine/timestep.py), which would otherwise cost a
pass of its own over p_L (3 ns per particle, 4 % of a dp2d step); the three
diagonal entries cost 0.8 ns per particle there, all nine 2.1 ns.  The wave
speed is evaluated at two densities only, so ``particle_wave_speed`` must be
monotone in the density (elastic: decreasing; Tait: increasing;
``geompm.testing`` checks it): a per-particle evaluation of the Tait speed,
a power per particle, cost 107 ns per particle on fluid3d, more than the
rest of the step.

The law's functions are compiled into the loops (``inline="always"`` on
their Python source, with the law's own fastmath flags): with a call per
particle instead, the views ``L[p]``, ``s[p]``, ``state[p]`` are reference
counted across the call and the Drucker-Prager update ran at 27 ns per
particle against 13 ns for the same arithmetic in one function (dp2d,
2 threads).  The loops are written as a small
module per law (source below) in geompm's kernel folder and imported from
there, because numba caches compiled code only for functions defined in a
source file, and a loop made by a closure over the law would be compiled
afresh in every process (a closure's cache key includes the law object, whose
identity changes from process to process).  The file's name carries a hash of
the law's module, name and source file, so editing a law writes a new loop
file and numba compiles it again; an unchanged law reuses the cache.

A law defined where it cannot be imported by name (inside a function, in
``__main__``) gets the same loops as closures, compiled in-process without
the cache.

The folder is ``$GEOMPM_KERNEL_DIR``, else ``geompm-loops`` under
``$NUMBA_CACHE_DIR`` when that is set, else ``$XDG_CACHE_HOME/geompm/loops``
(``~/.cache/geompm/loops``); if none can be written, a fresh temporary folder.
geompm writes only files it names ``loop_*.py`` whose first line is its own
header, and replaces one only if that header is there (fileio-style atomic
replace through a temporary file).
"""

from __future__ import annotations

import hashlib
import importlib.util
import inspect
import os
import sys
import tempfile
from pathlib import Path

HEADER = "# geompm generated kernel loop: do not edit (geompm/backend/cpu_loops.py)\n"

HEAD = '''{header}# law: {smod}.{stress} / {wmod}.{wave}; law source sha256 {digest}
import numpy as np
from numba import njit, prange

from {smod} import {stress} as _law_stress
from {wmod} import {wave} as _law_wave
'''

#: the loops over a block, given _law_stress and _law_wave (the module file's body, or a closure's)
LOOPS = '''
# the law's functions compiled into the loops (inline="always"), with the law's own fastmath flags: one
# function, so numba keeps the per-particle views L[p], s[p], state[p] free of reference counting
particle_stress = njit(inline="always", fastmath={fm_stress})(_law_stress.py_func)
particle_wave_speed = njit(inline="always", fastmath={fm_wave})(_law_wave.py_func)


@njit(parallel=True, fastmath={fm_stress}, cache=True)
def stress_block(prm, dt, p_L, p_rho, p_stress, p_state):
    rate = 0.0  # max |L_ii| over the block, for the next step's strain-increment limit
    for p in prange(p_L.shape[0]):
        L = p_L[p]
        particle_stress(prm, dt, L, p_rho[p], p_stress[p], p_state[p])
        rate = max(rate, max(abs(L[0, 0]), max(abs(L[1, 1]), abs(L[2, 2]))))
    return rate


@njit(parallel=True, cache=True)
def wave_speed_block(prm, p_rho):
    lo = np.inf
    hi = -np.inf
    for p in prange(p_rho.shape[0]):
        lo = min(lo, p_rho[p])
        hi = max(hi, p_rho[p])
    if hi < lo:
        return 0.0
    return max(particle_wave_speed(prm, lo), particle_wave_speed(prm, hi))
'''

_LOOPS: dict = {}
_FOLDER: list = []


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


def _importable(fn) -> bool:
    py = getattr(fn, "py_func", fn)
    mod = sys.modules.get(py.__module__)
    return (mod is not None and py.__module__ != "__main__" and "<locals>" not in py.__qualname__
            and getattr(mod, py.__name__, None) is fn and getattr(mod, "__file__", None) is not None)


def _fastmath(fn) -> str:
    """The law function's fastmath option as source text (False, True or a set of LLVM flags)."""
    flags = fn.targetoptions.get("fastmath", False)
    if isinstance(flags, (set, frozenset)) or (hasattr(flags, "flags") and not isinstance(flags, bool)):
        return repr(set(getattr(flags, "flags", flags)))
    return repr(bool(flags))


def _closure_loops(stress, wave):
    """The same loops for a law that cannot be imported by name: compiled in this process, not cached
    (numba caches only functions of a source file)."""
    import numpy as np
    from numba import njit, prange

    namespace = {"np": np, "njit": njit, "prange": prange, "_law_stress": stress, "_law_wave": wave}
    exec(LOOPS.format(fm_stress=_fastmath(stress), fm_wave=_fastmath(wave)).replace(", cache=True", ""), namespace)
    return namespace["stress_block"], namespace["wave_speed_block"]


def _write_if_changed(path: Path, text: str) -> None:
    if path.is_file():
        old = path.read_text()
        if old == text:
            return
        if not old.startswith(HEADER):
            raise RuntimeError(f"{path} exists and was not written by geompm: remove it or set GEOMPM_KERNEL_DIR")
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".loop-", suffix=".py")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, path)  # our own temporary file onto our own loop file


def block_loops(law):
    """(stress_block, wave_speed_block) of a material class."""
    stress, wave = law.particle_stress, law.particle_wave_speed
    if stress is None or wave is None:
        raise TypeError(f"material '{law.name}' must define particle_stress and particle_wave_speed "
                        "(docs/how-to/write-a-material-plugin.md)")
    key = (stress, wave)
    if key in _LOOPS:
        return _LOOPS[key]
    loops = _generated(stress, wave) if _importable(stress) and _importable(wave) else _closure_loops(stress, wave)
    _LOOPS[key] = loops
    return loops


def _generated(stress, wave):
    sp, wp = stress.py_func, wave.py_func
    files = sorted({inspect.getsourcefile(sp), inspect.getsourcefile(wp)})
    digest = hashlib.sha256(b"".join(Path(f).read_bytes() for f in files)).hexdigest()[:16]
    text = (HEAD.format(header=HEADER, smod=sp.__module__, stress=sp.__name__, wmod=wp.__module__,
                        wave=wp.__name__, digest=digest)
            + LOOPS.format(fm_stress=_fastmath(stress), fm_wave=_fastmath(wave)))
    # the name carries the law's identity and source digest: two installs of different law sources never
    # write the same file, and an edited law gets a new file (so a fresh numba compilation)
    ident = f"{sp.__module__}.{sp.__name__}|{wp.__module__}.{wp.__name__}|{digest}"
    stem = f"loop_{sp.__module__.replace('.', '_')}_{sp.__name__}_{hashlib.sha256(ident.encode()).hexdigest()[:12]}"
    path = kernel_folder() / f"{stem}.py"
    _write_if_changed(path, text)
    name = f"geompm_loops.{stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # numba's cache rebuilds the loop's environment by module name
    spec.loader.exec_module(module)
    return module.stress_block, module.wave_speed_block
