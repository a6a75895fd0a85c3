"""What a plugin is: the parameter model (``plugin.py``), the stage bases and phases (``stages.py``), the packing of
parameters into numba arrays (``layout.py``) and the entry-point registry that finds plugins (``registry.py``).
Imports only ``errors``: every other layer builds on it."""
