"""Interoperability: costmaps and paths in the formats robot and routing stacks read.

``export_costmap`` writes a costmap and its lethal sidecar as a Nav2 map_server map, a
costmap_2d-valued GeoTIFF or numpy arrays (:mod:`.costmap`); ``export_path`` writes a planned
path as GPX, KML or CSV (:mod:`.paths`). Both check every output against the inputs (an output
never replaces the costmap, its sidecar or the path), write each file atomically inside one output
transaction (a failed or cancelled export leaves the folder as it was) and record the inputs
(hashed) and what was written in the output folder's ``manifest.json`` under ``exports``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from overseec_core import defaults
from overseec_core.errors import InputError
from overseec_core.interop.costmap import (
    KEEP_OUT_MEANING,
    NAV2_MODES,
    CostmapExport,
    read_nav2_frame,
    write_costmap2d,
    write_nav2,
    write_npy,
)
from overseec_core.interop.frames import LocalFrame, nav2_geometry
from overseec_core.interop.paths import FRAMES, PATH_FORMATS, csv_text, gpx_text, kml_text, path_table, read_paths
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.grid import Grid, crs_label
from overseec_core.io.manifest import RunDir
from overseec_core.io.read import open_raster
from overseec_core.io.transaction import output_transaction
from overseec_core.io.write import check_output_path
from overseec_core.limits import check_pixels
from overseec_core.plan.grid import check_costmap_kind, load_costmap
from overseec_core.progress import Progress, check_cancelled

COSTMAP_FORMATS = defaults.COSTMAP_FORMATS

__all__ = [
    "COSTMAP_FORMATS",
    "FRAMES",
    "NAV2_MODES",
    "PATH_FORMATS",
    "CostmapExport",
    "CostmapExportOptions",
    "PathExport",
    "PathExportOptions",
    "export_costmap",
    "export_path",
]


@dataclass(frozen=True)
class CostmapExportOptions:
    """``overseec export costmap``: which costmap, which format, where."""

    costmap: Path
    to: str
    out: Path
    lethal: Path | None = None
    band: int | None = None
    nav2_mode: str = "trinary"
    local_origin: tuple[float, float] | None = None


@dataclass(frozen=True)
class PathExportOptions:
    """``overseec export path``: which path, which format and frame, where."""

    path: Path
    to: str
    out: Path
    frame: str = "crs"
    nav2_yaml: Path | None = None
    costmap: Path | None = None
    band: int | None = None
    local_origin: tuple[float, float] | None = None
    #: The layer of a vector file holding several (a paths.gpkg table); None: the only one.
    layer: str | None = None


@dataclass(frozen=True)
class PathExport:
    """What a path export wrote."""

    kind: str
    out: Path
    paths: int
    points: int
    frame: str | None = None
    details: Mapping[str, Any] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "out": str(self.out),
            "paths": self.paths,
            "points": self.points,
            "frame": self.frame,
            "details": dict(self.details),
            "notes": list(self.notes),
        }


def _record(run: RunDir, name: str, entry: dict[str, Any]) -> None:
    """Add this export to the manifest's ``exports`` (keyed by output file name)."""
    run.set_entry("exports", name, entry)


def export_costmap(
    options: CostmapExportOptions, progress: Progress | None = None, command_args: dict | None = None
) -> CostmapExport:
    """Costmap (+ lethal sidecar, found as ``plan`` finds it) -> Nav2 / costmap_2d / npy files."""

    o = options
    if o.to not in COSTMAP_FORMATS:
        raise InputError(f"--to must be one of {', '.join(COSTMAP_FORMATS)}, not {o.to!r}")
    inputs = [Path(o.costmap)] + ([Path(o.lethal)] if o.lethal else [])
    check_output_path(o.out, inputs)
    grid = load_costmap(o.costmap, lethal_path=o.lethal, band=o.band)
    if grid.lethal_source:
        inputs.append(Path(grid.lethal_source))
    check_cancelled(progress)
    notes: list[str] = []
    if grid.lethal_source is None:
        notes.append("no lethal sidecar found: only no-data and infinite cells are impassable")
    with output_transaction(progress):
        result = COSTMAP_WRITERS[o.to](o, grid, inputs, progress)
        check_cancelled(progress)
        run = RunDir(Path(o.out).parent, command="export", args=command_args)
        run.record_input(f"export_costmap_{Path(o.costmap).name}", o.costmap)
        if grid.lethal_source:
            run.record_input(f"export_lethal_{Path(grid.lethal_source).name}", grid.lethal_source)
        if result.counts.get("keep_out"):
            notes.append(f"{result.counts['keep_out']} {KEEP_OUT_MEANING}")
        result = CostmapExport(result.kind, result.outputs, result.counts, result.details, tuple(notes) + result.notes)
        _record(
            run,
            Path(o.out).name,
            {**result.to_json(), "costmap": str(Path(o.costmap).resolve()), "lethal": grid.lethal_source},
        )
        run.save()
    return result


