"""Probes: what a case measures at a place in the flow each step (depth, speed, discharge)."""
