"""Writing planned paths for GIS users and for other planners.

- RFC 7946 GeoJSON: a FeatureCollection with one LineString Feature through the pixel centres of
  the path, in WGS 84 longitude/latitude (the only CRS RFC 7946 allows), with the path's cost,
  length, mode, bound, costmap, prompt and waypoints as properties.
- The same path in the costmap's own CRS as a GeoPackage (layers ``path`` and ``waypoints``).
  A GeoPackage, not GeoJSON with a legacy "crs" member: RFC 7946 removed that member, GDAL/QGIS
  only honour it as an authority name (a CRS without an EPSG code, such as a local or custom
  projection, is lost), while a GeoPackage stores the full WKT and opens in QGIS with its CRS.
- Pixel indices as CSV (``index,row,col,x,y,cum_cost``) or JSON, with the grid's transform, for
  robotics users who feed the path (or the costmap) to their own planner.
- The cost-distance raster from the start (float32, NaN unreachable) on the costmap's grid.

Every file is written to a temporary name beside the target, checked (rasters and GeoPackages
are reopened), flushed to the disk and renamed when complete; a full disk is one OutputError
(``cannot write PATH: no space left on device``) and leaves neither the file nor a temporary one.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import sys
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager, redirect_stderr
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import runfiles
from overseec_core.errors import OutputError
from overseec_core.io.atomic import atomic_path, output_error, space_reason, write_text_atomic
from overseec_core.io.grid import crs_label
from overseec_core.io.write import RasterWriter, check_output_path, gdal_errors
from overseec_core.plan.grid import PlanningGrid
from overseec_core.plan.paths import cumulative_path_cost, point_names
from overseec_core.plan.planner import Planner
from overseec_core.plan.result import PathResult
from overseec_core.progress import Progress

WGS84 = "EPSG:4326"
#: Decimal places of longitude/latitude in GeoJSON: 1e-9 degrees is about 0.1 mm.
LONLAT_DECIMALS = 9
#: Costmap tags naming the cost program and its source (written by the costmap stage).
PROGRAM_TAG = "OVERSEEC_PROGRAM_FILE"


def find_prompt(grid: PlanningGrid) -> str | None:
    """The mission prompt behind a costmap: its tags, else the manifest.json beside it."""
    if grid.prompt:
        return grid.prompt
    if not grid.source:
        return None
    src = Path(grid.source)
    manifest = src.parent / runfiles.MANIFEST
    try:
        data = json.loads(manifest.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict):
        return None
    costmap = data.get("costmap")
    if isinstance(costmap, dict) and costmap.get("file") not in (None, src.name):
        return None  # the manifest describes another costmap in this folder
    prompt = (
        (data.get("parameters") or {}).get("costmap", {}).get("prompt")
        if isinstance(data.get("parameters"), dict)
        else None
    )
    if not prompt:
        interp = (
            (data.get("cost_program") or {}).get("interpretation")
            if isinstance(data.get("cost_program"), dict)
            else None
        )
        prompt = interp.get("prompt") if isinstance(interp, dict) else None
    return str(prompt) if prompt else None


def waypoint_records(
    grid: PlanningGrid,
    result: PathResult,
    requested: Sequence[tuple[float, float]] | None = None,
    requested_crs: str | None = None,
) -> list[dict[str, Any]]:
    """One record per waypoint: name, pixel, pixel-centre coordinates (native and lon/lat),
    and the coordinates the user asked for."""
    pts = np.array(result.waypoints, dtype=np.int64)
    n = len(pts)
    names = point_names(n)
    xs, ys = grid.pixel_to_world(pts[:, 0], pts[:, 1])
    lons, lats = grid.pixel_to_world(pts[:, 0], pts[:, 1], crs=WGS84)
    out = []
    for i in range(n):
        rec: dict[str, Any] = {
            "name": names[i],
            "row": int(pts[i, 0]),
            "col": int(pts[i, 1]),
            "x": float(xs[i]),
            "y": float(ys[i]),
            "lon": round(float(lons[i]), LONLAT_DECIMALS),
            "lat": round(float(lats[i]), LONLAT_DECIMALS),
        }
        if requested is not None:
            rec["requested"] = [float(requested[i][0]), float(requested[i][1])]
            rec["requested_crs"] = requested_crs or crs_label(grid.need_grid().crs)
        out.append(rec)
    return out


def path_properties(
    result: PathResult,
    grid: PlanningGrid,
    base_cost_per_m: float,
    waypoints: list[dict[str, Any]],
    prompt: str | None,
    smoothed: Any = None,
) -> dict[str, Any]:
    """The properties every path output carries.

    With ``smoothed`` (a :class:`~overseec_core.plan.smooth.SmoothedRoute`) the geometry is the
    smoothed line: ``total_cost``, ``length_m`` and ``leg_costs`` describe it (cell-integral
    rule), ``grid_route`` and ``smoothing`` summarise the planner's pixel route and the change;
    ``n_pixels``, ``bound``, ``gap`` and ``optimal`` stay those of the grid route.
    """
    g = grid.grid
    props = {
        "total_cost": result.cost,
        "length_m": result.length_m,
        "mode": result.mode,
        "requested_mode": result.requested_mode,
        "bound": result.bound,
        "gap": result.gap,
        "optimal": result.mode == "exact",
        "n_pixels": int(len(result.pixels)),
        "base_cost_per_m": base_cost_per_m,
        "leg_costs": list(result.leg_costs),
        "seconds": round(result.seconds, 6),
        "costmap": None if grid.source is None else str(Path(grid.source).resolve()),
        "lethal_mask": None if grid.lethal_source is None else str(Path(grid.lethal_source).resolve()),
        "lethal_threshold": grid.lethal_threshold,
        "cost_program": grid.tags.get(PROGRAM_TAG),
        "prompt": prompt,
        "costmap_crs": crs_label(g.crs) if g is not None else None,
        "pixel_size_m": list(grid.pixel_size_m),
        "waypoints": waypoints,
        "notes": list(result.notes),
    }
    if smoothed is not None:
        props.update(smoothed.properties())
    return props


def path_geojson(
    result: PathResult, grid: PlanningGrid, properties: dict[str, Any], pixels: np.ndarray | None = None
) -> dict[str, Any]:
    """RFC 7946 FeatureCollection: one LineString through the path's pixel centres (or through
    ``pixels``, e.g. the smoothed route's vertices), lon/lat."""
    px = result.pixels if pixels is None else pixels
    lons, lats = grid.pixel_to_world(px[:, 0], px[:, 1], crs=WGS84)
    lons = np.round(np.atleast_1d(lons), LONLAT_DECIMALS)
    lats = np.round(np.atleast_1d(lats), LONLAT_DECIMALS)
    coords = [[float(x), float(y)] for x, y in zip(lons, lats)]
    if len(coords) == 1:  # start == goal: a LineString needs two positions
        coords.append(list(coords[0]))
    bbox = [float(lons.min()), float(lats.min()), float(lons.max()), float(lats.max())]
    feature = {
        "type": "Feature",
        "bbox": bbox,
        "geometry": {"type": "LineString", "coordinates": coords},
        "properties": properties,
    }
    return {"type": "FeatureCollection", "bbox": bbox, "features": [feature]}


