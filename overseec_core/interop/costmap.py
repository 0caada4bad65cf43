"""Costmaps for robot and routing stacks: Nav2 map_server maps, costmap_2d GeoTIFFs, numpy arrays.

Every encoding starts from the planner's own view of a costmap (:class:`~overseec_core.plan.grid.
PlanningGrid`): finite costs in [0, 1] (0.5 neutral, lower = better), ``+inf`` where the lethal
sidecar (1, and keep-out 2) or the file itself forbids a cell, ``NaN`` for no data. So a cell is
exported as lethal exactly when ``overseec plan`` would refuse to enter it.

**Keep-out cells are lethal in every export.** They are the mission's hard rules: zones of
distance rules ("keep 20 m from buildings"), entities a never-cross rule forbids, and obstacles
nobody mentioned (buildings and water, by the interpreter's priors), so on a typical map they are
every building and every stretch of water. ``overseec plan`` enters them as a last resort, when
no route avoids them (a start inside a building), and says so in the route's notes; a robot's
planner reading these maps never will, which is right for a robot. Each export says so
(:data:`KEEP_OUT_MEANING`: the YAML's comments, the GeoTIFF's tags, the npy JSON, and a note
when the costmap has keep-out cells). Their own costs (the costmap's values under them) are not
exported; the costmap GeoTIFF keeps them.

- **Nav2** (``map_server`` PGM/PNG + YAML). ``trinary`` (default): the map ``map_saver`` writes
  and every ROS consumer reads the same way -- 254 free (every passable cell), 0 occupied (lethal,
  keep-out), 205 unknown (no data), with ROS 1 map_saver's thresholds (free 0.196: Nav2's saver
  default 0.25 would load 205 as *free*). ``scale``: the costs survive -- occupancy
  ``v = floor(99 c + 1/2)`` in 0..99, lethal 100 -- as an 8-bit grey+alpha PNG (Nav2 reads
  "unknown" in scale mode only from transparency, which PGM lacks) with thresholds 0 and 1, so
  Nav2's loader gives back exactly ``v``; its static layer with ``trinary_costmap: false`` turns
  that into ``v / 100 * 254`` (0..251, below costmap_2d's inscribed 253).
  Nav2 needs square metric cells in a local metric frame: only projected, north-up grids whose
  pixels are square in ground metres are exported (anything else is refused with the gdalwarp
  command that makes one; resampling here would move or thin lethal cells behind the user's back).
  Local (0, 0) is the costmap's lower-left corner unless ``local_origin`` names CRS coordinates;
  the YAML records it with the CRS (extra keys Nav2 ignores).
- **costmap_2d** values as a uint8 GeoTIFF on the same grid: ``round(252 c)`` (0 free ..
  252 = MAX_NON_OBSTACLE, still traversable), 254 LETHAL_OBSTACLE (lethal and keep-out), 255
  NO_INFORMATION (no data, also the GeoTIFF's nodata). 253 (inscribed) is never written: it is
  the robot footprint's business, not the map's.
- **npy**: the float32 cost array exactly as the planner holds it (NaN no data, +inf lethal and
  keep-out), a uint8 flags array (0 passable, 1 lethal, 2 keep-out, 255 no data) and a JSON
  sidecar with the transform (GDAL and affine order), CRS (WKT, EPSG), ground pixel size and the
  meaning of the scale.
"""

from __future__ import annotations

import io
import json
import math
import struct
import textwrap
import zlib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.crs import CRS

from overseec_core import __version__, defaults
from overseec_core.errors import InputError, OutputError
from overseec_core.interop.frames import LocalFrame, Nav2Geometry, nav2_geometry
from overseec_core.io.atomic import atomic_path, write_text_atomic
from overseec_core.io.grid import crs_label
from overseec_core.io.write import RasterWriter, check_output_path
from overseec_core.limits import read_text_limited
from overseec_core.plan.grid import PlanningGrid
from overseec_core.progress import Progress, check_cancelled

# costmap_2d's cost values (nav2_costmap_2d/cost_values.hpp)
FREE_SPACE = 0
MAX_NON_OBSTACLE = 252
INSCRIBED_INFLATED_OBSTACLE = 253
LETHAL_OBSTACLE = 254
NO_INFORMATION = 255

