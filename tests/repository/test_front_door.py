"""The README opens with three figures of what geompm computes (the dam's face pressures, a hazard map, the
dam break against Martin & Moyce 1952), drawn by benchmarks/front_door/make.py from the data it keeps in
benchmarks/front_door/data/ (from runs of the shipped cases) and tests/refdata.

The figures are current: docs/figures/front.json holds the sha256 of the script and of every file each
figure reads when it was drawn, and they must equal the files' as they are now; a changed script or data
file that was not redrawn fails here.  Drawing again from the kept data gives pictures of the same size.
"""

from __future__ import annotations

import importlib.util
import json
import struct
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "front_door" / "make.py"


def _make():
    spec = importlib.util.spec_from_file_location("front_door_make", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return struct.unpack(">II", head[16:24])


def test_the_readme_opens_with_the_three_figures():
    """Each figure is shown before the set-up section, in the script's order, and is a PNG of a readable size."""
    make = _make()
    top = (ROOT / "README.md").read_text().split("## Set-up", 1)[0]
    shown = [line.split("](", 1)[1].split(")", 1)[0] for line in top.splitlines() if line.startswith("![")]
    assert shown == [f"docs/figures/{name}" for name in make.FIGURE_INPUTS]
    for name in make.FIGURE_INPUTS:
        w, h = _png_size(ROOT / "docs" / "figures" / name)
        assert 500 <= w <= 1200 and 300 <= h <= 900, (name, w, h)


def test_the_figures_are_drawn_from_the_data_and_script_as_they_are():
    make = _make()
    recorded = json.loads((ROOT / "docs" / "figures" / "front.json").read_text())
    assert recorded == make.manifest(), "redraw: python benchmarks/front_door/make.py draw"
    dam = json.loads((make.DATA / "dam_status.json").read_text())
    assert dam["peak_force"] > 0.0 and dam["peak_pressure"] > 0.0


def test_drawing_again_gives_the_same_pictures_in_size(tmp_path):
    make = _make()
    make.draw(tmp_path)
    for name in make.FIGURE_INPUTS:
        assert _png_size(tmp_path / name) == _png_size(ROOT / "docs" / "figures" / name)
    assert json.loads((tmp_path / "front.json").read_text()) == make.manifest()
