"""Many routes on one loaded costmap: a table of start/goal pairs, and cost matrices.

``overseec plan COSTMAP --pairs FILE --out ROUTES.gpkg`` loads the costmap once and plans one
route per pair -- the same planner and keep-out rules as a single ``overseec plan`` (a
:class:`~overseec_core.plan.stage.RulePlanner`, buffers reused between queries) -- into one
GeoPackage layer (:data:`~overseec_core.runfiles.PAIRS_LAYER`) in the costmap's CRS, a feature per
pair with its id, cost and length. A pair that cannot be planned (a point outside the costmap or
on a lethal cell, no route) keeps its row, without geometry, with the reason in ``error``: one bad
row never loses the other routes. Progress counts routes; a cancel stops between and inside them.

``--matrix OUT.csv --points FILE`` writes the cost of the best route between every two points
(many-to-many), or from each point of ``--sources FILE`` to every point (one-to-many when it
holds one): one whole-grid search per source (:func:`~overseec_core.plan.corridor.costs_to`),
the same numbers as planning each pair.

Inputs: a CSV (``.csv``/``.txt``) with a header -- ``start_x,start_y,goal_x,goal_y`` and an
optional ``id`` for pairs, ``x,y`` and an optional ``id`` for points -- in the costmap's CRS unless
``--crs`` names another; or any vector layer (read with :func:`overseec_core.io.vectors.read_vector`
in its own CRS): lines for pairs (first vertex = start, last = goal), points for points, ids from
an ``id`` field when there is one, else the feature id.
"""

from __future__ import annotations

import csv
import io
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import runfiles
from overseec_core.errors import Cancelled, InputError, PlanError
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.grid import parse_crs
from overseec_core.io.manifest import RunDir
from overseec_core.io.transaction import transactional
from overseec_core.io.write import check_output_path
from overseec_core.limits import MAX_CSV_BYTES, read_csv_limited
from overseec_core.plan.corridor import costs_to
from overseec_core.plan.grid import PlanningGrid, load_costmap
from overseec_core.plan.paths import DEFAULT_BASE_COST_PER_M
from overseec_core.plan.planner import Planner, check_neighbours
from overseec_core.plan.result import PathResult
from overseec_core.progress import Progress

#: Suffixes read as CSV tables; anything else is opened as a vector layer.
CSV_SUFFIXES = (".csv", ".txt")
PAIR_COLUMNS = ("start_x", "start_y", "goal_x", "goal_y")
POINT_COLUMNS = ("x", "y")
#: Errors of unplanned pairs the manifest keeps (the GeoPackage keeps every one).
MANIFEST_ERRORS = 20
#: Most rows a table may hold (a cost matrix is rows x rows searches' worth of output).
MAX_ROWS = 100_000


@dataclass(frozen=True)
class Pair:
    """One start/goal pair: (x, y) map points in the CRS the table was read in."""

    id: str
    start: tuple[float, float]
    goal: tuple[float, float]


@dataclass(frozen=True)
class NamedPoint:
    """One point of a ``--points`` / ``--sources`` table."""

    id: str
    x: float
    y: float


# ------------------------------------------------------------------------------------------------
# Reading
# ------------------------------------------------------------------------------------------------


def _number(text: str | None, where: str, column: str) -> float:
    try:
        value = float(text or "")
    except ValueError:
        raise InputError(f"{where}: {column} is not a number ({text!r})") from None
    if not math.isfinite(value):
        raise InputError(f"{where}: {column} is not a finite number ({text!r})")
    return value


