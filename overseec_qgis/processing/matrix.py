"""``overseec:costmatrix``: the route cost between every two points (``overseec plan --matrix``).

One costmap load and one search per source point give the whole table, as the CLI does; the
points come from point layers (any CRS: the CLI reads them in the costmap's), ids from an ``id``
field or the feature ids. The CSV is the CLI's: a header ``from,<point ids>``, one row per source,
empty where no route joins the two.
"""

from __future__ import annotations

import csv
from pathlib import Path

from qgis.core import (
    QgsProcessing,
    QgsProcessingException,
    QgsProcessingOutputNumber,
    QgsProcessingParameterFeatureSource,
    QgsProcessingParameterFileDestination,
    QgsProcessingParameterRasterLayer,
)

from overseec_core import defaults

from .base import OverseecAlgorithm, enum_parameter
from .cli_options import add_cli_options, cli_args, cli_flags
from .parameters import (
    MODE_HELP,
    OVERRIDES_FLAGS,
    OVERRIDES_HELP,
    PLAN_MODES,
    PLANNER,
    add_overrides,
    override_args,
)

#: Formats the CLI reads a point layer from as one layer (a GeoPackage table is exported first:
#: the CLI reads a file's first table).
SINGLE_LAYER_FORMATS = ["geojson", "shp"]


def read_matrix(path: Path) -> tuple[int, int, int]:
    """(rows, columns, pairs without a route) of the CLI's matrix CSV."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    body = [r[1:] for r in rows[1:]]
    return len(body), len(rows[0]) - 1 if rows else 0, sum(1 for r in body for v in r if v == "")


class CostMatrixAlgorithm(OverseecAlgorithm):
    """Cost matrix: ``overseec plan --matrix`` between the points of one or two layers."""

    ID = "costmatrix"
    TAGS = ("cost matrix", "od matrix", "origin destination", "many to many", "route", "distance table")
    DISPLAY = "Cost matrix (route cost between points)"
    HELP = (
        "The cost of the least-cost route between every two points of POINTS (or from each point of "
        "SOURCES to each point of POINTS: one-to-many), on one costmap load with one search per "
        "source, as a CSV table: a header 'from,<point ids>', one row per source, the cost in the "
        "costmap's units (cost x ground metres, as Plan path's COST), empty where no route joins the "
        "two. Ids come from an 'id' field, else the feature ids. Same as `overseec plan --matrix`.\n"
        "Needs: COSTMAP and POINTS."
    )
    COMMAND = "plan"
    FLAGS = {
        "POINTS": "--points",
        "SOURCES": "--sources",
        "MODE": "--mode",
        **cli_flags(PLANNER),
        **OVERRIDES_FLAGS,
        "OUTPUT": "--matrix",
    }
    OWN_DEFAULTS = {"MODE": "fast, as the plugin's interactive planning and Plan path: exact is one choice away"}

    def initAlgorithm(self, config=None) -> None:
        """COSTMAP, POINTS, optional SOURCES, the planner, overrides, the CSV."""
        self.param(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"),
            "a costmap GeoTIFF (Build costmap); its lethal sidecar is found beside it.",
        )
        self.param(
            QgsProcessingParameterFeatureSource("POINTS", "Points", [QgsProcessing.TypeVectorPoint]),
            "the table's columns (and its rows without SOURCES), in any CRS; ids from an 'id' field.",
        )
        self.param(
            QgsProcessingParameterFeatureSource(
                "SOURCES", "Sources (rows; default: the points)", [QgsProcessing.TypeVectorPoint], optional=True
            ),
            "price from these points to POINTS instead (one-to-many). Optional.",
        )
        self.param(enum_parameter("MODE", "Planner", PLAN_MODES, defaults.INTERACTIVE_PLAN_MODE), MODE_HELP)
        add_cli_options(self, PLANNER)
        add_overrides(self, OVERRIDES_HELP + " The costmap file is not changed.")
        self.param(
            QgsProcessingParameterFileDestination("OUTPUT", "Cost matrix", "CSV (*.csv)"),
            "a CSV table (see above).",
        )
        self.addOutput(QgsProcessingOutputNumber("ROWS", "Rows (sources)"))
        self.addOutput(QgsProcessingOutputNumber("COLUMNS", "Columns (points)"))
        self.addOutput(QgsProcessingOutputNumber("UNREACHABLE", "Pairs without a route"))

    def points_file(self, parameters, name: str, context, feedback) -> str | None:
        """A point parameter as a one-layer file the CLI reads (a GeoPackage table, a memory
        layer or a selection written to GeoJSON first); None when not given."""
        if parameters.get(name) in (None, ""):
            return None
        path = self.parameterAsCompatibleSourceLayerPath(
            parameters, name, context, SINGLE_LAYER_FORMATS, "geojson", feedback
        )
        if not path:
            raise QgsProcessingException(f"{name}: choose a point layer or file")
        return path.split("|")[0]

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec plan --matrix --json``; the table's shape and unreachable pairs come back."""
        costmap = self.raster_file(parameters, "COSTMAP", context)
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        if out.suffix.lower() != ".csv":
            out = out.with_suffix(".csv")
        out.parent.mkdir(parents=True, exist_ok=True)
        args = [costmap, *self.arg("POINTS", self.points_file(parameters, "POINTS", context, feedback))]
        args += self.arg("SOURCES", self.points_file(parameters, "SOURCES", context, feedback))
        args += [*self.arg("OUTPUT", out), "--json"]
        args += self.arg("MODE", self.enum_value(parameters, "MODE", context))
        args += cli_args(self, parameters, context, PLANNER)
        args += override_args(self, parameters, context, feedback)
        doc = self.cli(args, feedback, weights={"matrix": 1.0})
        for note in doc.get("notes") or []:  # points on impassable cells: their costs are empty
            feedback.pushWarning(str(note))
        rows, columns, unreachable = read_matrix(out)
        feedback.pushInfo(f"cost matrix: {rows} x {columns}, {unreachable} pair(s) without a route -> {out}")
        if unreachable:
            feedback.pushWarning(f"{unreachable} pair(s) have no route (empty cells of the table)")
        return {"OUTPUT": str(out), "ROWS": rows, "COLUMNS": columns, "UNREACHABLE": unreachable}
