"""The export formats: one table that the writers, the CLI, Processing and the plugin read.

Each format has its name (``export costmap --to nav2``), what it exports (a costmap or a path),
the suffix of its main file, a label for file dialogs and one line of help. Adding a format is a
row here and its writer in :mod:`overseec_core.interop` (``COSTMAP_WRITERS``/``PATH_WRITERS``,
checked against this table by the tests); the choices, help texts, file filters and suffixes
follow. Standard library only: the QGIS plugin imports it at load.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ExportFormat:
    """One export format."""

    name: str  # what --to and Processing's FORMAT offer
    exports: str  # "costmap" or "path"
    suffix: str  # the main file's suffix, with its dot
    label: str  # the file dialogs' name of it
    help: str  # one line for --help and Processing
    #: How QGIS opens the exported file as a line layer (paths; None: not a layer, e.g. CSV).
    layer_uri: str | None = None


#: The formats, in menu order (Processing enums hold indices: append, never reorder).
FORMATS: tuple[ExportFormat, ...] = (
    ExportFormat("nav2", "costmap", ".yaml", "Nav2 map", "a ROS 2 Nav2 map_server map (YAML + PGM/PNG)"),
    ExportFormat("costmap2d", "costmap", ".tif", "costmap_2d GeoTIFF", "a costmap_2d-valued uint8 GeoTIFF"),
    ExportFormat("npy", "costmap", ".npy", "NumPy array", "a .npy array with a JSON sidecar"),
    ExportFormat("gpx", "path", ".gpx", "GPX", "GPX tracks (WGS 84)", "{path}|layername=tracks"),
    ExportFormat("kml", "path", ".kml", "KML", "KML placemarks (WGS 84)", "{path}"),
    ExportFormat("csv", "path", ".csv", "CSV", "a CSV of points (the costmap's CRS or a Nav2 frame)"),
)
BY_NAME: dict[str, ExportFormat] = {f.name: f for f in FORMATS}


def names(exports: str) -> tuple[str, ...]:
    """The names of the formats that export ``exports`` ("costmap" or "path"), in menu order."""
    return tuple(f.name for f in FORMATS if f.exports == exports)


def describe(exports: str) -> str:
    """ "nav2: a ROS 2 Nav2 map ...; costmap2d: ...": the formats' help, for help texts."""
    return "; ".join(f"{f.name}: {f.help}" for f in FORMATS if f.exports == exports)


def file_filter(exports: str) -> str:
    """A Qt file-dialog filter of the formats ("GPX (*.gpx);;KML (*.kml);;CSV (*.csv)")."""
    return ";;".join(f"{f.label} (*{f.suffix})" for f in FORMATS if f.exports == exports)
