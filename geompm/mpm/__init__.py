"""The data of a Material Point Method run, independent of any machine: the particle state (``state.py``), the
grid and its active window (``grid.py``), the memory a case needs (``memory.py``) and the pore pressure under a
water table (``water_table.py``).  A scheme's own particle fields (saturated soil's) are declared by the scheme
(schemes/saturated/fields.py)."""