NAV2_MODES = defaults.NAV2_MODES
#: Trinary PGM pixels, as map_saver writes them.
PGM_FREE, PGM_OCCUPIED, PGM_UNKNOWN = 254, 0, 205
#: ROS 1 map_saver's thresholds: 205 is occ = 0.19608 > 0.196, so it loads as unknown.
TRINARY_THRESHOLDS = (0.65, 0.196)  # occupied_thresh, free_thresh
#: Scale-mode thresholds that make Nav2's loader give back the occupancy written.
SCALE_THRESHOLDS = (1.0, 0.0)
#: Occupancy (0..100) of a lethal cell in scale mode; passable cells get 0..99.
OCC_LETHAL = 100

#: YAML keys (ignored by Nav2, read by ``overseec export path --frame nav2``).
YAML_LOCAL_ORIGIN = "overseec_local_origin"
YAML_CRS = "overseec_crs"
YAML_CRS_WKT = "overseec_crs_wkt"
YAML_SCALE = "overseec_ground_m_per_crs_unit"

#: What keep-out cells are and why they are exported as lethal (YAML comment, tag, JSON, note).
KEEP_OUT_MEANING = (
    "keep-out cells (overseec's lethal sidecar value 2) are ground the mission keeps out of: zones "
    "of distance rules, entities a never-cross rule forbids, and obstacles nobody mentioned such as "
    "buildings and water. They are exported as lethal: a robot's planner never enters them, while "
    "overseec plan enters them only as a last resort, when no route avoids them, and says so in "
    "the route's notes."
)

COST_SCALE_MEANING = {
    "range": [0.0, 1.0],
    "lower_is_better": True,
    "0.0": "the most preferred entity",
    "0.0-0.5": "preferred, by rank",
    "0.5": "neutral: unlabelled ground, anything the prompt does not mention or merely allows",
    "0.5-1.0": "avoided, by rank",
    "1.0": "the worst passable cost",
    "planner_step_cost": "(mean of the two cells' costs + base cost per metre) x step length in metres",
}


# ------------------------------------------------------------------------------------------
# Value mappings (pure)
# ------------------------------------------------------------------------------------------


def costmap2d_values(cost: np.ndarray) -> np.ndarray:
    """costmap_2d uint8 values: finite c in [0, 1] -> floor(252 c + 1/2); +inf -> 254; NaN -> 255."""
    with np.errstate(invalid="ignore"):
        scaled = np.floor(np.clip(cost, 0.0, 1.0) * MAX_NON_OBSTACLE + 0.5)
    out = np.where(np.isfinite(cost), scaled, 0).astype(np.uint8)
    out[np.isposinf(cost)] = LETHAL_OBSTACLE
    out[np.isnan(cost)] = NO_INFORMATION
    return out


def trinary_pixels(cost: np.ndarray) -> np.ndarray:
    """Trinary PGM pixels: passable 254 (free), +inf 0 (occupied), NaN 205 (unknown)."""
    out = np.full(cost.shape, PGM_FREE, dtype=np.uint8)
    out[np.isposinf(cost)] = PGM_OCCUPIED
    out[np.isnan(cost)] = PGM_UNKNOWN
    return out


def scale_occupancy(cost: np.ndarray) -> np.ndarray:
    """Occupancy in Nav2 scale mode (int16): floor(99 c + 1/2) in 0..99, +inf 100, NaN -1."""
    with np.errstate(invalid="ignore"):
        occ = np.floor(np.clip(cost, 0.0, 1.0) * (OCC_LETHAL - 1) + 0.5)
    out = np.where(np.isfinite(cost), occ, 0).astype(np.int16)
    out[np.isposinf(cost)] = OCC_LETHAL
    out[np.isnan(cost)] = -1
    return out


