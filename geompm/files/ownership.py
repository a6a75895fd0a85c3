"""What geompm made, and the one guarded way it deletes anything.

geompm never deletes or overwrites a file it did not create.  Every output
folder it makes (a run, a study, a calibration) gets a marker file,
``.geompm-folder``, holding its kind and the absolute path it was made at.
Every delete in the package goes through :func:`remove_tree` (a whole output
folder, for ``--overwrite``) or :func:`remove_file` (a checkpoint that is no
longer kept, a temporary file of an atomic write), and both refuse anything
that is not provably geompm's:

- a folder is removed only if it carries the marker of the expected kind,
  made at that very path (a copied or moved folder is not removed);
- never the current folder or an ancestor of it, the case file's folder or
  an ancestor of it, the home folder or ``/``; never a symbolic link;
- a file is removed only if this process made it (temporary files) or it lies
  inside a marked folder.

A refusal is a ``CaseError`` (exit 2) that says why and what to do instead,
raised before anything is touched.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from pathlib import Path

from geompm.errors import CaseError

MARKER = ".geompm-folder"
KINDS = ("run", "study", "calibration", "stability")

_made_files: set[str] = set()  # temporary files this process created (atomic writes)


def _real(path: str | Path) -> Path:
    return Path(os.path.realpath(path))


def _marker_of(folder: Path) -> dict | None:
    f = folder / MARKER
    try:
        data = json.loads(f.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def owned_kind(folder: str | Path) -> str | None:
    """The kind of geompm output folder that ``folder`` is ('run', 'study', ...), or None if geompm did not
    make it here."""
    folder = Path(folder)
    mark = _marker_of(folder)
    if mark is None or mark.get("path") != str(_real(folder)):
        return None
    return mark.get("kind")


def marked_kind(folder: str | Path) -> str | None:
    """The kind its marker names, wherever the marker was written (None without a marker)."""
    mark = _marker_of(Path(folder))
    return None if mark is None else mark.get("kind")


def mark_folder(folder: str | Path, kind: str, adopted: bool = False) -> None:
    """Write the marker that makes ``folder`` a geompm output folder of ``kind``."""
    assert kind in KINDS, kind
    folder = Path(folder)
    from geompm.version import __version__

    text = json.dumps({"kind": kind, "path": str(_real(folder)), "geompm": __version__,
                       "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "adopted": adopted}, indent=2) + "\n"
    (folder / MARKER).write_text(text)


def create_folder(folder: str | Path, kind: str, what: str = "--out") -> Path:
    """Make an output folder of ``kind`` (and its parents) and mark it; an existing empty folder is taken.

    A non-empty folder is refused: the caller decides about ``--overwrite``
    (``remove_tree``) or ``--resume`` before calling this."""
    folder = Path(folder)
    if folder.is_symlink() or (folder.exists() and not folder.is_dir()):
        raise CaseError([(what, f"'{folder}' exists and is not a folder; choose another {what}")])
    if folder.is_dir() and any(folder.iterdir()):
        raise CaseError([(what, f"'{folder}' already exists and is not empty; choose another {what}")])
    try:
        folder.mkdir(parents=True, exist_ok=True)
        mark_folder(folder, kind)
    except OSError as exc:
        raise CaseError([(what, f"cannot create the {kind} folder '{folder}': {exc.strerror}; "
                                f"choose another {what}")]) from None
    return folder


def _protected(extra: tuple) -> list[tuple[Path, str]]:
    out = [(_real("/"), "the root folder /"), (_real(Path.home()), "your home folder"),
           (_real(Path.cwd()), "the current folder")]
    out += [(_real(p), f"the folder of {name}") for p, name in extra]
    return out


def removal_problem(folder: str | Path, kind: str, protect: tuple = ()) -> str | None:
    """Why ``remove_tree(folder, kind, protect)`` would refuse, or None if it may delete ``folder``.

    ``protect`` holds (path, description) pairs, e.g. the case file's folder."""
    folder = Path(folder)
    if folder.is_symlink():
        return f"'{folder}' is a symbolic link; geompm does not delete through links"
    if not folder.is_dir():
        return f"'{folder}' is not a folder"
    real = _real(folder)
    for p, name in _protected(tuple(protect)):
        if p == real or real in p.parents:
            return (f"'{folder}' is {name}" if p == real else f"'{folder}' holds {name} ({p})") + \
                   "; geompm never deletes it"
    mark = _marker_of(folder)
    if mark is None:
        return (f"'{folder}' was not made by geompm (it has no {MARKER} marker), so geompm will not delete it; "
                "delete it yourself if you are sure, or choose another folder")
    if mark.get("path") != str(real):
        return (f"'{folder}' holds a geompm marker for '{mark.get('path')}': it was copied or moved here, so "
                "geompm will not delete it; delete it yourself if you are sure, or choose another folder")
    if mark.get("kind") != kind:
        return (f"'{folder}' is a geompm {mark.get('kind')} folder, not a {kind} folder; geompm will not "
                "delete it here; choose another folder")
    return None