def _csv_rows(path: Path, label: str, columns: Sequence[str]) -> list[tuple[str, list[float]]]:
    """(id, values of ``columns``) per row of a CSV table with a header; ids default to the row number."""
    header, table = read_csv_limited(path, MAX_CSV_BYTES, label)  # bounded, pipes refused, field limits
    missing = [c for c in columns if c not in header]
    if missing:
        raise InputError(
            f"{label} {path}: needs the columns {','.join(columns)} (and optionally id); missing {', '.join(missing)}"
        )
    rows: list[tuple[str, list[float]]] = []
    for n, (_line, row) in enumerate(table, start=1):
        if len(rows) >= MAX_ROWS:
            raise InputError(f"{label} {path}: more than {MAX_ROWS} rows")
        if not any((v or "").strip() for v in row.values() if isinstance(v, str)):
            continue  # a blank line
        where = f"{label} {path} row {n}"
        ident = (row.get("id") or "").strip() or str(n)
        rows.append((ident, [_number(row.get(c), where, c) for c in columns]))
    if not rows:
        raise InputError(f"{label} {path}: no rows")
    _check_unique([r[0] for r in rows], label, path)
    return rows


def _check_unique(ids: Sequence[str], label: str, path: Path) -> None:
    seen: set[str] = set()
    for i in ids:
        if i in seen:
            raise InputError(f"{label} {path}: the id {i!r} is used twice; give each row its own id")
        seen.add(i)


def _feature_id(feature: Any) -> str:
    value = feature.properties.get("id") if feature.properties else None
    return str(value) if value not in (None, "") else str(feature.fid)


def read_pairs(path: str | Path, grid: PlanningGrid, crs: str | None) -> tuple[list[Pair], str | None]:
    """The pairs of a CSV table (in ``crs``) or a vector layer of lines (in the costmap's CRS
    after reading); returns them with the CRS their coordinates are in (None = the costmap's)."""
    from overseec_core.io.vectors import read_vector

    p = Path(path)
    if p.suffix.lower() in CSV_SUFFIXES:
        rows = _csv_rows(p, "--pairs", PAIR_COLUMNS)
        return [Pair(i, (v[0], v[1]), (v[2], v[3])) for i, v in rows], crs
    feats = read_vector(
        p, grid.need_grid().crs, label="--pairs", geometry_types=("LineString", "MultiPoint"), max_features=MAX_ROWS
    )
    if not feats:
        raise InputError(f"--pairs {p}: no lines (a start/goal pair is a line from the start to the goal)")
    pairs = []
    for f in feats:
        coords = [(float(x), float(y)) for x, y, *_ in _vertices(f.geometry)]
        pairs.append(Pair(_feature_id(f), coords[0], coords[-1]))
    _check_unique([q.id for q in pairs], "--pairs", p)
    return pairs, None


def _vertices(geometry: Any) -> list[tuple[float, ...]]:
    if geometry.geom_type == "MultiPoint":
        return [tuple(g.coords[0]) for g in geometry.geoms]
    return [tuple(c) for c in geometry.coords]


def read_points(
    path: str | Path, grid: PlanningGrid, crs: str | None, label: str
) -> tuple[list[NamedPoint], str | None]:
    """The points of a CSV table (``x,y[,id]`` in ``crs``) or a point layer (read in the
    costmap's CRS); returns them with the CRS their coordinates are in (None = the costmap's)."""
    from overseec_core.io.vectors import read_vector

    p = Path(path)
    if p.suffix.lower() in CSV_SUFFIXES:
        return [NamedPoint(i, v[0], v[1]) for i, v in _csv_rows(p, label, POINT_COLUMNS)], crs
    feats = read_vector(p, grid.need_grid().crs, label=label, geometry_types=("Point",), max_features=MAX_ROWS)
    if not feats:
        raise InputError(f"{label} {p}: no points")
    points = [NamedPoint(_feature_id(f), float(f.geometry.x), float(f.geometry.y)) for f in feats]
    _check_unique([q.id for q in points], label, p)
    return points, None


# ------------------------------------------------------------------------------------------------
# Planning
# ------------------------------------------------------------------------------------------------


