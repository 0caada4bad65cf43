"""Planned paths for GPS units, Google Earth and robot stacks: GPX, KML and CSV.

The input is the RFC 7946 GeoJSON ``overseec plan`` writes (WGS 84 lon/lat through pixel
centres, with the prompt, cost, length and waypoints as properties); any FeatureCollection of
LineStrings in lon/lat reads the same way. Any other vector file GDAL reads (the plugin's
``paths.gpkg``, whose tables hold one costmap's routes each, a Shapefile, FlatGeobuf ...) is read
through :func:`overseec_core.io.vectors.read_vector` in any CRS and reprojected to WGS 84; its
line features are the paths, their attributes the properties, and a ``waypoints`` attribute in
WKT (the plugin's MULTIPOINT of start, vias and goal, in the layer's CRS) gives the waypoints.

- **GPX 1.1**: one track per path (``trk/name`` the prompt, ``desc`` cost, length and mode), its
  points as ``trkpt lat lon``, and the start, via and goal points as ``wpt``.
- **KML 2.2**: a ``path`` folder with one LineString Placemark per path, a ``waypoints`` folder
  with a Point Placemark for the start, each via and the goal.
- **CSV** in the costmap's CRS (``--frame crs``) or in the local metric frame of a Nav2 map
  (``--frame nav2``): ``path,index,x,y,length_m,cost`` -- cumulative ground length in metres
  (pixel steps times the ground pixel size, like the planner's ``length_m``; Euclidean in the
  Nav2 frame when no costmap is at hand) and the cost of the cell under each vertex (empty
  without a costmap). Vertices of a path planned on the costmap are snapped back onto the exact
  cell centres (the GeoJSON rounds them to 1e-9 degree).
"""

from __future__ import annotations

import csv
import io
import math
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import __version__, defaults
from overseec_core.errors import InputError
from overseec_core.interop.frames import LocalFrame
from overseec_core.io.grid import Grid
from overseec_core.io.read import open_raster
from overseec_core.limits import MAX_JSON_BYTES, read_json_limited

PATH_FORMATS, FRAMES = defaults.PATH_FORMATS, defaults.PATH_FRAMES
GPX_NS = "http://www.topografix.com/GPX/1/1"
KML_NS = "http://www.opengis.net/kml/2.2"
CSV_COLUMNS = ("path", "index", "x", "y", "length_m", "cost")


@dataclass(frozen=True)
class PathFeature:
    """One path: (N, 2) lon/lat (WGS 84) and the GeoJSON feature's properties."""

    lonlat: np.ndarray
    properties: Mapping[str, Any] = field(default_factory=dict)

    @property
    def name(self) -> str:
        prompt = self.properties.get("prompt")
        return str(prompt) if prompt else "overseec path"

    @property
    def description(self) -> str:
        """Cost, length and mode, as far as the properties say."""
        p = self.properties
        parts = []
        if isinstance(p.get("total_cost"), (int, float)):
            parts.append(f"cost {p['total_cost']:.6g}")
        if isinstance(p.get("length_m"), (int, float)):
            parts.append(f"length {p['length_m']:.1f} m")
        if p.get("mode"):
            parts.append(f"mode {p['mode']}")
        if p.get("costmap"):
            parts.append(f"costmap {Path(str(p['costmap'])).name}")
        return "; ".join(parts) or "overseec path"

    def waypoints(self) -> list[tuple[str, float, float]]:
        """(name, lon, lat) of the start, vias and goal: the plan's records, else the ends."""
        recs = self.properties.get("waypoints")
        out = []
        if isinstance(recs, list):
            for i, r in enumerate(recs):
                if isinstance(r, dict) and _finite(r.get("lon")) and _finite(r.get("lat")):
                    out.append((str(r.get("name") or f"point {i}"), float(r["lon"]), float(r["lat"])))
        if len(out) >= 2:
            return out
        (lon0, lat0), (lon1, lat1) = self.lonlat[0], self.lonlat[-1]
        return [("start", float(lon0), float(lat0)), ("goal", float(lon1), float(lat1))]