def scale_pixels(occupancy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(grey, alpha) uint8 for scale-mode occupancy: grey = round(255 (100 - v) / 100) (Nav2's
    map_saver rule, which its loader inverts exactly with thresholds 0 and 1); unknown (-1) is
    transparent."""
    v = np.clip(occupancy, 0, OCC_LETHAL).astype(np.float64)
    grey = np.floor(255.0 * (OCC_LETHAL - v) / OCC_LETHAL + 0.5).astype(np.uint8)
    alpha = np.where(occupancy < 0, 0, 255).astype(np.uint8)
    grey[occupancy < 0] = 128
    return grey, alpha


def flags_array(grid: PlanningGrid) -> np.ndarray:
    """uint8 per cell: 0 passable, 1 lethal, 2 keep-out (see :data:`KEEP_OUT_MEANING`), 255 no data."""
    out = np.zeros(grid.shape, dtype=np.uint8)
    out[np.isposinf(grid.cost)] = 1
    if grid.keep_out is not None:
        out[grid.keep_out] = 2
    out[np.isnan(grid.cost)] = 255
    return out


def cell_counts(grid: PlanningGrid) -> dict[str, int]:
    """How many cells are passable, lethal (keep-out included), keep-out and no data."""
    lethal = int(np.isposinf(grid.cost).sum())
    nodata = int(np.isnan(grid.cost).sum())
    keep = 0 if grid.keep_out is None else int(grid.keep_out.sum())
    return {"passable": int(grid.cost.size) - lethal - nodata, "lethal": lethal, "keep_out": keep, "nodata": nodata}


# ------------------------------------------------------------------------------------------
# Image and text formats (pure)
# ------------------------------------------------------------------------------------------


def pgm_bytes(pixels: np.ndarray, comment: str = "") -> bytes:
    """Binary PGM (P5, maxval 255); row 0 of ``pixels`` is the image's top row."""
    arr = np.ascontiguousarray(pixels, dtype=np.uint8)
    lines = "".join(f"# {c}\n" for c in comment.splitlines() if c.isascii())
    header = f"P5\n{lines}{arr.shape[1]} {arr.shape[0]}\n255\n".encode("ascii")
    return header + arr.tobytes()


def png_grey_alpha_bytes(grey: np.ndarray, alpha: np.ndarray) -> bytes:
    """8-bit grey+alpha PNG (colour type 4), written with zlib: no imaging library needed."""
    return png_grey_alpha_strips(grey.shape[1], grey.shape[0], [(grey, alpha)])


def png_grey_alpha_strips(width: int, height: int, strips: Iterable[tuple[np.ndarray, np.ndarray]]) -> bytes:
    """:func:`png_grey_alpha_bytes` of the (grey, alpha) row strips, top first, compressed as they
    come (the same bytes as one array: the deflate stream does not depend on how it is fed)."""
    z = zlib.compressobj(6)
    parts = []
    rows = 0
    for grey, alpha in strips:
        h = grey.shape[0]
        pairs = np.stack([grey, alpha], axis=-1).astype(np.uint8).reshape(h, 2 * width)
        raw = np.concatenate([np.zeros((h, 1), np.uint8), pairs], axis=1).tobytes()  # filter 0 rows
        parts.append(z.compress(raw))
        rows += h
    if rows != height:
        raise ValueError(f"PNG strips hold {rows} rows, not {height}")
    parts.append(z.flush())

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 4, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", b"".join(parts)) + chunk(b"IEND", b"")


def _j(value: Any) -> str:
    """A YAML flow value as JSON (YAML 1.2 reads JSON; floats keep every digit via repr)."""
    return json.dumps(value, allow_nan=False)


def nav2_yaml_text(image: str, mode: str, geometry: Nav2Geometry, source: str, lethal: str | None) -> str:
    """The map_server YAML, with comments explaining the encoding and the overseec_* frame keys."""
    occupied, free = TRINARY_THRESHOLDS if mode == "trinary" else SCALE_THRESHOLDS
    f = geometry.frame
    if mode == "trinary":
        encoding = (
            "# trinary: 254 free (every passable cell, whatever its cost), 0 occupied (lethal and\n"
            "#   keep-out cells), 205 unknown (no data). The mission's cost levels are not in a\n"
            "#   trinary map; export with --nav2-mode scale to keep them.\n"
        )
    else:
        encoding = (
            "# scale: occupancy v = floor(99 cost + 1/2) in 0..99 for passable cells (0.5 neutral -> 50),\n"
            "#   100 lethal and keep-out, transparent = unknown (no data); Nav2's static layer with\n"
            "#   trinary_costmap: false maps v to v / 100 * 254.\n"
        )
    keep_out = "".join(f"# {line}\n" for line in textwrap.wrap(KEEP_OUT_MEANING, 94))
    return (
        f"# Nav2 map_server map exported by overseec {__version__} from {source}\n"
        f"# lethal sidecar: {lethal or 'none'}\n"
        + encoding
        + keep_out
        + "# Image row 0 is the top (largest northing); origin is the lower-left corner of the\n"
        "#   lower-left cell in the local metric frame:\n"
        f"#   local = (CRS coordinates - overseec_local_origin) x {f.scale!r} m per CRS unit, "
        f"CRS {crs_label(f.crs) if f.crs.to_epsg() else 'in overseec_crs_wkt'}\n"
        f"image: {_j(image)}\n"
        f"mode: {mode}\n"
        f"resolution: {_j(geometry.resolution)}\n"
        f"origin: [{_j(geometry.origin[0])}, {_j(geometry.origin[1])}, 0.0]\n"
        "negate: 0\n"
        f"occupied_thresh: {_j(occupied)}\n"
        f"free_thresh: {_j(free)}\n"
        f"{YAML_LOCAL_ORIGIN}: [{_j(f.origin[0])}, {_j(f.origin[1])}]\n"
        f"{YAML_SCALE}: {_j(f.scale)}\n"
        f"{YAML_CRS}: {_j(crs_label(f.crs) if f.crs.to_epsg() else None)}\n"
        f"{YAML_CRS_WKT}: {_j(f.crs.to_wkt())}\n"
    )


def read_nav2_frame(path: str | Path) -> tuple[LocalFrame, dict[str, Any]]:
    """The local frame an exported Nav2 YAML records, and the YAML as a dict (one-line errors)."""

    p = Path(path)
    text = read_text_limited(p, 1 << 20, "--nav2-yaml")
    try:
        import yaml

        doc = yaml.safe_load(text)
    except ImportError:  # PyYAML absent: our own files hold JSON values, one key per line
        doc = _read_flat_yaml(text)
    except Exception as exc:  # yaml.YAMLError and its many subclasses
        raise InputError(f"--nav2-yaml {p}: not YAML ({' '.join(str(exc).split())[:160]})") from None
    if not isinstance(doc, dict) or "resolution" not in doc or "origin" not in doc:
        raise InputError(f"--nav2-yaml {p}: not a map_server map (no resolution/origin)")
    missing = [k for k in (YAML_LOCAL_ORIGIN, YAML_CRS_WKT) if k not in doc]
    if missing:
        raise InputError(
            f"--nav2-yaml {p}: lacks {', '.join(missing)} (not written by overseec "
            "export); pass the costmap with --costmap and --local-origin instead"
        )
    try:
        crs = CRS.from_wkt(str(doc[YAML_CRS_WKT]))
        ox, oy = (float(v) for v in doc[YAML_LOCAL_ORIGIN])
        scale = float(doc.get(YAML_SCALE, 1.0))
    except Exception:
        raise InputError(f"--nav2-yaml {p}: unreadable {YAML_LOCAL_ORIGIN}/{YAML_CRS_WKT}") from None
    if not (math.isfinite(ox) and math.isfinite(oy) and scale > 0 and math.isfinite(scale)):
        raise InputError(f"--nav2-yaml {p}: {YAML_LOCAL_ORIGIN} and {YAML_SCALE} must be finite")
    return LocalFrame(crs=crs, origin=(ox, oy), scale=scale), doc


def _read_flat_yaml(text: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for line in text.splitlines():
        if not line.strip() or line.lstrip().startswith("#") or ":" not in line:
            continue
        key, value = line.split(":", 1)
        try:
            out[key.strip()] = json.loads(value.strip())
        except ValueError:
            out[key.strip()] = value.strip()
    return out


# ------------------------------------------------------------------------------------------
# Writers
# ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CostmapExport:
    """What an export wrote: the format, its files (role -> path), cell counts and notes."""

    kind: str
    outputs: Mapping[str, Path]
    counts: Mapping[str, int]
    details: Mapping[str, Any] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "outputs": {k: str(v) for k, v in self.outputs.items()},
            "counts": dict(self.counts),
            "details": dict(self.details),
            "notes": list(self.notes),
        }


#: Rows encoded at a time (a cancel is noticed within one strip: ~0.1 s at 6000 columns).
STRIP_ROWS = 256


def _strips(cost: np.ndarray, progress: Progress | None):
    """(first row, rows) strips of ``cost``, checking for a cancel before each."""
    for r0 in range(0, cost.shape[0], STRIP_ROWS):
        check_cancelled(progress)
        yield r0, cost[r0 : r0 + STRIP_ROWS]


def _write_bytes_atomic(path: Path, data: bytes) -> Path:
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(data)
    return path


def nav2_outputs(out: Path, mode: str) -> dict[str, Path]:
    """The YAML ``out`` and its image beside it (.pgm trinary, .png scale)."""
    if out.suffix.lower() not in (".yaml", ".yml"):
        raise InputError(f"--out {out}: a Nav2 map is a .yaml file (its image is written beside it)")
    return {"yaml": out, "image": out.with_suffix(".pgm" if mode == "trinary" else ".png")}


def write_nav2(
    out: Path,
    grid: PlanningGrid,
    mode: str = "trinary",
    local_origin: tuple[float, float] | None = None,
    inputs: Iterable[Path] = (),
    progress: Progress | None = None,
) -> CostmapExport:
    """A Nav2 map_server map (YAML + image) of ``grid``; see the module docstring. ``progress``
    is polled for a cancel between strips of :data:`STRIP_ROWS` rows."""
    if mode not in NAV2_MODES:
        raise InputError(f"--nav2-mode must be one of {', '.join(NAV2_MODES)}, not {mode!r}")
    if grid.grid is None:
        raise InputError("a Nav2 map needs a georeferenced costmap")
    files = nav2_outputs(Path(out), mode)
    inputs = list(inputs)
    for p in files.values():
        check_output_path(p, inputs)
    geometry = nav2_geometry(grid.grid, grid.source, local_origin)
    if mode == "trinary":
        pixels = np.empty(grid.shape, dtype=np.uint8)
        for r0, strip in _strips(grid.cost, progress):
            pixels[r0 : r0 + len(strip)] = trinary_pixels(strip)
        data = pgm_bytes(pixels, f"overseec {__version__} trinary map")
    else:
        data = png_grey_alpha_strips(
            grid.width,
            grid.height,
            (scale_pixels(scale_occupancy(strip)) for _r0, strip in _strips(grid.cost, progress)),
        )
    check_cancelled(progress)
    source = Path(grid.source).name if grid.source else "costmap"
    lethal = Path(grid.lethal_source).name if grid.lethal_source else None
    text = nav2_yaml_text(files["image"].name, mode, geometry, source, lethal)
    _write_bytes_atomic(files["image"], data)
    write_text_atomic(files["yaml"], text)
    notes = []
    if mode == "trinary":
        notes.append(
            "trinary map: every passable cell is free, the cost levels are not kept (--nav2-mode scale keeps them)"
        )
    details = {
        "mode": mode,
        "resolution": geometry.resolution,
        "origin": list(geometry.origin),
        "local_origin": list(geometry.frame.origin),
        "ground_m_per_crs_unit": geometry.frame.scale,
        "crs": crs_label(geometry.frame.crs),
    }
    return CostmapExport("nav2", files, cell_counts(grid), details, tuple(notes))


def write_costmap2d(
    out: Path, grid: PlanningGrid, inputs: Iterable[Path] = (), progress: Progress | None = None
) -> CostmapExport:
    """costmap_2d values (uint8) as a GeoTIFF on the costmap's grid, via the atomic RasterWriter."""
    if grid.grid is None:
        raise InputError("a costmap_2d GeoTIFF needs a georeferenced costmap")
    tags = {
        "OVERSEEC_EXPORT": "costmap_2d",
        "OVERSEEC_EXPORT_MAPPING": "cost c in [0,1] -> floor(252 c + 0.5); lethal and keep-out "
        "-> 254 (LETHAL_OBSTACLE); no data -> 255 (NO_INFORMATION)",
        "OVERSEEC_KEEP_OUT": KEEP_OUT_MEANING,
        "OVERSEEC_SOURCE_COSTMAP": Path(grid.source).name if grid.source else "",
    }
    with RasterWriter(
        out, grid.grid, 1, "uint8", nodata=NO_INFORMATION, descriptions=["costmap_2d"], tags=tags, inputs=inputs
    ) as w:
        step = max(1, w.block_rows)
        for r0 in range(0, grid.height, step):
            check_cancelled(progress)
            w.write(costmap2d_values(grid.cost[r0 : r0 + step]), r0)
    details = {
        "mapping": {
            "free": "floor(252 c + 0.5)",
            "lethal": LETHAL_OBSTACLE,
            "keep_out": LETHAL_OBSTACLE,
            "nodata": NO_INFORMATION,
        }
    }
    return CostmapExport("costmap2d", {"geotiff": Path(out)}, cell_counts(grid), details)


def npy_outputs(out: Path) -> dict[str, Path]:
    """``X.npy`` (cost), ``X.flags.npy`` and ``X.json`` (metadata)."""
    if out.suffix.lower() != ".npy":
        raise InputError(f"--out {out}: a numpy export is a .npy file (X.flags.npy and X.json go beside it)")
    return {"npy": out, "flags": out.with_name(f"{out.stem}.flags.npy"), "json": out.with_suffix(".json")}


def npy_metadata(grid: PlanningGrid, files: Mapping[str, Path]) -> dict[str, Any]:
    """The JSON sidecar of an npy export: grid, CRS, ground size, encodings and counts."""
    g = grid.grid
    assert g is not None  # callers refuse a bare array first (write_npy)
    t = g.transform
    return {
        "format": "overseec-costmap-npy/1",
        "array": files["npy"].name,
        "flags": files["flags"].name,
        "shape": [grid.height, grid.width],
        "dtype": "float32",
        "layout": "C order, [row, col]; row 0 is the top of the costmap (the largest y in a north-up grid)",
        "transform_gdal": [t.c, t.a, t.b, t.f, t.d, t.e],
        "transform_affine": [t.a, t.b, t.c, t.d, t.e, t.f],
        "pixel_centre": "x = c + (col + 0.5) a + (row + 0.5) b, y = f + (col + 0.5) d + (row + 0.5) e "
        "(transform_affine = [a, b, c, d, e, f])",
        "crs": crs_label(g.crs),
        "crs_epsg": g.crs.to_epsg(),
        "crs_wkt": g.crs.to_wkt(),
        "pixel_size_m": list(grid.pixel_size_m),
        "ground_scale": g.ground_scale().to_dict(),
        "cost_scale": COST_SCALE_MEANING,
        "encoding": {
            "finite": "cost in [0, 1]",
            "+inf": "impassable: lethal, or a keep-out cell "
            "(flags 2: overseec's planner enters those only when no route exists otherwise)",
            "nan": "no data: impassable",
        },
        "flags_encoding": {
            "0": "passable",
            "1": "lethal",
            "2": "keep-out: a distance rule's zone, a never-cross entity or an obstacle such as a building or water",
            "255": "no data",
        },
        "keep_out": KEEP_OUT_MEANING,
        "counts": cell_counts(grid),
        "source": {"costmap": grid.source, "lethal": grid.lethal_source, "lethal_threshold": grid.lethal_threshold},
    }


def _npy_bytes(arr: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.ascontiguousarray(arr), allow_pickle=False)
    return buf.getvalue()


def write_npy(out: Path, grid: PlanningGrid, inputs: Iterable[Path] = ()) -> CostmapExport:
    """float32 cost (.npy), uint8 flags (.flags.npy) and the JSON sidecar."""
    if grid.grid is None:
        raise InputError("an npy export needs a georeferenced costmap")
    files = npy_outputs(Path(out))
    inputs = list(inputs)
    for p in files.values():
        check_output_path(p, inputs)
    _write_bytes_atomic(files["npy"], _npy_bytes(grid.cost.astype(np.float32, copy=False)))
    _write_bytes_atomic(files["flags"], _npy_bytes(flags_array(grid)))
    meta = npy_metadata(grid, files)
    try:
        text = json.dumps(meta, indent=2, allow_nan=False)
    except ValueError as exc:  # a NaN/inf in the metadata would make invalid JSON
        raise OutputError(f"cannot write {files['json']}: {exc}") from None
    write_text_atomic(files["json"], text + "\n")
    return CostmapExport("npy", files, cell_counts(grid), {"json": files["json"].name})