def remove_tree(folder: str | Path, kind: str, protect: tuple = (), what: str = "--out") -> None:
    """Delete a whole output folder that geompm made, or raise CaseError saying why not."""
    problem = removal_problem(folder, kind, protect)
    if problem:
        raise CaseError([(what, problem)])
    shutil.rmtree(folder)


def register_made(path: str | Path) -> None:
    """Record a file this process has just created, so that remove_file may delete it."""
    _made_files.add(str(_real(path)))


def _inside_owned(path: Path) -> bool:
    for parent in path.parents:
        if (parent / MARKER).is_file():
            return owned_kind(parent) is not None
    return False


def remove_file(path: str | Path) -> None:
    """Delete one file that geompm made (see the module docstring); refuse anything else."""
    real = _real(path)
    made = str(real) in _made_files
    if not made and (real.name == MARKER or not _inside_owned(real)):
        raise CaseError([("", f"geompm will not delete '{path}': it did not make it")])
    if Path(path).is_symlink() or real.is_dir():
        raise CaseError([("", f"geompm will not delete '{path}': not a plain file")])
    os.unlink(real)
    _made_files.discard(str(real))


def may_write(path: str | Path) -> bool:
    """True if writing ``path`` destroys nothing geompm did not make: it does not exist, this process made
    it, or it lies inside a geompm output folder."""
    path = Path(path)
    if not path.exists() and not path.is_symlink():
        return True
    return path.is_file() and (str(_real(path)) in _made_files or _inside_owned(_real(path)))


def prepare_folder(folder: str | Path, kind: str, *, resume: bool, overwrite: bool, protect: tuple = (),
                   legacy=None, what: str = "--out") -> Path:
    """The output folder of a study or calibration, ready to write into.

    A missing or empty folder is made and marked.  An existing one is kept with
    ``resume`` if it is geompm's folder of this kind (or, without any marker,
    ``legacy(folder)`` says it holds only what an older geompm wrote: it is then
    marked as adopted), deleted first with ``overwrite`` (``remove_tree``'s
    rules), else refused."""
    folder = Path(folder)
    if not folder.exists() or (folder.is_dir() and not folder.is_symlink() and not any(folder.iterdir())):
        return create_folder(folder, kind, what)
    if resume:
        if owned_kind(folder) == kind:
            return folder
        if not (folder / MARKER).exists() and folder.is_dir() and legacy is not None and legacy(folder):
            mark_folder(folder, kind, adopted=True)
            return folder
        raise CaseError([(what, f"'{folder}' is not a geompm {kind} folder, so geompm will not write into it; "
                                f"choose another {what}")])
    if overwrite:
        remove_tree(folder, kind, protect, what)
        return create_folder(folder, kind, what)
    raise CaseError([(what, f"{kind} folder '{folder}' already exists; use --resume to keep what it holds, "
                            f"--overwrite to start again (only for a folder geompm made), or another {what}")])


def holds_only(folder: Path, names: set[str], pattern: str | None = None) -> bool:
    """True if every entry of ``folder`` is one of ``names`` or matches the regular expression ``pattern``."""
    import re

    return all(e.name in names or (pattern is not None and re.fullmatch(pattern, e.name))
               for e in folder.iterdir())