class _CancelOnly:
    """A Progress that passes a cancel through but shows nothing: the pairs' own progress
    counts routes, not the legs inside each."""

    def __init__(self, outer: Progress | None) -> None:
        self.outer = outer

    def begin(self, stage: str, total: int | None, unit: str = "tile") -> None:
        """Nothing (one route's own stages are not shown)."""

    def advance(self, n: int = 1) -> None:
        """Nothing."""

    def end(self) -> None:
        """Nothing."""

    def message(self, text: str) -> None:
        """Passed on."""
        if self.outer is not None:
            self.outer.message(text)

    def cancelled(self) -> bool:
        """The outer progress's cancel."""
        return self.outer is not None and self.outer.cancelled()


@dataclass(frozen=True)
class PairRoute:
    """A pair and its route (None with ``error`` saying why it could not be planned)."""

    pair: Pair
    result: PathResult | None
    error: str | None = None

    def to_json(self) -> dict[str, Any]:
        """The route's figures (no pixels): id, total_cost (the name `plan --json` and the routes
        GeoPackage use), length, mode, error. ``cost`` is the same figure under its old name,
        kept for scripts written against it (deprecated; see CHANGELOG)."""
        r = self.result
        return {
            "id": self.pair.id,
            "total_cost": None if r is None else r.cost,
            "cost": None if r is None else r.cost,
            "length_m": None if r is None else r.length_m,
            "mode": None if r is None else r.mode,
            "n_pixels": 0 if r is None else int(len(r.pixels)),
            "error": self.error,
        }


def plan_pairs(
    grid: PlanningGrid,
    pairs: Sequence[Pair],
    crs: str | None,
    *,
    mode: str = "exact",
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M,
    neighbours: int = 8,
    progress: Progress | None = None,
) -> list[PairRoute]:
    """One route per pair on one planner (see the module docstring), with the planner's steps
    (``neighbours`` 8, or 16 with knight moves); Cancelled on a cancel."""
    from overseec_core.plan.stage import RulePlanner, points_to_pixels

    planner = RulePlanner(Planner(grid, base_cost_per_m, neighbours=neighbours))
    inner = _CancelOnly(progress)
    out: list[PairRoute] = []
    if progress is not None:
        progress.begin("pairs", total=len(pairs), unit="route")
    try:
        for pair in pairs:
            if inner.cancelled():
                raise Cancelled("planning cancelled by the user")
            try:
                pixels, labels = points_to_pixels(grid, (pair.start, pair.goal), crs)
                result, _ = planner.plan(pixels, mode=mode, labels=labels, progress=inner)
                out.append(PairRoute(pair, result))
            except (PlanError, InputError) as exc:
                out.append(PairRoute(pair, None, f"pair {pair.id}: {exc}"))
            if progress is not None:
                progress.advance(1)
    finally:
        if progress is not None:
            progress.end()
    return out


def cost_matrix(
    grid: PlanningGrid,
    sources: Sequence[NamedPoint],
    targets: Sequence[NamedPoint],
    crs: str | None,
    *,
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M,
    neighbours: int = 8,
    progress: Progress | None = None,
) -> np.ndarray:
    """(len(sources), len(targets)) float64 route costs, +inf where no route joins the two or
    either point lies on an impassable cell (:func:`blocked_points` names those): one whole-grid
    search per source, with the planner's steps (``neighbours``). PlanError for a point outside
    the costmap, and when every source is blocked."""
    from overseec_core.plan.stage import points_to_pixels

    planner = Planner(grid, base_cost_per_m, neighbours=neighbours)
    src_px, src_labels = points_to_pixels(grid, tuple((p.x, p.y) for p in sources), crs)
    dst_px, _ = points_to_pixels(grid, tuple((p.x, p.y) for p in targets), crs)
    open_src = _passable(grid, src_px)
    if not any(open_src):
        raise PlanError(f"every source of the matrix lies on an impassable cell: {_names(sources, open_src)}")
    inner = _CancelOnly(progress)
    matrix = np.full((len(sources), len(targets)), np.inf)
    if progress is not None:
        progress.begin("matrix", total=len(sources), unit="source")
    try:
        for i, (px, label) in enumerate(zip(src_px, src_labels)):
            if inner.cancelled():
                raise Cancelled("planning cancelled by the user")
            if not open_src[i]:  # its row stays empty; blocked_points names it
                if progress is not None:
                    progress.advance(1)
                continue
            matrix[i] = costs_to(planner, px, dst_px, label=f"{sources[i].id} {label}", progress=inner)
            if progress is not None:
                progress.advance(1)
    finally:
        if progress is not None:
            progress.end()
    return matrix