def write_geojson(
    path: str | os.PathLike, collection: dict[str, Any], inputs: Iterable[str | os.PathLike] = ()
) -> Path:
    """Write a GeoJSON feature collection atomically to ``path`` (checked not to overwrite one of
    ``inputs``); NaN is refused, since GeoJSON has no such number."""
    out = check_output_path(path, inputs)
    text = json.dumps(collection, allow_nan=False, separators=(",", ":"))
    return write_text_atomic(out, text + "\n")


def write_native_gpkg(
    path: str | os.PathLike,
    result: PathResult,
    grid: PlanningGrid,
    properties: dict[str, Any],
    inputs: Iterable[str | os.PathLike] = (),
    pixels: np.ndarray | None = None,
) -> Path:
    """GeoPackage in the costmap's CRS: layer 'path' (LineString through the pixel centres of
    the route, or of ``pixels``) and 'waypoints' (Points)."""

    out = check_output_path(path, inputs)
    px = result.pixels if pixels is None else pixels
    xs, ys = grid.pixel_to_world(px[:, 0], px[:, 1])
    coords = [(float(x), float(y)) for x, y in zip(np.atleast_1d(xs), np.atleast_1d(ys))]
    if len(coords) == 1:
        coords.append(coords[0])
    wkt = grid.need_grid().crs.to_wkt()
    path_fields = {
        "total_cost": "float",
        "length_m": "float",
        "mode": "str",
        "bound": "float",
        "gap": "float",
        "n_pixels": "int",
        "base_cost_per_m": "float",
        "costmap": "str",
        "prompt": "str",
        "waypoints": "str",
        "notes": "str",
    }
    path_schema = {"geometry": "LineString", "properties": path_fields}
    record = {
        "geometry": {"type": "LineString", "coordinates": coords},
        "properties": {
            "total_cost": properties["total_cost"],
            "length_m": properties["length_m"],
            "mode": properties["mode"],
            "bound": properties["bound"],
            "gap": properties["gap"],
            "n_pixels": properties["n_pixels"],
            "base_cost_per_m": properties["base_cost_per_m"],
            "costmap": properties["costmap"],
            "prompt": properties["prompt"],
            "waypoints": json.dumps(properties["waypoints"]),
            "notes": "; ".join(properties["notes"]),
        },
    }
    for key in ("grid_route", "smoothing"):  # smoothed routes: the summaries as JSON text
        if key in properties:
            path_fields[key] = "str"
            record["properties"][key] = json.dumps(properties[key])
    wp_schema = {"geometry": "Point", "properties": {"name": "str", "row": "int", "col": "int"}}
    wps = [
        {
            "geometry": {"type": "Point", "coordinates": (w["x"], w["y"])},
            "properties": {"name": w["name"], "row": w["row"], "col": w["col"]},
        }
        for w in properties["waypoints"]
    ]
    layers = [("path", path_schema, [record]), ("waypoints", wp_schema, wps)]
    return write_gpkg(out, wkt, layers)


