"""The time loop: the scheduler that orders a step's stages on a backend (``scheduler.py``), the runner that
drives writers, checkpoints and progress (``runner.py``), the health checks (``health.py``), checkpoints
(``checkpoint.py``) and the time-step report (``estimate.py``)."""
