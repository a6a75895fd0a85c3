"""Verification: small runs against closed-form solutions (elastic bar, geostatic column, Poiseuille and
Nusselt flows, blocks on inclines, yield points, hydrostatic and stream forces on walls and obstacles)."""
