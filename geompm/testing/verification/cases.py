"""The clone's folders that harnesses replaying a shipped case read: ``ROOT`` (the repository) and ``CASES``
(its cases/).  geompm installed from a clone (``pip install -e .``, as the README does) has them beside the
package; a harness that needs one and does not find it says so when it is asked."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
CASES = ROOT / "cases"


def shipped_case(name: str) -> Path:
    """cases/<name> of the clone; FileNotFoundError naming the folder looked in."""
    path = CASES / name
    if not path.is_file():
        raise FileNotFoundError(f"{path}: this harness replays a case shipped in geompm's repository; run it from "
                                "a clone (pip install -e .)")
    return path
