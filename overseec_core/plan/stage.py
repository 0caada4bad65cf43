"""The plan stage's options and result, and turning map points into pixels.

``overseec plan``, the QGIS task and Processing all go through
:func:`overseec_core.pipeline.run_plan`, which uses these.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

from ..errors import InputError, PlanError
from ..raster import crs_label, parse_crs
from .grid import PlanningGrid
from .planner import (DEFAULT_BASE_COST_PER_M, MODES, PathResult, Planner, point_names,
                      step_lengths_m)


@dataclass(frozen=True)
class PlanOptions:
    """What to plan and where to write it.

    ``points`` are (x, y) map coordinates: start, via points..., goal, in ``crs`` (None = the
    costmap's CRS; for EPSG:4326 x is longitude). ``native_out`` / ``pixels_out`` /
    ``cumulative_out`` are optional extra outputs (None = not written).
    """

    costmap: Path
    points: tuple[tuple[float, float], ...]
    out: Path
    crs: str | None = None
    mode: str = "exact"
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M
    lethal: Path | None = None
    lethal_threshold: float | None = None
    native_out: Path | None = None
    pixels_out: Path | None = None
    cumulative_out: Path | None = None

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise InputError(f"unknown planning mode {self.mode!r}; use {' or '.join(MODES)}")
        if len(self.points) < 2:
            raise InputError("planning needs a start and a goal")
        if self.crs is not None:
            parse_crs(self.crs)  # one-line error now, not after loading the costmap

    def inputs(self) -> list[Path]:
        return [p for p in (self.costmap, self.lethal) if p is not None]


def default_outputs(out: Path) -> dict[str, Path]:
    """Sibling file names derived from the GeoJSON path: path.geojson -> path.native.gpkg, ..."""
    stem = out.name[: -len(out.suffix)] if out.suffix else out.name
    return {"native": out.with_name(f"{stem}.native.gpkg"), "pixels": out.with_name(f"{stem}.pixels.csv")}


def format_point(x: float, y: float) -> str:
    return f"({x:.10g}, {y:.10g})"


def points_to_pixels(grid: PlanningGrid, points: tuple[tuple[float, float], ...],
                     crs: str | None) -> tuple[list[tuple[int, int]], list[str]]:
    """Pixels holding each map point, and labels for messages; PlanError for a point outside."""
    where = f" {crs_label(parse_crs(crs))}" if crs else ""
    pixels, labels = [], []
    for name, (x, y) in zip(point_names(len(points)), points):
        label = f"{format_point(x, y)}{where}"
        row, col = grid.world_to_pixel(x, y, crs=crs)
        if not grid.contains(row, col):
            raise PlanError(f"{name} {label} is outside the costmap {Path(grid.source or '').name} "
                            f"(bounds {_bounds_text(grid, crs)})")
        pixels.append((row, col))
        labels.append(label)
    return pixels, labels


def _bounds_text(grid: PlanningGrid, crs: str | None) -> str:
    import numpy as np

    rows = np.array([0, 0, grid.height, grid.height], dtype=float) - 0.5
    cols = np.array([0, grid.width, 0, grid.width], dtype=float) - 0.5
    xs, ys = grid.pixel_to_world(rows, cols, crs=crs)
    return f"x {min(xs):.10g}..{max(xs):.10g}, y {min(ys):.10g}..{max(ys):.10g}"


@dataclass(frozen=True)
class PlanRunResult:
    """A planned path and the files written for it."""

    result: PathResult
    outputs: dict[str, Path]
    waypoints: list[dict[str, Any]]
    prompt: str | None
    timings: dict[str, float] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        return {**self.result.to_json(), "outputs": {k: str(v) for k, v in self.outputs.items()},
                "waypoints": self.waypoints, "prompt": self.prompt, "timings": self.timings}


class RulePlanner:
    """A :class:`Planner` that enters keep-out zones only when no route exists without them.

    Keep-out zones are what distance rules forbid ("keep at least 20 m from buildings"). When
    the points cannot be joined without them (a point inside one, or a zone cutting the map),
    the route is planned again on a copy where they are passable at the top cost, so it stays
    in them as little as it can, and its notes say the rule cannot be met and by how much. The
    copy is built once, on first need, and reused for later queries.
    """

    def __init__(self, planner: Planner) -> None:
        self.strict = planner
        self._relaxed: Planner | None = None
        #: Planned routes that had to break a rule.
        self.rules_broken = 0

    @property
    def grid(self) -> PlanningGrid:
        return self.strict.grid

    def plan(self, points: Sequence[tuple[int, int]], *, mode: str = "exact", labels=None,
             progress=None) -> tuple[PathResult, Planner]:
        """The route and the planner that found it (the strict one unless a rule was broken)."""
        try:
            return self.strict.plan(points, mode=mode, labels=labels, progress=progress), self.strict
        except PlanError as exc:
            if self.grid.keep_out is None:
                raise
            strict_error = exc
        if self._relaxed is None:
            self._relaxed = Planner(self.grid.entering_keep_out(), self.strict.base_cost_per_m)
        try:
            result = self._relaxed.plan(points, mode=mode, labels=labels, progress=progress)
        except PlanError:
            raise strict_error from None
        keep_out = self.grid.keep_out
        inside = keep_out[result.pixels[:, 0], result.pixels[:, 1]]
        steps = step_lengths_m(result.pixels, *self.grid.pixel_size_m)
        metres = float((steps * (inside[1:] | inside[:-1])).sum())
        note = (f"a distance rule cannot be met between these points: no route avoids its "
                f"keep-out zone, so this one runs {metres:.1f} m inside it ({strict_error})")
        self.rules_broken += 1
        return replace(result, notes=tuple(result.notes) + (note,)), self._relaxed


def plan_keeping_rules(grid: PlanningGrid, points: Sequence[tuple[int, int]], *, mode: str = "exact",
                       base_cost_per_m: float = DEFAULT_BASE_COST_PER_M, labels=None,
                       progress=None) -> tuple[PathResult, Planner]:
    """One query of a :class:`RulePlanner` on ``grid``: the route and the planner that found it."""
    return RulePlanner(Planner(grid, base_cost_per_m)).plan(points, mode=mode, labels=labels,
                                                            progress=progress)
