"""docs/design.md is an index of decisions: each number once, each decision listed under its section in the
page's Index with its number and title, so other pages can cite a decision by number."""

from __future__ import annotations

import re
from pathlib import Path

PAGE = Path(__file__).resolve().parents[2] / "docs" / "design.md"
ENTRY = re.compile(r"(?ms)^(\d+)\. \*\*(.+?)\*\*")


def test_every_decision_has_one_number_and_an_index_line():
    text = PAGE.read_text()
    index, body = text.split("## Index", 1)[1].split("\n## ", 1)
    found = [(int(n), re.sub(r"\s+", " ", t).strip().rstrip(".:,")) for n, t in ENTRY.findall(body)]
    numbers = [n for n, _ in found]
    assert len(numbers) > 50
    assert sorted({n for n in numbers if numbers.count(n) > 1}) == []
    listed = re.findall(r"(?:: |; )(\d+) ", index)
    assert sorted(int(n) for n in listed) == sorted(numbers)
    missing = [f"{n} {t}" for n, t in found if f"{n} {t}" not in index]
    assert not missing, missing
