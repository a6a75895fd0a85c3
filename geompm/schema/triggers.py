"""Checks of ``triggers`` (the specs are in case.py) that need the resolved materials.

``triggers``: what changes over a run to take a slope from stable to failure (docs/slope-stability.md).

``strength_reduction``: the factor F(t) by which the shear strength of the named soils (default every
soil whose law has a strength to reduce, ``Material.strength_reduction``) is divided, piecewise linear
through (``times``, ``factors``) and held at its end values outside them; each law's
``strength_reduced(params, F)`` says what dividing its strength means (c / F and tan(phi) / F for the
Mohr-Coulomb-type laws).  `geompm stability` writes its trials with the same trigger.
"""

from __future__ import annotations


def trigger_problems(case, loaded) -> list[tuple[str, str]]:
    """The materials a trigger names: each must exist and have a strength to reduce."""
    spec = case.triggers.strength_reduction if case.triggers is not None else None
    if spec is None:
        return []
    out = []
    path = "triggers.strength_reduction.materials"
    names = spec.materials
    if names is None:
        if not any(r.cls.strength_reduction for r in loaded.materials.values()):
            out.append(("triggers.strength_reduction", "no material of the case has a strength to reduce; give a "
                                                        "body a soil law such as mohr_coulomb or drucker_prager"))
        return out
    for i, name in enumerate(names):
        r = loaded.materials.get(name)
        if name not in case.materials:
            out.append((f"{path}.{i}", f"no material named '{name}' in 'materials' (there are: "
                                       f"{', '.join(sorted(case.materials))})"))
        elif r is not None and not r.cls.strength_reduction:
            out.append((f"{path}.{i}", f"material '{name}' ({r.cls.name}) has no shear strength to reduce"))
    return out
