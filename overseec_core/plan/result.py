"""The result of a planning query: a :class:`PathResult` (the path, its cost and how it was found)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PathResult:
    """A planned path and how it was found.

    ``pixels`` (N, 2) int64 (row, col) from the first waypoint to the last, consecutive cells
    8-connected. ``cost`` is the total under the step rule, ``length_m`` its ground length.
    ``mode`` is the mode that produced the path ('exact', or 'fast' when at least one leg came
    from a corridor search). ``bound`` is a guaranteed lower bound on the optimal cost: equal to
    ``cost`` for exact paths, below it for fast ones.
    """

    pixels: np.ndarray
    cost: float
    length_m: float
    mode: str
    bound: float
    seconds: float
    waypoints: tuple[tuple[int, int], ...]
    leg_costs: tuple[float, ...]
    requested_mode: str
    expanded: int = 0
    notes: tuple[str, ...] = ()

    @property
    def gap(self) -> float:
        """Largest possible relative excess over the optimum, (cost - bound) / cost."""
        return 0.0 if self.cost <= 0 else max(0.0, (self.cost - self.bound) / self.cost)

    def to_json(self) -> dict:
        """Everything but the pixels, as plain JSON types."""
        return {
            "cost": self.cost,
            "length_m": self.length_m,
            "mode": self.mode,
            "requested_mode": self.requested_mode,
            "bound": self.bound,
            "gap": self.gap,
            "seconds": self.seconds,
            "n_pixels": int(len(self.pixels)),
            "waypoints": [list(w) for w in self.waypoints],
            "leg_costs": list(self.leg_costs),
            "expanded": self.expanded,
            "notes": list(self.notes),
        }
