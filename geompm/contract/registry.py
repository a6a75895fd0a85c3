"""Entry-point discovery of plugins.

Groups: ``geompm.materials``, ``geompm.damping``, ``geompm.boundaries``,
``geompm.obstacles``, ``geompm.writers``, ``geompm.schemes``.  Built-in plugins register through
the same entry points (in geompm's pyproject.toml) as third-party packages.

Discovery is lazy (a group is scanned the first time it is asked for) and
cached; a plugin that fails to import produces a warning naming it and its
package, never a crash.  Unknown names raise ``CaseError`` listing the
installed names and the closest match.
"""

from __future__ import annotations

import difflib
import warnings
from dataclasses import dataclass
from importlib.metadata import entry_points

from geompm.errors import CaseError

GROUPS = {
    "materials": "geompm.materials",
    "damping": "geompm.damping",
    "boundaries": "geompm.boundaries",
    "obstacles": "geompm.obstacles",
    "writers": "geompm.writers",
    "schemes": "geompm.schemes",
}


@dataclass(frozen=True)
class PluginInfo:
    name: str
    group: str
    package: str
    value: str
    plugin: type


_cache: dict[str, dict[str, PluginInfo]] = {}


def clear_cache() -> None:
    """Forget discovered plugins (tests install distributions at run time)."""
    _cache.clear()


def _discover(kind: str) -> dict[str, PluginInfo]:
    group = GROUPS[kind]
    found: dict[str, PluginInfo] = {}
    for ep in entry_points(group=group):
        dist = getattr(ep, "dist", None)
        package = dist.metadata["Name"] if dist is not None else "?"
        try:
            obj = ep.load()
        except Exception as exc:  # a broken third-party plugin must not stop geompm
            warnings.warn(
                f"geompm: plugin '{ep.name}' in group {group} from package '{package}' "
                f"could not be loaded ({type(exc).__name__}: {exc}); it is skipped",
                RuntimeWarning,
                stacklevel=2,
            )
            continue
        if ep.name in found and found[ep.name].value != ep.value:
            warnings.warn(
                f"geompm: plugin name '{ep.name}' in group {group} is registered twice "
                f"('{found[ep.name].package}' and '{package}'); the first one is used",
                RuntimeWarning,
                stacklevel=2,
            )
            continue
        found[ep.name] = PluginInfo(ep.name, group, package, ep.value, obj)
    return found


def available(kind: str) -> dict[str, PluginInfo]:
    """All loadable plugins of ``kind`` ("materials", "boundaries", ...)."""
    if kind not in _cache:
        _cache[kind] = _discover(kind)
    return _cache[kind]


def unknown_name_message(name: str, names) -> str:
    names = sorted(names)
    close = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    return f"unknown name '{name}'{hint} (installed: {', '.join(names) or 'none'})"


def get(kind: str, name: str, path: str = "") -> type:
    """The plugin class registered as ``name`` in ``kind``; CaseError if absent."""
    plugins = available(kind)
    if name not in plugins:
        raise CaseError([(path, unknown_name_message(name, plugins))])
    return plugins[name].plugin


def describe(plugin: type) -> str:
    """One-line description of a plugin class."""
    text = getattr(plugin, "description", "") or (plugin.__doc__ or "").strip()
    return text.splitlines()[0] if text else ""
