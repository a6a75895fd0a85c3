"""geompm: an explicit Material Point Method framework for geotechnical hazards.

SI units throughout: metres, seconds, kilograms, pascals.
"""

__version__ = "0.1.0"
