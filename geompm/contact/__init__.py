"""Contact with rigid surfaces, shared by boundaries, obstacles and terrain: the velocity rules (``rules.py``),
signed-distance lattices (``sdf_field.py``), the particle guard (``guard.py``), the recorded contact force
(``force.py``, ``recorded.py``), face pressures (``face_pressure.py``), surface meshes for output
(``tessellate.py``) and a mesh's thinnest part (``thickness.py``)."""
