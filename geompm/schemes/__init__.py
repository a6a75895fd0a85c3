"""The time step as declared schemes (schemes/base.py): ``usl``, ``musl`` and ``saturated`` (two-phase
soil, schemes/saturated/), each registered as a ``geompm.schemes`` entry point."""