def write_gpkg(out: Path, wkt: str, layers: Sequence[tuple[str, dict, list[dict]]]) -> Path:
    """Write (name, fiona schema, records) layers in CRS ``wkt`` as one GeoPackage at ``out``,
    atomically: read back and checked before it takes the final name; GDAL's messages (a full
    disk among them) become one-line OutputErrors and a failed file leaves nothing behind."""
    import fiona

    # fiona's Env first: our GDAL handler must be on top of the stack to see every message
    with fiona.Env(), gdal_errors() as messages, _unraisable_into(messages):
        with atomic_path(out, suffix=".partial.gpkg", sidecars=SQLITE_SIDECARS) as tmp:
            tmp.unlink()  # the driver creates the file itself
            try:
                _write_gpkg_layers(tmp, wkt, layers)
                problem = _check_gpkg(tmp, layers)
            except (OSError, RuntimeError, fiona.errors.FionaError) as exc:
                raise output_error(out, exc, messages, tmp) from None
            if problem or space_reason(None, messages):
                raise output_error(out, None, [problem] if problem else messages, tmp)
    return out


#: Files SQLite may leave beside a GeoPackage being written (deleted with a failed one).
SQLITE_SIDECARS = ("-journal", "-wal", "-shm")


@contextmanager
def _unraisable_into(messages: list[str]) -> Iterator[None]:
    """Collect, instead of printing, exceptions Python cannot raise (``Exception ignored in``).

    fiona 1.9 closing a layer after a failed write raises its flush error inside a Cython
    destructor, which prints a traceback to ``sys.stderr`` and then calls the unraisable hook;
    the write is already failing with one line. Both are redirected for the duration.
    """
    previous = sys.unraisablehook
    buffer = io.StringIO()

    def collect(unraisable) -> None:
        messages.append(" ".join(str(unraisable.exc_value).split()))

    sys.unraisablehook = collect
    try:
        with redirect_stderr(buffer):
            yield
    finally:
        sys.unraisablehook = previous


def _write_gpkg_layers(tmp: Path, wkt: str, layers: Sequence[tuple[str, dict, list]]) -> None:
    """Write each (name, schema, records) as a layer of the GeoPackage ``tmp``, in the CRS ``wkt``."""
    import fiona

    for name, schema, records in layers:
        with fiona.open(tmp, "w", driver="GPKG", layer=name, schema=schema, crs_wkt=wkt) as dst:
            dst.writerecords(records)


