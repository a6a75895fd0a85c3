"""A schedule given in a case: one value per time, linear between (the triggers, a wall's head)."""


def check_schedule(times, values, key: str, noun: str) -> None:
    """A trigger's schedule: one value per time, times >= 0 s and non-decreasing (ValueError otherwise)."""
    if len(times) != len(values):
        raise ValueError(f"'times' has {len(times)} entries and '{key}' {len(values)}: give one {noun} per time")
    if any(b < a for a, b in zip(times, times[1:])):
        raise ValueError("'times' must not decrease")
    if any(t < 0.0 for t in times):
        raise ValueError("'times' must be >= 0 s")
