"""``overseec:exportcostmap`` and ``overseec:exportpath``: costmaps and paths for other planners and
devices (``overseec export costmap``, ``overseec export path``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessing,
    QgsProcessingOutputString,
    QgsProcessingParameterFeatureSource,
    QgsProcessingParameterFile,
    QgsProcessingParameterFileDestination,
    QgsProcessingParameterPoint,
    QgsProcessingParameterRasterLayer,
)

from overseec_core import defaults, formats, runfiles

from ..layers import Provenance
from ..legend import layer_name
from . import loading
from .base import OverseecAlgorithm, enum_parameter

#: `overseec export costmap --to` and `--nav2-mode` choices, and the suffix of each format's main file.
COSTMAP_FORMATS = defaults.COSTMAP_FORMATS
NAV2_MODES = defaults.NAV2_MODES
COSTMAP_SUFFIX = {name: formats.BY_NAME[name].suffix for name in COSTMAP_FORMATS}
#: `overseec export path --to` and `--frame` choices (a format is its file's suffix).
PATH_FORMATS = defaults.PATH_FORMATS
FRAMES = defaults.PATH_FRAMES


#: Exported path formats QGIS opens as a line layer, and the layer's URI (GPX: its tracks).
PATH_LAYER_URIS = {f.name: f.layer_uri for f in formats.FORMATS if f.exports == "path" and f.layer_uri}


def with_suffix(out: Path, suffix: str) -> Path:
    """``out`` with ``suffix`` unless it already has it (in any case)."""
    return out if out.suffix.lower() == suffix else out.with_suffix(suffix)


class ExportCostmapAlgorithm(OverseecAlgorithm):
    """Export costmap: a Nav2 map, a costmap_2d GeoTIFF or a NumPy array with its sidecar."""

    ID = "exportcostmap"
    TAGS = ("export", "nav2", "costmap_2d", "ros", "occupancy grid", "robot")
    DISPLAY = "Export costmap (Nav2, costmap_2d, NumPy)"
    GROUP = "export"
    HELP = (
        "Writes a costmap and its lethal sidecar for other planners: a ROS 2 Nav2 map (YAML + "
        "PGM, or a grey+alpha PNG in 'scale' mode; needs a projected grid with square ground "
        "cells), a costmap_2d uint8 GeoTIFF (0-252 passable, 254 lethal, 255 unknown) or a .npy "
        "array with a JSON sidecar (transform, CRS, ground pixel size, cost scale). Same as "
        "`overseec export costmap`.\n"
        "Needs: COSTMAP."
    )
    COMMAND = "export costmap"
    #: COSTMAP is the positional argument.
    FLAGS = {"FORMAT": "--to", "NAV2_MODE": "--nav2-mode", "LOCAL_ORIGIN": "--local-origin", "OUTPUT": "--out"}

    def initAlgorithm(self, config=None) -> None:
        """COSTMAP, the format, the Nav2 options and the output file."""
        self.param(QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"), "a costmap GeoTIFF.")
        self.param(enum_parameter("FORMAT", "Format", COSTMAP_FORMATS, "nav2"), "")
        self.param(
            enum_parameter("NAV2_MODE", "Nav2 map mode", NAV2_MODES, "trinary"),
            "trinary: PGM free/occupied/unknown; scale: PNG keeping the cost levels.",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterPoint(
                "LOCAL_ORIGIN", "Nav2 local frame origin (default: the lower-left corner)", optional=True
            ),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterFileDestination(
                "OUTPUT",
                "Output (map.yaml, costmap2d.tif or cost.npy)",
                formats.file_filter("costmap"),
            ),
            "the suffix follows FORMAT.",
        )
        self.addOutput(QgsProcessingOutputString("FILES", "Files written (comma-separated)"))

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec export costmap --json``; OUTPUT takes the format's suffix. A costmap_2d
        GeoTIFF loads as a layer (Nav2's PGM/PNG and NumPy arrays carry no georeferencing QGIS reads)."""
        costmap = self.raster_file(parameters, "COSTMAP", context)
        layer = self.parameterAsRasterLayer(parameters, "COSTMAP", context)
        to = self.enum_value(parameters, "FORMAT", context)
        out = with_suffix(Path(self.parameterAsFileOutput(parameters, "OUTPUT", context)), COSTMAP_SUFFIX[to])
        out.parent.mkdir(parents=True, exist_ok=True)
        args = [costmap, *self.arg("FORMAT", to), *self.arg("OUTPUT", out), "--json"]
        args += self.arg("NAV2_MODE", self.enum_value(parameters, "NAV2_MODE", context))
        if parameters.get("LOCAL_ORIGIN") not in (None, ""):
            args += self.point_arg("LOCAL_ORIGIN", self.point_in(parameters, "LOCAL_ORIGIN", context, layer.crs()))
        doc = self.cli(args, feedback)
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        if to == "costmap2d":  # a georeferenced GeoTIFF: on the map beside its costmap
            prov = Provenance(run_dir=str(out.parent), stage="export")
            name = layer_name(
                "costmap_2d", layer.customProperty("overseec/prompt", "") or "", f"costmap_2d — {out.name}"
            )
            loading.load_on_completion(
                context, str(out), name, "OUTPUT", loading.StyleLayer("costmap2d", "export", prov)
            )
        return {"OUTPUT": str(out), "FILES": ",".join(str(p) for p in (doc.get("outputs") or {}).values())}


