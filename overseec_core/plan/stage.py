"""The plan stage's options and result, and turning map points into pixels.

``overseec plan``, the QGIS task and Processing all go through
:func:`run_plan` below, which uses these.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import defaults
from overseec_core.errors import InputError, PlanError
from overseec_core.io.grid import crs_label, parse_crs
from overseec_core.io.manifest import RunDir
from overseec_core.io.transaction import transactional
from overseec_core.io.write import check_output_path
from overseec_core.plan import load_costmap
from overseec_core.plan.export import (
    find_prompt,
    path_geojson,
    path_properties,
    waypoint_records,
    write_cumulative,
    write_geojson,
    write_native_gpkg,
    write_pixels,
)
from overseec_core.plan.grid import NEUTRAL_COST, PlanningGrid
from overseec_core.plan.overrides import path_override_properties, with_overrides
from overseec_core.plan.paths import (
    DEFAULT_BASE_COST_PER_M,
    check_slope_model,
    cumulative_path_cost,
    path_length_m,
    point_names,
    step_lengths_m,
)
from overseec_core.plan.planner import MODES, Planner
from overseec_core.plan.result import PathResult
from overseec_core.plan.smooth import smooth_if_asked
from overseec_core.progress import Progress
from overseec_core.synthesize.overrides import record_overrides

#: Own costs this far above neutral count as avoided ground in a broken rule's note (float32 and
#: program arithmetic leave neutral ground a few ulps off 0.5).
AVOIDED_EPS = 1e-6
#: What makes keep-out cells (lethal sidecar flag 2), named in a broken rule's note: the note
#: cannot tell them apart (the sidecar holds one flag for all three), so it names all of them.
RULE_KINDS = "a distance rule, a never-cross rule or an obstacle such as a building or water"
#: The slope model ``--dem`` plans with unless ``--slope-model`` names another.
DEFAULT_SLOPE_MODEL = defaults.SLOPE_MODELS[0]


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
    #: The costmap's band (None: the costmap must have exactly one).
    band: int | None = None
    #: Override polygon files (overseec_core.synthesize.overrides), applied to the loaded grid in memory.
    overrides: tuple[Path, ...] = ()
    #: Line-of-sight smoothing's cost tolerance (0.01 = 1 %; None = no smoothing; see plan.smooth).
    smooth: float | None = None
    #: Steps: 8 neighbours, or 16 (plus knight moves priced by the cell integral; the kernel's).
    neighbours: int = 8
    #: A DEM (any CRS and resolution; resampled bilinearly onto the costmap grid) for the
    #: anisotropic mode, and its slope model (``paths.SLOPE_MODELS``; default tobler with a DEM).
    dem: Path | None = None
    slope_model: str | None = None

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise InputError(f"unknown planning mode {self.mode!r}; use {' or '.join(MODES)}")
        if len(self.points) < 2:
            raise InputError("planning needs a start and a goal")
        if self.crs is not None:
            parse_crs(self.crs)  # one-line error now, not after loading the costmap
        if self.smooth is not None and not 0.0 <= float(self.smooth) <= 1.0:
            raise InputError(f"smoothing tolerance must be between 0 and 1 (0.01 = 1 %), not {self.smooth}")
        if self.slope_model is not None:
            check_slope_model(self.slope_model)
        if self.slope_model is not None and self.dem is None:
            raise InputError("--slope-model needs --dem DEM.tif (the elevations it prices)")
        if self.dem is not None and self.smooth is not None:
            raise InputError("--smooth prices straight segments without slopes: leave it out with --dem")

    @property
    def terrain_model(self) -> str | None:
        """The slope model planned with: None without a DEM, else the one asked for (tobler by default)."""
        return None if self.dem is None else (self.slope_model or DEFAULT_SLOPE_MODEL)

    def inputs(self) -> list[Path]:
        return [p for p in (self.costmap, self.lethal, self.dem, *self.overrides) if p is not None]


def default_outputs(out: Path) -> dict[str, Path]:
    """Sibling file names derived from the GeoJSON path: path.geojson -> path.native.gpkg, ..."""
    stem = out.name[: -len(out.suffix)] if out.suffix else out.name
    return {"native": out.with_name(f"{stem}.native.gpkg"), "pixels": out.with_name(f"{stem}.pixels.csv")}


def format_point(x: float, y: float) -> str:
    """A map point as text for messages, at 10 significant digits."""
    return f"({x:.10g}, {y:.10g})"


def points_to_pixels(
    grid: PlanningGrid, points: tuple[tuple[float, float], ...], crs: str | None
) -> tuple[list[tuple[int, int]], list[str]]:
    """Pixels holding each map point, and labels for messages; PlanError for a point outside."""
    where = f" {crs_label(parse_crs(crs))}" if crs else ""
    pixels, labels = [], []
    for name, (x, y) in zip(point_names(len(points)), points):
        label = f"{format_point(x, y)}{where}"
        row, col = grid.world_to_pixel(x, y, crs=crs)
        if not grid.contains(row, col):
            raise PlanError(
                f"{name} {label} is outside the costmap {Path(grid.source or '').name} "
                f"(bounds {_bounds_text(grid, crs)}){_lonlat_hint(grid, points, crs)}"
            )
        pixels.append((row, col))
        labels.append(label)
    return pixels, labels


def _lonlat_hint(grid: PlanningGrid, points: Sequence[tuple[float, float]], crs: str | None) -> str:
    """A hint when points given without a CRS look like longitude/latitude on a projected
    costmap (the usual mistake: degrees read as metres land next to the CRS's origin)."""
    g = grid.grid
    if crs is not None or g is None or g.crs is None or not getattr(g.crs, "is_projected", False):
        return ""
    if not all(abs(x) <= 180.0 and abs(y) <= 90.0 for x, y in points):
        return ""
    return "; these look like longitude/latitude; add --crs EPSG:4326"


def _bounds_text(grid: PlanningGrid, crs: str | None) -> str:
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
    #: The smoothed route (``overseec_core.plan.smooth.SmoothedRoute``) when smoothing was asked.
    smoothed: Any = None
    #: The properties the path files carry (``plan.export.path_properties``): the same figures
    #: under the same names as the GeoJSON and GeoPackage written.
    properties: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        """`overseec plan --json`: the written path's properties, under the file's own names
        (``total_cost``, ``length_m``, ... of the route the file holds; with ``--smooth`` the
        smoothed one, and the grid route under ``grid_route``), plus ``outputs``, ``timings`` and
        the planner's ``expanded`` count."""
        r = self.result
        doc: dict[str, Any] = dict(self.properties) or {
            "total_cost": r.cost,
            "length_m": r.length_m,
            "mode": r.mode,
            "requested_mode": r.requested_mode,
            "bound": r.bound,
            "gap": r.gap,
            "optimal": r.mode == "exact",
            "n_pixels": int(len(r.pixels)),
            "leg_costs": list(r.leg_costs),
            "seconds": r.seconds,
            "waypoints": self.waypoints,
            "notes": list(r.notes),
            **({} if self.smoothed is None else self.smoothed.properties()),
        }
        doc.update(
            prompt=self.prompt,
            expanded=r.expanded,
            outputs={k: str(v) for k, v in self.outputs.items()},
            timings=self.timings,
        )
        return doc


class RulePlanner:
    """A :class:`Planner` that enters keep-out zones only when no route exists without them.

    Keep-out zones are what distance rules forbid ("keep at least 20 m from buildings"), an
    entity a rule forbids itself ("never cross the railway") and obstacles nobody mentioned
    (buildings and water, by the interpreter's priors): the lethal sidecar flags all three alike
    (2). When a leg cannot be planned without them (a point inside one, or a zone cutting the
    map), that leg alone is planned again on
    :meth:`~overseec_core.plan.grid.PlanningGrid.entering_keep_out`, where zone cells cost
    :data:`~overseec_core.plan.grid.KEEP_OUT_ENTRY_COST` per metre on top of their own cost: the
    leg runs as few metres inside as it can and, among such routes, over the cheapest ground (in a
    zone around buildings, beside them rather than through them; across a strip it must not
    cross, at its narrowest, cheapest place). The leg's note says a keep-out rule cannot be met
    (naming the three kinds, which the sidecar does not tell apart) and by how much: metres
    inside the zone, and how many of those on avoided ground (own cost above neutral,
    :data:`~overseec_core.plan.grid.NEUTRAL_COST`). Its reported cost counts zone cells at their
    own cost, the costmap's value there (what the route really crosses; the entry price is a
    planning device, not a cost of the ground). The relaxed copy is built once, on first need,
    and reused for later queries.
    """

    def __init__(self, planner: Planner) -> None:
        self.strict = planner
        self._relaxed: Planner | None = None
        #: Planned routes that had to break a rule.
        self.rules_broken = 0

    @property
    def grid(self) -> PlanningGrid:
        return self.strict.grid

    def plan(
        self, points: Sequence[tuple[int, int]], *, mode: str = "exact", labels=None, progress=None
    ) -> tuple[PathResult, Planner]:
        """The route and the planner that found it (the strict one unless a rule was broken)."""
        try:
            return self.strict.plan(points, mode=mode, labels=labels, progress=progress), self.strict
        except PlanError:
            if self.grid.keep_out is None:
                raise
        if self._relaxed is None:
            s = self.strict  # the relaxed planner plans like the strict one (the worker's fast settings)
            self._relaxed = Planner(
                self.grid.entering_keep_out(),
                s.base_cost_per_m,
                coarse_factor=s.coarse_factor,
                corridor_blocks=s.corridor_blocks,
                bound_hops=s.bound_hops,
                tight_bound=s.tight_bound,
                coarse_trees=s.coarse_trees,
                neighbours=s.neighbours,
                elevation=None if s.elevation is None else s.elevation.reshape(s.shape),
                slope_model=s.slope_model,
            )
        legs, broken = [], []
        for i in range(len(points) - 1):
            leg_labels = None if labels is None else list(labels)[i : i + 2]
            try:
                legs.append(self.strict.plan(points[i : i + 2], mode=mode, labels=leg_labels, progress=progress))
            except PlanError:
                leg = self._relaxed.plan(points[i : i + 2], mode=mode, labels=leg_labels, progress=progress)
                legs.append(self._priced_at_own_cost(leg))
                broken.append((i, *self.metres_inside(leg.pixels)))
        result = _join(legs, mode)
        names = point_names(len(points))
        for i, inside, avoided in broken:
            result = replace(
                result,
                notes=tuple(result.notes)
                + (
                    f"a keep-out rule cannot be met between {names[i]} and {names[i + 1]} ({RULE_KINDS}): "
                    f"no route avoids it, so this one runs {inside:.1f} m inside "
                    f"({avoided:.1f} m of that on avoided ground)",
                ),
            )
        self.rules_broken += 1
        return result, self._relaxed

    def metres_inside(self, pixels: np.ndarray) -> tuple[float, float]:
        """Ground metres of a pixel route inside keep-out zones, and of those on avoided ground
        (own cost above neutral). A step counts by the mean of its two cells, like the planner
        prices it: the straight line between the cell centres is half in each cell, so a route
        crossing a zone one pixel wide runs one pixel's width inside it."""
        px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
        if self.grid.keep_out is None or len(px) < 2:
            return 0.0, 0.0
        inside = self.grid.keep_out[px[:, 0], px[:, 1]].astype(np.float64)
        avoided = inside * (self.grid.own_cost(px) > NEUTRAL_COST + AVOIDED_EPS)
        steps = step_lengths_m(px, *self.grid.pixel_size_m)
        return (
            math.fsum(0.5 * (inside[1:] + inside[:-1]) * steps),
            math.fsum(0.5 * (avoided[1:] + avoided[:-1]) * steps),
        )

    def _priced_at_own_cost(self, leg: PathResult) -> PathResult:
        """The leg's cost under the costmap's own values (zone cells included) instead of the
        planning price; a fast leg keeps its gap to the bound."""
        px = leg.pixels
        own = self.grid.own_cost(px)
        steps = step_lengths_m(px, *self.grid.pixel_size_m)
        cost = math.fsum((0.5 * (own[1:] + own[:-1]) + self.strict.base_cost_per_m) * steps)
        s = self.strict
        if s.neighbours == 16 or s.slope_model is not None:  # knight steps (four cells), slopes
            z = None if s.elevation is None else s.elevation.reshape(s.shape)
            cost = float(
                cumulative_path_cost(
                    self.grid, px, s.base_cost_per_m, own=True, elevation=z, slope_model=s.slope_model
                )[-1]
            )
        bound = max(0.0, cost - max(0.0, leg.cost - leg.bound))
        return replace(leg, cost=cost, bound=bound, leg_costs=(cost,))


def _join(legs: Sequence[PathResult], requested_mode: str) -> PathResult:
    """One route from consecutive legs (each leg's first pixel is the previous leg's last)."""
    pixels = np.concatenate([legs[0].pixels] + [leg.pixels[1:] for leg in legs[1:]])
    notes: list[str] = []
    for leg in legs:
        notes.extend(n for n in leg.notes if n not in notes)
    return PathResult(
        pixels=pixels,
        cost=sum(leg.cost for leg in legs),
        length_m=sum(leg.length_m for leg in legs),
        mode="fast" if any(leg.mode == "fast" for leg in legs) else "exact",
        bound=sum(leg.bound for leg in legs),
        seconds=sum(leg.seconds for leg in legs),
        waypoints=tuple(legs[0].waypoints[:1]) + tuple(leg.waypoints[-1] for leg in legs),
        leg_costs=tuple(c for leg in legs for c in leg.leg_costs),
        requested_mode=requested_mode,
        expanded=sum(leg.expanded for leg in legs),
        notes=tuple(notes),
    )


def plan_keeping_rules(
    grid: PlanningGrid,
    points: Sequence[tuple[int, int]],
    *,
    mode: str = "exact",
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M,
    labels=None,
    progress=None,
    neighbours: int = 8,
    elevation: np.ndarray | None = None,
    slope_model: str | None = None,
) -> tuple[PathResult, Planner]:
    """One query of a :class:`RulePlanner` on ``grid``: the route and the planner that found it
    (anisotropic with ``elevation`` on the grid and ``slope_model``)."""
    planner = Planner(grid, base_cost_per_m, neighbours=neighbours, elevation=elevation, slope_model=slope_model)
    return RulePlanner(planner).plan(points, mode=mode, labels=labels, progress=progress)


def dem_on_grid(dem: Path, grid: PlanningGrid) -> np.ndarray:
    """The DEM's elevations (float32 metres, NaN where it has none) on the costmap grid, read
    with :class:`~overseec_core.io.dem.DemReader` (bilinear, in tiles); one-line errors for a
    DEM that cannot be read or covers none of the grid. Cells it leaves without elevation are
    impassable to the anisotropic planner."""
    from rasterio.windows import Window

    from overseec_core.io.dem import DemReader

    with DemReader(dem, grid.need_grid()) as reader:
        z = reader.read(Window(0, 0, grid.width, grid.height))
    return z.astype(np.float32)


def terrain_properties(result: PathResult, grid: PlanningGrid, slope_model: str | None) -> dict[str, Any]:
    """What a route planned on a DEM adds to its files and manifest: the slope model and the
    ground length ``length_2d_m`` (``length_m`` counts the elevation change); {} without a DEM."""
    if slope_model is None:
        return {}
    return {"slope_model": slope_model, "length_2d_m": path_length_m(result.pixels, *grid.pixel_size_m)}


# --- the stage: costmap + points -> path files ---
def record_costmap_inputs(
    run: RunDir, stage: str, costmap: str | Path, grid: PlanningGrid, overrides: tuple[Any, Any], progress
) -> None:
    """Record in ``run``'s manifest what a planning stage read: the costmap, the lethal sidecar it
    found and the override polygons ``(OverrideSet | None, OverrideCounts | None)`` with their
    counts, under names prefixed by ``stage`` (plan, corridor)."""
    run.record_input(f"{stage}_costmap_{Path(costmap).name}", costmap)
    if grid.lethal_source:
        run.record_input(f"{stage}_lethal_{Path(grid.lethal_source).name}", grid.lethal_source)
    record_overrides(run, overrides[0], overrides[1], stage, progress)


@transactional
def run_plan(options: PlanOptions, progress: Progress | None = None, command_args: dict | None = None) -> PlanRunResult:
    """Costmap + map points (any CRS) -> a path: RFC 7946 GeoJSON (WGS 84) with cost, length,
    mode, bound and prompt; on request the path in the costmap's CRS (GeoPackage), its pixel
    indices and the cost-distance raster from the start. The output folder's manifest records
    the costmap (hashed), parameters, the result and timings."""
    o = options
    requested = {"geojson": o.out, "native": o.native_out, "pixels": o.pixels_out, "cumulative": o.cumulative_out}
    targets = {k: Path(v) for k, v in requested.items() if v is not None}
    if len({p.resolve() for p in targets.values()}) != len(targets):
        raise InputError("two outputs have the same path; give each output its own file")
    for path in targets.values():
        check_output_path(path, o.inputs())
    t0 = _time.perf_counter()
    grid = load_costmap(o.costmap, lethal_path=o.lethal, lethal_threshold=o.lethal_threshold, band=o.band)
    # the lethal sidecar found beside the costmap is an input too: never write over it
    inputs = o.inputs() + ([Path(grid.lethal_source)] if grid.lethal_source else [])
    for path in targets.values():
        check_output_path(path, inputs)
    grid, overrides, override_counts = with_overrides(grid, o.overrides)
    pixels, labels = points_to_pixels(grid, o.points, o.crs)
    elevation = None if o.dem is None else dem_on_grid(o.dem, grid)
    t1 = _time.perf_counter()
    result, planner = plan_keeping_rules(
        grid,
        pixels,
        mode=o.mode,
        base_cost_per_m=o.base_cost_per_m,
        labels=labels,
        progress=progress,
        neighbours=o.neighbours,
        elevation=elevation,
        slope_model=o.terrain_model,
    )
    t2 = _time.perf_counter()

    smoothed = smooth_if_asked(result, grid, o.base_cost_per_m, o.smooth, progress)
    line = None if smoothed is None else smoothed.vertices  # the geometry written
    prompt = find_prompt(grid)
    waypoints = waypoint_records(grid, result, o.points, o.crs)
    props = path_properties(result, grid, o.base_cost_per_m, waypoints, prompt, smoothed)
    plan_overrides = None
    if overrides is not None and override_counts is not None:  # both set above, or neither
        plan_overrides = overrides.summary(override_counts, "plan")
    props.update(path_override_properties(grid.tags, plan_overrides))
    terrain = terrain_properties(result, grid, o.terrain_model)
    props.update(terrain)
    write_geojson(targets["geojson"], path_geojson(result, grid, props, line), inputs)
    if "native" in targets:
        write_native_gpkg(targets["native"], result, grid, props, inputs, pixels=line)
    if "pixels" in targets:
        write_pixels(targets["pixels"], result, grid, o.base_cost_per_m, inputs)
    if "cumulative" in targets:
        write_cumulative(targets["cumulative"], planner, pixels[0], label=labels[0], inputs=inputs, progress=progress)
    timings = {
        "load_s": round(t1 - t0, 4),
        "plan_s": round(t2 - t1, 4),
        "write_s": round(_time.perf_counter() - t2, 4),
        "total_s": round(_time.perf_counter() - t0, 4),
    }
    timings.update({} if smoothed is None else {"smooth_s": round(smoothed.seconds, 4)})  # in write_s
    run = RunDir(targets["geojson"].parent, command="plan", args=command_args)
    record_costmap_inputs(run, "plan", o.costmap, grid, (overrides, override_counts), progress)
    if o.dem is not None:
        run.record_input(f"plan_dem_{Path(o.dem).name}", o.dem)
    run.update_parameters(
        plan={
            "mode": o.mode,
            "base_cost_per_m": o.base_cost_per_m,
            "lethal_threshold": o.lethal_threshold,
            "crs": o.crs,
            "points": [list(p) for p in o.points],
            "smooth": o.smooth,
            "neighbours": o.neighbours,
            "dem": None if o.dem is None else str(o.dem),
            "slope_model": o.terrain_model,
        }
    )
    run.set(
        "plan",
        {
            **result.to_json(),
            **terrain,
            "outputs": {k: p.name for k, p in targets.items()},
            "waypoints": waypoints,
            "prompt": prompt,
            "timings": timings,
            **({} if smoothed is None else {"smoothing": smoothed.to_json()}),
        },
    )
    run.save()
    return PlanRunResult(
        result=result,
        outputs=targets,
        waypoints=waypoints,
        prompt=prompt,
        timings=timings,
        smoothed=smoothed,
        properties=props,
    )
