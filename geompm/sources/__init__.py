"""Sources: what adds material to a run between steps (an inflow hydrograph through a cross-section)."""