class ExportPathAlgorithm(OverseecAlgorithm):
    """Export path: GPX, KML or CSV of a planned path."""

    ID = "exportpath"
    TAGS = ("export", "route", "path", "gpx", "waypoints", "nav2")
    DISPLAY = "Export path (GPX, KML, CSV)"
    GROUP = "export"
    HELP = (
        "Writes a planned path (the GeoJSON Plan path writes, its GEOJSON output, or a route layer "
        f"of the map tool's {runfiles.PATHS_LAYER}, or any line layer) as GPX for "
        "handheld GPS, KML for Google Earth, or CSV (x, y, cumulative ground length, cell cost) in "
        "the costmap's CRS or in the local frame of an exported Nav2 map. Same as "
        "`overseec export path`.\n"
        "Needs: PATH."
    )
    COMMAND = "export path"
    #: PATH's file is the positional argument; the table it names in that file feeds --layer.
    FLAGS = {
        "PATH": "--layer",
        "FORMAT": "--to",
        "FRAME": "--frame",
        "NAV2_YAML": "--nav2-yaml",
        "COSTMAP": "--costmap",
        "OUTPUT": "--out",
    }

    def initAlgorithm(self, config=None) -> None:
        """PATH, the format, the CSV frame, a Nav2 map, a costmap and the output file."""
        self.param(
            QgsProcessingParameterFeatureSource(
                "PATH", "Path (route layer or Plan path's GeoJSON)", [QgsProcessing.TypeVectorLine]
            ),
            "Plan path's GEOJSON output (WGS 84, with the path's properties), a route layer the map "
            f"tool drew (a table of {runfiles.PATHS_LAYER}) or any line layer, in any CRS; with 'Selected "
            "features only', just those routes.",
        )
        self.param(enum_parameter("FORMAT", "Format", PATH_FORMATS, "gpx"), "")
        self.param(
            enum_parameter("FRAME", "CSV coordinates", FRAMES, "crs"),
            "crs: the costmap's CRS; nav2: the local frame of NAV2_YAML.",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterFile("NAV2_YAML", "Nav2 map (for the nav2 frame)", extension="yaml", optional=True),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap (default: the one the path names)", optional=True),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterFileDestination("OUTPUT", "Output", formats.file_filter("path")),
            "the suffix follows FORMAT.",
        )

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec export path --json``; OUTPUT takes the format's suffix. GPX and KML load
        as line layers in the routes group (a CSV is a table of points, left as a file)."""
        to = self.enum_value(parameters, "FORMAT", context)
        out = with_suffix(Path(self.parameterAsFileOutput(parameters, "OUTPUT", context)), f".{to}")
        out.parent.mkdir(parents=True, exist_ok=True)
        path, layer = self.vector_file_and_layer(parameters, "PATH", context, feedback)
        args = [path, *self.arg("FORMAT", to), *self.arg("OUTPUT", out), "--json"]
        args += self.arg("PATH", layer)
        args += self.arg("FRAME", self.enum_value(parameters, "FRAME", context))
        args += self.arg("NAV2_YAML", self.optional_file(parameters, "NAV2_YAML", context))
        args += self.arg("COSTMAP", self.optional_raster_file(parameters, "COSTMAP", context))
        doc = self.cli(args, feedback)
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        if to in PATH_LAYER_URIS:  # GPX and KML open as line layers: into the routes group
            prov = Provenance(run_dir=str(out.parent), stage="export")
            uri = PATH_LAYER_URIS[to].format(path=out)
            post = loading.StyleLayer("path", "path", prov)
            loading.load_on_completion(context, uri, layer_name("path", "", f"path — {out.name}"), "OUTPUT", post)
        return {"OUTPUT": str(out)}