def _passable(grid: PlanningGrid, pixels: Sequence[tuple[int, int]]) -> list[bool]:
    """Whether a route may start or end on each pixel (not lethal, kept out or no data)."""
    return [bool(np.isfinite(grid.cost[r, c])) for r, c in pixels]


def _names(points: Sequence[NamedPoint], open_: Sequence[bool]) -> str:
    return ", ".join(repr(p.id) for p, ok in zip(points, open_) if not ok)


def blocked_points(grid: PlanningGrid, points: Sequence[NamedPoint], crs: str | None, what: str) -> str | None:
    """One note naming every point of ``points`` on an impassable (lethal, kept-out or no-data)
    cell, whose row or column of the matrix is left empty; None when there is none."""
    from overseec_core.plan.stage import points_to_pixels

    px, _ = points_to_pixels(grid, tuple((p.x, p.y) for p in points), crs)
    open_ = _passable(grid, px)
    if all(open_):
        return None
    n = open_.count(False)
    return f"{n} of the {what} lie on impassable cells, their costs left empty: {_names(points, open_)}"


# ------------------------------------------------------------------------------------------------
# Writing
# ------------------------------------------------------------------------------------------------

ROUTE_FIELDS = {
    "id": "str",
    "total_cost": "float",
    "length_m": "float",
    "mode": "str",
    "n_pixels": "int",
    "start_x": "float",
    "start_y": "float",
    "goal_x": "float",
    "goal_y": "float",
    "error": "str",
    "notes": "str",
}


def _route_record(route: PairRoute, grid: PlanningGrid) -> dict[str, Any]:
    r, p = route.result, route.pair
    geometry = None
    if r is not None:
        xs, ys = grid.pixel_to_world(r.pixels[:, 0], r.pixels[:, 1])
        coords = [(float(x), float(y)) for x, y in zip(np.atleast_1d(xs), np.atleast_1d(ys))]
        if len(coords) == 1:
            coords.append(coords[0])
        geometry = {"type": "LineString", "coordinates": coords}
    props = {
        "id": p.id,
        "total_cost": None if r is None else r.cost,
        "length_m": None if r is None else r.length_m,
        "mode": None if r is None else r.mode,
        "n_pixels": 0 if r is None else int(len(r.pixels)),
        "start_x": p.start[0],
        "start_y": p.start[1],
        "goal_x": p.goal[0],
        "goal_y": p.goal[1],
        "error": route.error,
        "notes": "" if r is None else "; ".join(r.notes),
    }
    return {"geometry": geometry, "properties": props}


def write_routes(path: str | Path, routes: Sequence[PairRoute], grid: PlanningGrid, inputs: Sequence[Path]) -> Path:
    """The routes as one GeoPackage layer (:data:`runfiles.PAIRS_LAYER`) in the costmap's CRS, atomically.

    ``start_x`` ... ``goal_y`` are the pair's points as given (in the table's CRS)."""
    from overseec_core.plan.export import write_gpkg

    out = check_output_path(path, inputs)
    records = [_route_record(r, grid) for r in routes]
    layers = [(runfiles.PAIRS_LAYER, {"geometry": "LineString", "properties": ROUTE_FIELDS}, records)]
    return write_gpkg(out, grid.need_grid().crs.to_wkt(), layers)


