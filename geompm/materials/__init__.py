"""Constitutive laws, one per module, registered in the geompm.materials entry-point group."""