def _finite(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def parse_paths(doc: Any, name: str = "path") -> tuple[PathFeature, ...]:
    """The LineString features of a GeoJSON document (FeatureCollection, Feature or geometry)."""
    if isinstance(doc, dict) and doc.get("type") == "FeatureCollection":
        features = doc.get("features") or []
    elif isinstance(doc, dict) and doc.get("type") == "Feature":
        features = [doc]
    elif isinstance(doc, dict) and doc.get("type") == "LineString":
        features = [{"type": "Feature", "geometry": doc, "properties": {}}]
    else:
        raise InputError(f"{name}: not GeoJSON (expected a FeatureCollection of LineStrings)")
    out = []
    for f in features:
        geom = f.get("geometry") if isinstance(f, dict) else None
        if not isinstance(geom, dict) or geom.get("type") != "LineString":
            continue
        try:
            coords = np.array(
                [[float(c[0]), float(c[1])] for c in geom.get("coordinates") or []], dtype=np.float64
            ).reshape(-1, 2)
        except (TypeError, ValueError, IndexError):
            raise InputError(f"{name}: a LineString has malformed coordinates") from None
        if len(coords) < 2:
            raise InputError(f"{name}: a LineString needs at least two positions")
        if not (
            np.isfinite(coords).all() and (np.abs(coords[:, 0]) <= 180).all() and (np.abs(coords[:, 1]) <= 90).all()
        ):
            raise InputError(f"{name}: coordinates must be WGS 84 longitude/latitude (RFC 7946)")
        props = f.get("properties") if isinstance(f.get("properties"), dict) else {}
        out.append(PathFeature(lonlat=coords, properties=props))
    if not out:
        raise InputError(f"{name}: no LineString feature (is this a path from overseec plan?)")
    return tuple(out)


#: Suffixes read as GeoJSON text (the planner's own output); any other file goes through GDAL.
GEOJSON_SUFFIXES = (".geojson", ".json")
#: Most line features a vector path file may hold (a paths table of a long session is far less).
MAX_PATH_FEATURES = 10_000


def read_paths(path: str | Path, layer: str | None = None) -> tuple[PathFeature, ...]:
    """Read the paths of a GeoJSON (bounded read; it holds one layer, so ``layer`` is moot) or of
    any other vector file's line layer (see :func:`read_vector_paths`); one-line errors."""
    p = Path(path)
    if p.suffix.lower() not in GEOJSON_SUFFIXES:
        return read_vector_paths(p, layer)
    doc = read_json_limited(p, MAX_JSON_BYTES, "path")
    return parse_paths(doc, f"path {p}")


def read_vector_paths(path: Path, layer: str | None = None) -> tuple[PathFeature, ...]:
    """The line features of a vector file's layer as paths in WGS 84: ``layer`` names the table
    of a file holding several (required then: the plugin's ``paths.gpkg`` keeps one per
    costmap); a MultiLineString gives one path per part. A ``waypoints`` attribute in WKT (the
    plugin's start, vias and goal) becomes the waypoint records GeoJSON paths carry."""
    from pyproj import CRS as ProjCRS  # noqa: N811 (pyproj's CRS)
    from pyproj import Transformer
    from rasterio.crs import CRS

    from overseec_core.io.vectors import read_vector, vector_layers

    label = "path"
    if layer is None:
        names = vector_layers(path, label, noun="path file")
        if len(names) > 1:
            raise InputError(f"{label} {path}: {len(names)} layers ({', '.join(names)}); name one with --layer")
    wgs84 = CRS.from_epsg(4326)
    features = read_vector(
        path,
        wgs84,
        label=label,
        geometry_types=("LineString", "MultiLineString"),
        max_features=MAX_PATH_FEATURES,
        noun="path file",
        layer=layer,
    )
    crs_wkt = _layer_crs_wkt(path, layer)
    to_wgs84 = Transformer.from_crs(ProjCRS.from_wkt(crs_wkt), ProjCRS.from_epsg(4326), always_xy=True)
    out = []
    for f in features:
        props = {k: v for k, v in f.properties.items() if v is not None}
        waypoints = _waypoint_records(props.pop("waypoints", None), to_wgs84)
        if waypoints:
            props["waypoints"] = waypoints
        parts = f.geometry.geoms if f.geometry.geom_type == "MultiLineString" else [f.geometry]
        for part in parts:
            coords = np.asarray(part.coords, dtype=np.float64)[:, :2]
            if len(coords) >= 2:
                out.append(PathFeature(lonlat=coords, properties=props))
    if not out:
        where = f" layer {layer}" if layer else ""
        raise InputError(f"{label} {path}{where}: no line feature (is this a layer of planned paths?)")
    return tuple(out)


def _layer_crs_wkt(path: Path, layer: str | None) -> str:
    """The CRS of a vector layer read_vector has read (so it has one) as WKT."""
    import fiona

    with fiona.open(path, layer=layer) as src:
        return str(src.crs_wkt)


def _waypoint_records(wkt: Any, to_wgs84: Any) -> list[dict[str, Any]]:
    """Named lon/lat records (start, via 1 ..., goal) of a WKT MULTIPOINT in the layer's CRS;
    empty for anything else (a missing or malformed attribute: the path's ends stand in)."""
    import shapely.wkt
    from shapely.errors import ShapelyError

    if not isinstance(wkt, str) or not wkt.strip():
        return []
    try:
        geom = shapely.wkt.loads(wkt)
    except (ShapelyError, ValueError):
        return []
    points = list(geom.geoms) if geom.geom_type == "MultiPoint" else [geom] if geom.geom_type == "Point" else []
    if len(points) < 2:
        return []
    lon, lat = to_wgs84.transform([p.x for p in points], [p.y for p in points])
    names = ["start", *(f"via {i}" for i in range(1, len(points) - 1)), "goal"]
    return [{"name": n, "lon": float(x), "lat": float(y)} for n, x, y in zip(names, lon, lat)]


# ------------------------------------------------------------------------------------------
# GPX and KML (pure)
# ------------------------------------------------------------------------------------------


def _deg(v: float) -> str:
    """Decimal degrees without an exponent (xsd:decimal), 1e-10 degree (0.01 mm) steps."""
    text = f"{v:.10f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _clean(text: str) -> str:
    """Text XML 1.0 can carry (no control characters besides tab and newline)."""
    return "".join(ch for ch in text if ch in "\t\n" or ord(ch) >= 0x20)


def _sub(parent: ET.Element, tag: str, text: str | None = None, **attrs: str) -> ET.Element:
    el = ET.SubElement(parent, tag, attrs)
    if text is not None:
        el.text = _clean(text)
    return el


def gpx_text(paths: Sequence[PathFeature]) -> str:
    """GPX 1.1: waypoints (start, vias, goal) then one track per path."""
    ET.register_namespace("", GPX_NS)
    q = lambda tag: f"{{{GPX_NS}}}{tag}"  # noqa: E731
    root = ET.Element(q("gpx"), {"version": "1.1", "creator": f"overseec {__version__}"})
    meta = _sub(root, q("metadata"))
    _sub(meta, q("name"), paths[0].name)
    _sub(meta, q("desc"), paths[0].description)
    for feature in paths:
        for name, lon, lat in feature.waypoints():
            wpt = _sub(root, q("wpt"), lat=_deg(lat), lon=_deg(lon))
            _sub(wpt, q("name"), name)
    for feature in paths:
        trk = _sub(root, q("trk"))
        _sub(trk, q("name"), feature.name)
        _sub(trk, q("desc"), feature.description)
        seg = _sub(trk, q("trkseg"))
        for lon, lat in feature.lonlat:
            _sub(seg, q("trkpt"), lat=_deg(lat), lon=_deg(lon))
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def kml_text(paths: Sequence[PathFeature]) -> str:
    """KML 2.2: folder 'path' (LineStrings) and folder 'waypoints' (Points)."""
    ET.register_namespace("", KML_NS)
    q = lambda tag: f"{{{KML_NS}}}{tag}"  # noqa: E731
    root = ET.Element(q("kml"))
    doc = _sub(root, q("Document"))
    _sub(doc, q("name"), paths[0].name)
    lines = _sub(doc, q("Folder"))
    _sub(lines, q("name"), "path")
    points = _sub(doc, q("Folder"))
    _sub(points, q("name"), "waypoints")
    for feature in paths:
        pm = _sub(lines, q("Placemark"))
        _sub(pm, q("name"), feature.name)
        _sub(pm, q("description"), feature.description)
        ls = _sub(pm, q("LineString"))
        _sub(ls, q("tessellate"), "1")
        _sub(ls, q("coordinates"), " ".join(f"{_deg(lon)},{_deg(lat)}" for lon, lat in feature.lonlat))
        for name, lon, lat in feature.waypoints():
            wp = _sub(points, q("Placemark"))
            _sub(wp, q("name"), name)
            _sub(_sub(wp, q("Point")), q("coordinates"), f"{_deg(lon)},{_deg(lat)}")
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


# ------------------------------------------------------------------------------------------
# CSV in the costmap's CRS or a Nav2 frame
# ------------------------------------------------------------------------------------------


def lonlat_to(crs, lonlat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Project (N, 2) WGS 84 lon/lat into ``crs`` (x, y)."""
    from pyproj import Transformer

    tr = Transformer.from_crs("EPSG:4326", crs.to_wkt(), always_xy=True)
    xs, ys = tr.transform(lonlat[:, 0], lonlat[:, 1])
    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    if not (np.isfinite(xs).all() and np.isfinite(ys).all()):
        raise InputError("the path does not project into the costmap's CRS (outside its domain)")
    return xs, ys


def cumulative_length_m(xs: np.ndarray, ys: np.ndarray, m_per_unit: tuple[float, float]) -> np.ndarray:
    """Cumulative ground length (first value 0): each step's (dx, dy) times metres per unit."""
    dx = np.diff(xs) * m_per_unit[0]
    dy = np.diff(ys) * m_per_unit[1]
    return np.concatenate([[0.0], np.cumsum(np.hypot(dx, dy))])


def grid_metres_per_unit(grid: Grid) -> tuple[float, float]:
    """Ground metres per CRS unit along x and y: the grid's ground pixel size over its step."""
    px, py = grid.pixel_size_m()
    return px / math.hypot(grid.transform.a, grid.transform.d), py / math.hypot(grid.transform.b, grid.transform.e)


def sample_costs(costmap: Path, band: int, grid: Grid, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """The costmap's value in the cell under each (x, y) in its CRS (NaN outside or no data).

    Reads only the window the points span."""
    from rasterio.windows import Window

    cols, rows = ~grid.transform * (xs, ys)
    cols = np.floor(np.asarray(cols)).astype(np.int64)
    rows = np.floor(np.asarray(rows)).astype(np.int64)
    inside = (rows >= 0) & (rows < grid.height) & (cols >= 0) & (cols < grid.width)
    out = np.full(len(xs), np.nan)
    if not inside.any():
        return out
    r0, r1 = int(rows[inside].min()), int(rows[inside].max()) + 1
    c0, c1 = int(cols[inside].min()), int(cols[inside].max()) + 1
    with open_raster(costmap) as ds:
        block = ds.read(band, window=Window(c0, r0, c1 - c0, r1 - r0)).astype(np.float64)
        nodata = ds.nodatavals[band - 1]
    if nodata is not None and not math.isnan(nodata):
        block[block == nodata] = np.nan
    out[inside] = block[rows[inside] - r0, cols[inside] - c0]
    return out


#: Largest distance (in pixels) from cell centres at which path vertices are snapped onto them.
SNAP_TOLERANCE_PX = 0.01


def snap_to_centres(grid: Grid, xs: np.ndarray, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact cell centres when every vertex lies within :data:`SNAP_TOLERANCE_PX` of one.

    ``plan`` writes pixel centres rounded to 1e-9 degree (about 0.1 mm); projected back they miss
    the centres by that much. A path of this costmap gets its exact centres back (so lengths equal
    the plan's); any other line keeps its coordinates.
    """
    cols, rows = ~grid.transform * (xs, ys)
    cols, rows = np.asarray(cols, dtype=float), np.asarray(rows, dtype=float)
    fc, fr = np.floor(cols), np.floor(rows)
    if np.max(np.abs(cols - fc - 0.5)) > SNAP_TOLERANCE_PX or np.max(np.abs(rows - fr - 0.5)) > SNAP_TOLERANCE_PX:
        return xs, ys
    sx, sy = grid.transform * (fc + 0.5, fr + 0.5)
    return np.asarray(sx, dtype=float), np.asarray(sy, dtype=float)


@dataclass(frozen=True)
class PathTable:
    """Rows of the CSV for one path: coordinates in the output frame, length, cost."""

    xs: np.ndarray
    ys: np.ndarray
    length_m: np.ndarray
    cost: np.ndarray | None = None


def csv_text(tables: Sequence[PathTable]) -> str:
    """``path,index,x,y,length_m,cost`` (coordinates to 1e-6 of the frame's unit)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for k, t in enumerate(tables):
        for i in range(len(t.xs)):
            c = "" if t.cost is None or not math.isfinite(t.cost[i]) else f"{t.cost[i]:.9g}"
            w.writerow([k, i, f"{t.xs[i]:.6f}", f"{t.ys[i]:.6f}", f"{t.length_m[i]:.6f}", c])
    return buf.getvalue()


def path_table(
    feature: PathFeature,
    frame: str,
    *,
    grid: Grid | None = None,
    costmap: Path | None = None,
    band: int = 1,
    nav2: LocalFrame | None = None,
) -> PathTable:
    """One path's CSV rows in ``frame``: 'crs' (needs ``grid``) or 'nav2' (needs ``nav2``).

    Lengths come from the costmap's ground pixel size when ``grid`` is given (so they agree
    with the plan's ``length_m``), else from the Nav2 frame's metres. Costs need ``costmap``.
    """
    if frame not in FRAMES:
        raise InputError(f"--frame must be one of {', '.join(FRAMES)}, not {frame!r}")
    if frame == "crs" and grid is None:
        raise InputError("a CSV in the costmap's CRS needs the costmap: pass --costmap COSTMAP.tif")
    if frame == "nav2" and nav2 is None:
        raise InputError("a CSV in a Nav2 frame needs --nav2-yaml MAP.yaml or the costmap")
    cost = length = None
    if grid is not None:
        gx, gy = snap_to_centres(grid, *lonlat_to(grid.crs, feature.lonlat))
        length = cumulative_length_m(gx, gy, grid_metres_per_unit(grid))
        if costmap is not None:
            cost = sample_costs(costmap, band, grid, gx, gy)
    if frame == "crs":
        assert length is not None  # frame 'crs' has its grid (checked above)
        return PathTable(gx, gy, length, cost)
    assert nav2 is not None  # frame 'nav2' has its frame (checked above)
    if grid is not None and grid.crs == nav2.crs:
        cx, cy = gx, gy
    else:
        cx, cy = lonlat_to(nav2.crs, feature.lonlat)
    lx, ly = nav2.to_local(cx, cy)
    if length is None:
        length = cumulative_length_m(lx, ly, (1.0, 1.0))
    return PathTable(lx, ly, length, cost)