def matrix_csv(sources: Sequence[NamedPoint], targets: Sequence[NamedPoint], matrix: np.ndarray) -> str:
    """The matrix as CSV: a header ``from,<target ids>...``, one row per source, costs with
    full precision (``repr``), empty where no route joins the two."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["from", *(t.id for t in targets)])
    for s, row in zip(sources, matrix):
        w.writerow([s.id, *(repr(float(v)) if math.isfinite(v) else "" for v in row)])
    return buf.getvalue()


# ------------------------------------------------------------------------------------------------
# The stage
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PairsOptions:
    """`overseec plan --pairs/--matrix`: which tables, where to write, the planner's costs."""

    costmap: Path
    pairs: Path | None = None
    out: Path | None = None
    points: Path | None = None
    sources: Path | None = None
    matrix_out: Path | None = None
    crs: str | None = None
    mode: str = "exact"
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M
    #: Steps: 8 neighbours, or 16 with knight moves (``plan --neighbours``; the kernel's).
    neighbours: int = 8
    lethal: Path | None = None
    lethal_threshold: float | None = None
    band: int | None = None
    overrides: tuple[Path, ...] = ()

    def __post_init__(self) -> None:
        if self.pairs is None and self.matrix_out is None:
            raise InputError("give --pairs FILE (routes) or --matrix OUT.csv with --points FILE (costs)")
        if self.pairs is None and self.out is not None:
            raise InputError("--out names the routes of --pairs; --matrix writes only its CSV")
        if self.pairs is not None and self.out is None:
            raise InputError("--pairs needs --out ROUTES.gpkg")
        if self.out is not None and self.pairs is not None and Path(self.out).suffix.lower() != ".gpkg":
            raise InputError(f"--pairs writes a GeoPackage: name --out ROUTES.gpkg, not {Path(self.out).name}")
        if self.matrix_out is not None and self.points is None:
            raise InputError("--matrix needs --points FILE (the points to price routes between)")
        if (self.points is not None or self.sources is not None) and self.matrix_out is None:
            raise InputError("--points/--sources go with --matrix OUT.csv")
        check_neighbours(self.neighbours)
        if self.crs is not None:
            parse_crs(self.crs)

    def inputs(self) -> list[Path]:
        """The files read (never written over)."""
        files = (self.costmap, self.lethal, self.pairs, self.points, self.sources, *self.overrides)
        return [Path(p) for p in files if p is not None]

    def targets(self) -> dict[str, Path]:
        """The files written, by kind."""
        found = {"routes": self.out if self.pairs is not None else None, "matrix": self.matrix_out}
        return {k: Path(v) for k, v in found.items() if v is not None}


@dataclass(frozen=True)
class PairsRunResult:
    """What a pairs/matrix run planned and wrote."""

    routes: list[PairRoute]
    matrix: np.ndarray | None
    outputs: dict[str, Path]
    timings: dict[str, float] = field(default_factory=dict)
    #: What the run wants the user to know (points on impassable cells, their costs left empty).
    notes: list[str] = field(default_factory=list)

    @property
    def failed(self) -> int:
        """Pairs without a route."""
        return sum(1 for r in self.routes if r.result is None)

    def summary(self, outputs: dict[str, str]) -> dict[str, Any]:
        """What the manifest records: counts, the first :data:`MANIFEST_ERRORS` errors, the
        matrix's shape, outputs and timings (every route's figures are in the GeoPackage)."""
        doc: dict[str, Any] = {
            "pairs": len(self.routes),
            "planned": len(self.routes) - self.failed,
            "failed": self.failed,
            "errors": [r.error for r in self.routes if r.error][:MANIFEST_ERRORS],
            "outputs": outputs,
            "timings": self.timings,
        }
        if self.matrix is not None:
            doc["matrix_shape"] = list(self.matrix.shape)
        if self.notes:
            doc["notes"] = list(self.notes)
        return doc

    def to_json(self) -> dict[str, Any]:
        """`overseec plan --pairs ... --json`: every route's figures, the matrix's shape, outputs, timings."""
        doc: dict[str, Any] = {
            "routes": [r.to_json() for r in self.routes],
            "planned": len(self.routes) - self.failed,
            "failed": self.failed,
        }
        if self.matrix is not None:
            doc["matrix_shape"] = list(self.matrix.shape)
        doc.update(outputs={k: str(v) for k, v in self.outputs.items()}, timings=self.timings, notes=list(self.notes))
        return doc


