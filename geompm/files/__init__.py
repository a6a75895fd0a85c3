"""Files geompm reads and writes: atomic writes with the user's umask (``atomic.py``), the one guarded delete and
the ownership marks it checks (``ownership.py``), digital elevation models (``dem.py``) and surface meshes
(``mesh.py``)."""
