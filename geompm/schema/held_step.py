"""The checks of ``solver.held_step`` before any work: what a held batch cannot carry (engine/held_step.py)."""

from __future__ import annotations


def held_step_problems(case, loaded) -> list[tuple[str, str]]:
    """(JSON path, sentence) of each part of ``case`` that needs the host between steps, where the case asks for
    held steps; none otherwise.  The run on several MPI ranks is refused when it starts (engine/runner.py).  The
    series writer a run adds where the case has none (every step, engine/run_case.py) writes after each batch."""
    if case.solver.held_step is None:
        return []
    out = []
    fix = "; remove solver.held_step"
    if case.inflows:
        out.append(("inflows", "an inflow adds particles on the host between steps, which a held batch cannot" + fix))
    if loaded.scheme is not None and not loaded.scheme.holds_step:
        out.append(("solver.update", f"scheme '{loaded.scheme.name}' reduces its own terms of the stable step, "
                                     "which the held step's check does not see" + fix))
    triggers = case.triggers
    if triggers is not None and triggers.water_table is not None:
        out.append(("triggers.water_table", "a water table lays its pressure on the particles on the host" + fix))
    if triggers is not None and triggers.strength_reduction is not None:
        out.append(("triggers.strength_reduction", "a strength trigger changes the laws between steps" + fix))
    for i, spec in enumerate(case.outputs):
        if spec.interval == 0.0:
            out.append((f"outputs.{i}.interval", f"0 writes every step, but the host sees the state only at the end "
                                                 f"of a held batch; give an interval [s] (e.g. {1e-3:g}) or remove "
                                                 "solver.held_step"))
    for r in loaded.boundaries + loaded.obstacles + loaded.damping:
        if not r.cls.holds_step:
            out.append((r.path, f"'{r.label}' computes its parameters from the particles or from what it reduced "
                                "(its class does not declare holds_step)" + fix))
    return out
