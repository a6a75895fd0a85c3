"""A test-only distribution on sys.path: a ``.dist-info`` folder with ``entry_points.txt`` and the modules it
names, exactly what ``pip install`` of a plugin package leaves, so a test registers a third-party plugin
without editing geompm."""

from __future__ import annotations

from pathlib import Path

from geompm.contract import registry


def install(folder: Path, monkeypatch, name: str, entry_points: dict[str, dict[str, str]],
            modules: dict[str, str]) -> None:
    """Make distribution ``name`` in ``folder``: ``entry_points`` maps a group to {plugin name: "module:Class"},
    ``modules`` a module name to its source.  The registry forgets what it found before; call
    ``registry.clear_cache()`` after the test (the fixtures do)."""
    info = folder / f"{name.replace('-', '_')}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("".join(
        f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in eps.items()) for group, eps in entry_points.items()))
    for module, source in modules.items():
        (folder / f"{module}.py").write_text(source)
    monkeypatch.syspath_prepend(str(folder))
    registry.clear_cache()
