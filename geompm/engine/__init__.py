"""State, grid window, time-step control and the scheduler (time loop of stages)."""
