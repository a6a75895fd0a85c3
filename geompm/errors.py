"""Error types that the CLI turns into exit codes.

``CaseError`` (exit 2) carries every problem found in a case, each as a
(JSON path, message) pair, so a user sees all of them at once.
``SimulationError`` (exit 3) is raised when a run becomes unphysical.
"""

from __future__ import annotations


class CaseError(Exception):
    """A case (JSON file) that cannot be run; ``problems`` is [(path, message)]."""

    def __init__(self, problems: list[tuple[str, str]], warnings: list[tuple[str, str]] | None = None):
        self.problems = list(problems)
        #: (path, message) warnings found before the refusal (values that look like a wrong unit): a
        #: refusal caused by such a value is explained by them, so the CLI prints them with the errors
        self.warnings = list(warnings or [])
        super().__init__(self.format())

    def format(self) -> str:
        lines = [f"{path or '<case>'}: {msg}" for path, msg in self.problems]
        return "\n".join(lines)


class SimulationError(Exception):
    """A run that had to stop because its state became unphysical."""


def join_path(*parts) -> str:
    """Join JSON path elements as ``bodies.0.geometry.min``."""
    return ".".join(str(p) for p in parts if p != "" and p is not None)
