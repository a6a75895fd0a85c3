"""``geompm plot``'s pictures (matplotlib, the optional 'plot' extra): a run's series, forces and deposit
(``run.py``), hazard maps (``maps.py``), face pressures (``pressure.py``) and a calibration (``calibration.py``);
``figure.py`` holds what they share."""