def _check_gpkg(tmp: Path, layers: Sequence[tuple[str, dict, list]]) -> str | None:
    """Reopen a written GeoPackage: None when every layer holds its records, else what is wrong.

    SQLite on a full disk can fail a statement that fiona does not report, or leave the
    database without its tables; a file that does not read back is never renamed into place.
    """
    import fiona

    for name, _schema, records in layers:
        with fiona.open(tmp, layer=name) as src:
            if len(src) != len(records):
                return f"incomplete file: layer {name} has {len(src)} of {len(records)} features"
    return None


def write_pixels(
    path: str | os.PathLike,
    result: PathResult,
    grid: PlanningGrid,
    base_cost_per_m: float,
    inputs: Iterable[str | os.PathLike] = (),
) -> Path:
    """Pixel indices of the path: CSV (index,row,col,x,y,cum_cost) or JSON, by file suffix.

    ``cum_cost`` counts keep-out cells at their own cost, as ``total_cost`` does for a route that
    had to enter them (on the strict ``grid`` they are impassable: the sum would turn infinite
    there, and JSON has no infinity)."""
    out = check_output_path(path, inputs)
    px = result.pixels
    cum = cumulative_path_cost(grid, px, base_cost_per_m, own=True)
    geo = grid.grid
    if geo is not None:
        wx, wy = grid.pixel_to_world(px[:, 0], px[:, 1])
        xs, ys = np.atleast_1d(wx), np.atleast_1d(wy)
    else:
        xs = ys = np.full(len(px), np.nan)
    if out.suffix.lower() == ".json":
        doc: dict[str, Any] = {
            "rows": px[:, 0].tolist(),
            "cols": px[:, 1].tolist(),
            "cum_cost": cum.tolist(),
            "shape": [grid.height, grid.width],
            "pixel_size_m": list(grid.pixel_size_m),
            "total_cost": result.cost,
            "length_m": result.length_m,
            "mode": result.mode,
            "note": "row/col index the costmap's pixels (row 0 = top); x/y are pixel centres in crs",
        }
        if geo is not None:
            doc.update(
                crs=crs_label(geo.crs),
                crs_wkt=geo.crs.to_wkt(),
                transform=list(geo.transform)[:6],
                x=xs.tolist(),
                y=ys.tolist(),
            )
        return write_text_atomic(out, json.dumps(doc, allow_nan=False) + "\n")
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["index", "row", "col", "x", "y", "cum_cost"])
    for i, (r, c) in enumerate(px.tolist()):
        x, y = ("", "") if geo is None else (f"{xs[i]:.6f}", f"{ys[i]:.6f}")
        w.writerow([i, r, c, x, y, f"{cum[i]:.9g}"])
    return write_text_atomic(out, buf.getvalue())


def write_cumulative(
    path: str | os.PathLike,
    planner: Planner,
    start: tuple[int, int],
    *,
    label: str | None = None,
    inputs: Iterable[str | os.PathLike] = (),
    progress: Progress | None = None,
) -> Path:
    """Cost-distance from ``start`` to every cell (float32, NaN unreachable), on the costmap's grid."""
    grid = planner.grid
    if grid.grid is None:
        raise OutputError("a cost-distance raster needs a georeferenced costmap")
    planner.expand(start, label=label, progress=progress)
    tags = {
        "OVERSEEC_START_ROW": str(start[0]),
        "OVERSEEC_START_COL": str(start[1]),
        "OVERSEEC_BASE_COST_PER_M": repr(planner.base_cost_per_m),
    }
    if grid.source:
        tags["OVERSEEC_COSTMAP_FILE"] = Path(grid.source).name
    with RasterWriter(
        path, grid.grid, 1, "float32", nodata=math.nan, descriptions=["cumulative_cost"], tags=tags, inputs=inputs
    ) as w:
        step = max(1, w.block_rows)
        for r0 in range(0, grid.height, step):
            w.write(planner.cumulative_rows(r0, min(grid.height, r0 + step)), r0)
    return Path(path)