def _load(o: PairsOptions) -> tuple[PlanningGrid, Any, Any]:
    """The costmap with its overrides applied in memory, the overrides and their counts."""
    from overseec_core.plan.overrides import with_overrides

    return with_overrides(
        load_costmap(o.costmap, lethal_path=o.lethal, lethal_threshold=o.lethal_threshold, band=o.band), o.overrides
    )


@transactional
def run_pairs(
    options: PairsOptions, progress: Progress | None = None, command_args: dict | None = None
) -> PairsRunResult:
    """Costmap + pairs table -> routes GeoPackage; + points table -> cost matrix CSV; one costmap
    load for both, recorded in the output folder's manifest."""
    from overseec_core.plan.stage import record_costmap_inputs

    o = options
    targets = o.targets()
    if len({p.resolve() for p in targets.values()}) != len(targets):
        raise InputError("two outputs have the same path; give each output its own file")
    for path in targets.values():
        check_output_path(path, o.inputs())
    t0 = time.perf_counter()
    grid, overrides, counts = _load(o)
    grid.need_grid()
    inputs = o.inputs() + ([Path(grid.lethal_source)] if grid.lethal_source else [])
    routes: list[PairRoute] = []
    matrix = None
    if o.pairs is not None:
        pairs, crs = read_pairs(o.pairs, grid, o.crs)
        routes = plan_pairs(
            grid, pairs, crs, mode=o.mode, base_cost_per_m=o.base_cost_per_m, neighbours=o.neighbours, progress=progress
        )
        if all(r.result is None for r in routes):
            raise PlanError(f"no pair of {o.pairs} could be planned; the first: {routes[0].error}")
        write_routes(targets["routes"], routes, grid, inputs)
    t1 = time.perf_counter()
    notes: list[str] = []
    if o.points is not None and o.matrix_out is not None:
        points, pcrs = read_points(o.points, grid, o.crs, "--points")
        sources, scrs = read_points(o.sources, grid, o.crs, "--sources") if o.sources else (points, pcrs)
        if scrs != pcrs:  # a vector layer's points are in the costmap's CRS, a table's in --crs
            raise InputError("--sources and --points must both be tables or both be vector layers")
        matrix = cost_matrix(
            grid, sources, points, pcrs, base_cost_per_m=o.base_cost_per_m, neighbours=o.neighbours, progress=progress
        )
        groups = [(points, "points")] if o.sources is None else [(sources, "sources"), (points, "points")]
        notes += [n for pts, what in groups if (n := blocked_points(grid, pts, pcrs, what)) is not None]
        write_text_atomic(targets["matrix"], matrix_csv(sources, points, matrix))
    timings = {
        "pairs_s": round(t1 - t0, 4),
        "matrix_s": round(time.perf_counter() - t1, 4),
        "total_s": round(time.perf_counter() - t0, 4),
    }
    done = PairsRunResult(routes, matrix, targets, timings, notes)
    first = next(iter(targets.values()))
    run = RunDir(first.parent, command="plan", args=command_args)
    record_costmap_inputs(run, "plan", o.costmap, grid, (overrides, counts), progress)
    for kind, table in (("pairs", o.pairs), ("points", o.points), ("sources", o.sources)):
        if table is not None:
            run.record_input(f"plan_{kind}_{Path(table).name}", table)
    run.update_parameters(
        plan_pairs={
            "mode": o.mode,
            "base_cost_per_m": o.base_cost_per_m,
            "neighbours": o.neighbours,
            "crs": o.crs,
            "lethal_threshold": o.lethal_threshold,
        }
    )
    run.set("plan_pairs", done.summary(outputs={k: p.name for k, p in targets.items()}))
    run.save()
    return done


__all__ = [
    "NamedPoint",
    "Pair",
    "PairRoute",
    "PairsOptions",
    "PairsRunResult",
    "cost_matrix",
    "matrix_csv",
    "plan_pairs",
    "read_pairs",
    "read_points",
    "run_pairs",
    "write_routes",
]
