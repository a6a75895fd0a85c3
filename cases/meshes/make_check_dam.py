"""Writes check_dam.stl: a slit check dam of two concrete blocks (metres).

Each block is 0.1 m thick (x), 0.7 m high (y), 0.2 m wide (z); they leave a
0.1 m slit in the middle of a 0.5 m wide flume.  Two closed boxes, so the
mesh is watertight.  Run: python cases/meshes/make_check_dam.py
"""

from pathlib import Path

import trimesh

left = trimesh.creation.box(extents=[0.1, 0.7, 0.2])
left.apply_translation([0.0, 0.0, -0.15])
right = trimesh.creation.box(extents=[0.1, 0.7, 0.2])
right.apply_translation([0.0, 0.0, 0.15])
dam = trimesh.util.concatenate([left, right])
assert dam.is_watertight
dam.export(Path(__file__).with_name("check_dam.stl"))
