"""The search for the factor of safety: bracket, then k-section, with k trials in flight per round.

A trial at factor F runs the case with its strength divided by F and ends stable or failed
(criterion.py).  The factor of safety lies between the largest stable F and the smallest failed F.
With no bracket yet the search steps away from the known trials by ``grow`` (up from a stable trial,
down from a failed one); with a bracket it splits it into k + 1 equal parts and runs the k inner
points at once (bisection for k = 1), so each round shrinks the bracket by k + 1.  It stops when the
bracket is no wider than ``tolerance`` (absolute, on F), or when it leaves [lowest, highest]: a case
still failing at ``lowest`` is reported as F < lowest, one still stable at ``highest`` as F > highest.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Search:
    tolerance: float = 0.01
    start: float = 1.0
    grow: float = 1.5
    lowest: float = 0.05
    highest: float = 20.0
    #: (F, failed) of every trial so far, in the order they were recorded
    trials: list = field(default_factory=list)

    @property
    def stable(self) -> float | None:
        """The largest F of a stable trial."""
        ok = [f for f, failed in self.trials if not failed]
        return max(ok) if ok else None

    @property
    def failed(self) -> float | None:
        """The smallest F of a failed trial."""
        bad = [f for f, failed in self.trials if failed]
        return min(bad) if bad else None

    def record(self, factor: float, failed: bool) -> None:
        self.trials.append((float(factor), bool(failed)))

    def inconsistent(self) -> list[tuple[float, float]]:
        """Pairs (stable F, failed F) with the failed one below the stable one: the criterion is not
        monotone in F there (a trial too short to decide, or a mechanism that arrests)."""
        ok = [f for f, failed in self.trials if not failed]
        bad = [f for f, failed in self.trials if failed]
        return [(s, b) for s in ok for b in bad if b < s]

    def bracket(self) -> tuple[float | None, float | None]:
        """(largest stable F, smallest failed F above it): the factor of safety lies between them."""
        lo = self.stable
        bad = [f for f, failed in self.trials if failed and (lo is None or f > lo)]
        return lo, (min(bad) if bad else None)

    def done(self) -> bool:
        lo, hi = self.bracket()
        if lo is not None and hi is not None:
            return hi - lo <= self.tolerance * (1.0 + 1e-9)
        if lo is None and hi is not None:
            return hi <= self.lowest
        if hi is None and lo is not None:
            return lo >= self.highest
        return False

    def next_factors(self, k: int) -> list[float]:
        """The k factors (or fewer) to try in the next round."""
        lo, hi = self.bracket()
        if not self.trials:
            return [self.start * self.grow ** i for i in range(k)]
        if lo is not None and hi is not None:
            return [lo + (hi - lo) * (i + 1) / (k + 1) for i in range(k)]
        if hi is None:
            out = [lo * self.grow ** (i + 1) for i in range(k)]
            return [min(f, self.highest) for f in out[: 1 + sum(f < self.highest for f in out)]]
        out = [hi / self.grow ** (i + 1) for i in range(k)]
        return [max(f, self.lowest) for f in out[: 1 + sum(f > self.lowest for f in out)]]

    def result(self) -> dict:
        """factor_of_safety (the bracket's middle; None where there is no bracket), the bracket, and
        'less_than' / 'more_than' when the search left [lowest, highest]."""
        lo, hi = self.bracket()
        if lo is not None and hi is not None:
            return {"factor_of_safety": 0.5 * (lo + hi), "bracket": [lo, hi], "bound": None}
        if hi is not None:
            return {"factor_of_safety": None, "bracket": [None, hi], "bound": f"F < {hi:g}"}
        return {"factor_of_safety": None, "bracket": [lo, None], "bound": f"F > {lo:g}" if lo else None}