#: The costmap writers by format name (``formats.FORMATS``' costmap rows): options, the loaded
#: grid, the inputs an output must never replace, progress -> what was written.
COSTMAP_WRITERS: dict[str, Callable[[CostmapExportOptions, Any, list[Path], Progress | None], CostmapExport]] = {
    "nav2": lambda o, grid, inputs, progress: write_nav2(
        Path(o.out), grid, o.nav2_mode, o.local_origin, inputs, progress
    ),
    "costmap2d": lambda o, grid, inputs, progress: write_costmap2d(Path(o.out), grid, inputs, progress),
    "npy": lambda o, grid, inputs, progress: write_npy(Path(o.out), grid, inputs),
}


def _costmap_for_path(o: PathExportOptions, properties: Mapping[str, Any]) -> Path | None:
    """The costmap behind a path: --costmap, else the one the path names (if it still exists)."""
    if o.costmap is not None:
        if not Path(o.costmap).exists():
            raise InputError(f"--costmap {o.costmap}: no such file")
        return Path(o.costmap)
    named = properties.get("costmap")
    if isinstance(named, str) and named and Path(named).exists():
        return Path(named)
    return None


def export_path(
    options: PathExportOptions, progress: Progress | None = None, command_args: dict | None = None
) -> PathExport:
    """Path GeoJSON (WGS 84) or line layer (any CRS) -> GPX / KML / CSV (costmap CRS or Nav2 frame)."""

    o = options
    if o.to not in PATH_FORMATS:
        raise InputError(f"--to must be one of {', '.join(PATH_FORMATS)}, not {o.to!r}")
    if o.frame not in FRAMES:
        raise InputError(f"--frame must be one of {', '.join(FRAMES)}, not {o.frame!r}")
    if o.to != "csv" and (o.frame != "crs" or o.nav2_yaml is not None):
        raise InputError(f"--frame and --nav2-yaml apply to CSV; {o.to.upper()} is always WGS 84")
    inputs = [Path(o.path)] + [Path(p) for p in (o.nav2_yaml, o.costmap) if p is not None]
    out = check_output_path(o.out, inputs)
    paths = read_paths(o.path, o.layer)
    notes: list[str] = []
    details: dict[str, Any] = {}
    text, costmap = PATH_WRITERS[o.to](o, paths, notes, details)
    if costmap is not None:
        inputs.append(costmap)
        check_output_path(out, inputs)
    check_cancelled(progress)
    with output_transaction(progress):
        write_text_atomic(out, text)
        run = RunDir(out.parent, command="export", args=command_args)
        run.record_input(f"export_path_{Path(o.path).name}", o.path)
        if costmap is not None:
            run.record_input(f"export_costmap_{costmap.name}", costmap)
        if o.nav2_yaml is not None:
            run.record_input(f"export_nav2_yaml_{Path(o.nav2_yaml).name}", o.nav2_yaml)
        result = PathExport(
            o.to,
            out,
            len(paths),
            int(sum(len(p.lonlat) for p in paths)),
            o.frame if o.to == "csv" else None,
            details,
            tuple(notes),
        )
        _record(run, out.name, {**result.to_json(), "path": str(Path(o.path).resolve())})
        run.save()
    return result


#: The path writers by format name (``formats.FORMATS``' path rows): options, the paths, the
#: notes and details to fill -> (the file's text, the costmap it read or None).
PATH_WRITERS: dict[str, Callable[[PathExportOptions, Any, list[str], dict[str, Any]], tuple[str, Path | None]]] = {
    "gpx": lambda o, paths, notes, details: (gpx_text(paths), None),
    "kml": lambda o, paths, notes, details: (kml_text(paths), None),
    "csv": lambda o, paths, notes, details: _csv(o, paths, notes, details),
}


def _csv(o: PathExportOptions, paths, notes: list[str], details: dict[str, Any]):
    """CSV text and the costmap it used (or None)."""

    costmap = _costmap_for_path(o, paths[0].properties)
    grid = band = None
    if costmap is not None:
        with open_raster(costmap) as ds:
            if ds.crs is None:
                raise InputError(f"{costmap} has no CRS; a costmap must be georeferenced")
            band = check_costmap_kind(ds, costmap, o.band)
            check_pixels(ds.width, ds.height, costmap, "costmap")  # budgets apply to every command
            grid = Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)
    elif o.costmap is None and paths[0].properties.get("costmap"):
        notes.append(f"the path's costmap {paths[0].properties['costmap']} is missing: no cost column")
    nav2: LocalFrame | None = None
    if o.frame == "nav2":
        if o.nav2_yaml is not None:
            nav2, _doc = read_nav2_frame(o.nav2_yaml)
        elif grid is not None:
            nav2 = nav2_geometry(grid, str(costmap), o.local_origin).frame
        else:
            raise InputError("a CSV in a Nav2 frame needs --nav2-yaml MAP.yaml or the costmap (--costmap COSTMAP.tif)")
        details.update(local_origin=list(nav2.origin), ground_m_per_crs_unit=nav2.scale, crs=crs_label(nav2.crs))
    elif grid is not None:
        details.update(crs=crs_label(grid.crs))
    tables = [path_table(p, o.frame, grid=grid, costmap=costmap, band=band or 1, nav2=nav2) for p in paths]
    return csv_text(tables), costmap
