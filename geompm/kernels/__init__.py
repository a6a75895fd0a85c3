"""Numba kernels.  They take arrays and scalars only; no configuration objects."""
