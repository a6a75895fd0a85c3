"""The data of a Material Point Method run, independent of any machine: the particle state (``state.py``), the
grid and its active window (``grid.py``) and the memory a case needs (``memory.py``)."""
