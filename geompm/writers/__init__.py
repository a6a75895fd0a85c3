"""Output writers (geompm.writers entry-point group): plain Python outside the hot loop."""
