"""The case's time-step scheme (schemes/base.py), found through the ``geompm.schemes`` entry points.

``solver.update`` names the scheme; left out, the case gets the scheme that declares itself the ``default``
of its kind: a case with a saturated material (``pore_water``) one that runs pore water, any other a dry
one.  A named scheme of the other kind is refused with the names that would run the case.
"""

from __future__ import annotations

from geompm.contract import registry
from geompm.errors import CaseError


def resolve_scheme(case) -> tuple[type | None, list[tuple[str, str]]]:
    """(the scheme class, problems with their JSON paths)."""
    wet = any(m.pore_water is not None for m in case.materials.values())
    schemes = registry.available("schemes")
    fitting = sorted(name for name, info in schemes.items() if info.plugin.pore_water == wet)
    kind = "saturated materials ('pore_water')" if wet else "dry materials"
    name = case.solver.update
    if name is None:
        defaults = [n for n in fitting if schemes[n].plugin.default]
        if not defaults:
            return None, [("solver.update", f"no installed scheme runs {kind} by default; name one of "
                                            f"{', '.join(fitting) or 'none'}")]
        return schemes[defaults[0]].plugin, []
    try:
        cls = registry.get("schemes", name, "solver.update")
    except CaseError as exc:
        return None, list(exc.problems)
    if cls.pore_water != wet:
        return None, [("solver.update", f"scheme '{name}' does not run {kind}; use one of "
                                        f"{', '.join(fitting) or 'none'} (or leave solver.update out)")]
    return cls, []
