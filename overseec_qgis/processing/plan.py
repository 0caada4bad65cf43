"""``overseec:plan``: the least-cost path on a costmap through given points (``overseec plan``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessing,
    QgsProcessingException,
    QgsProcessingOutputFile,
    QgsProcessingOutputNumber,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterFeatureSource,
    QgsProcessingParameterNumber,
    QgsProcessingParameterPoint,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterVectorDestination,
)

from overseec_core import defaults, runfiles

from .. import jobs
from ..layers import Provenance
from . import loading
from .base import OverseecAlgorithm, enum_parameter, path_figures, temp_file
from .cli_options import CliOption, add_cli_options, cli_args, cli_flags
from .parameters import (
    MODE_HELP,
    OVERRIDES_FLAGS,
    OVERRIDES_HELP,
    PLAN_MODES,
    PLANNER,
    POINT_HELP,
    add_overrides,
    override_args,
)

#: Planning on terrain, single routes only.
TERRAIN = (
    CliOption(
        "--dem",
        "Plan on terrain: elevation model (DEM)",
        "any CRS and resolution: steps cost their 3D length times a slope multiplier, uphill and downhill "
        "differ, and the length counts the climb; cells without elevation are impassable. Single routes only.",
        raster=True,
    ),
    CliOption("--slope-model", "Slope model (with a DEM)", needs="DEM"),
)

#: Suffixes of a destination the CLI writes itself as GeoJSON (WGS 84).
GEOJSON_SUFFIXES = (".geojson", ".json")


def vector_output(alg: OverseecAlgorithm, parameters, name: str, context) -> str:
    """The file a vector destination asks for (a plain file; GeoPackage tables are refused)."""
    dest = alg.parameterAsOutputLayer(parameters, name, context)
    if dest.startswith(("ogr:", "postgis:", "spatialite:", "memory:")):
        raise QgsProcessingException(f"{name}: save to a file (.gpkg, .geojson, .shp ...)")
    Path(dest).parent.mkdir(parents=True, exist_ok=True)
    return dest


def convert_vector(src: str, dest: str, context) -> None:
    """Write the layer ``src`` to ``dest`` in the format its extension names (QGIS's writer)."""
    from qgis.core import QgsVectorFileWriter, QgsVectorLayer

    layer = QgsVectorLayer(src, "path", "ogr")
    if not layer.isValid():
        raise QgsProcessingException(f"cannot read {src}")
    options = QgsVectorFileWriter.SaveVectorOptions()
    options.driverName = QgsVectorFileWriter.driverForExtension(Path(dest).suffix.lstrip("."))
    if not options.driverName:
        raise QgsProcessingException(f"OUTPUT: no vector format for {Path(dest).suffix}")
    error, message, *_ = QgsVectorFileWriter.writeAsVectorFormatV3(layer, dest, context.transformContext(), options)
    if error != QgsVectorFileWriter.NoError:
        raise QgsProcessingException(f"OUTPUT: cannot write {dest} ({message})")


class PlanAlgorithm(OverseecAlgorithm):
    """Plan path: the path as a vector file with its cost and length, and the GeoJSON the CLI writes."""

    ID = "plan"
    TAGS = ("plan", "route", "path", "shortest path", "least cost", "navigation")
    DISPLAY = "Plan path"
    HELP = (
        "Plans the least-cost path on a costmap from START through optional VIAS (a point layer, "
        "in feature order) to GOAL. Writes the path with its cost and length in metres (a "
        "GeoPackage in the costmap's CRS, GeoJSON in WGS 84, or any format QGIS writes), loaded "
        "as 'path — cost C, L m|km'. Same as `overseec plan`. With PAIRS (a layer of lines, first "
        "vertex = start, last = goal) it plans one route per line instead, from one costmap load, "
        "into one layer with each route's id, cost and length (`overseec plan --pairs`); START_POINTS "
        "and GOAL_POINTS (point layers, paired by a shared 'id' field, else by feature order) do the "
        "same for pairs given as points.\n"
        "Needs: COSTMAP, and START and GOAL, or PAIRS, or START_POINTS and GOAL_POINTS.\n"
        "With qgis_process, an output left as a temporary output is deleted when the command "
        "exits; give OUTPUT (and GEOJSON) a file name to keep the path."
    )
    COMMAND = "plan"
    #: COSTMAP is the positional argument; SMOOTH gates ``--smooth SMOOTH_TOLERANCE``; OUTPUT feeds
    #: ``--out`` as GeoJSON and ``--native-out`` otherwise (a GeoPackage, converted when asked).
    FLAGS = {
        "START": "--start",
        "PAIRS": "--pairs",
        "START_POINTS": "--pairs",
        "GOAL_POINTS": "--pairs",
        "VIAS": "--via",
        "GOAL": "--goal",
        "MODE": "--mode",
        **cli_flags(PLANNER + TERRAIN),
        **OVERRIDES_FLAGS,
        "SMOOTH_TOLERANCE": "--smooth",
        "OUTPUT": "--out",
    }
    OWN_DEFAULTS = {
        "MODE": "fast, as the plugin's interactive planning: a path comes back at once; exact is one choice away"
    }

    def initAlgorithm(self, config=None) -> None:
        """COSTMAP, START, GOAL, optional VIAS, the planner, overrides, smoothing, the path file."""
        self.param(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"),
            "a costmap GeoTIFF (Build costmap); its lethal sidecar is found beside it.",
        )
        self.param(QgsProcessingParameterPoint("START", "Start", optional=True), POINT_HELP + " Not with PAIRS.")
        self.param(QgsProcessingParameterPoint("GOAL", "Goal", optional=True), POINT_HELP + " Not with PAIRS.")
        self.param(
            QgsProcessingParameterFeatureSource(
                "PAIRS", "Start/goal pairs (lines: start -> goal)", [QgsProcessing.TypeVectorLine], optional=True
            ),
            "plan one route per line (first vertex = start, last = goal; ids from an 'id' field) "
            "instead of START/GOAL, into one layer. Optional.",
        )
        self.param(
            QgsProcessingParameterFeatureSource(
                "START_POINTS", "Start points (paired with goal points)", [QgsProcessing.TypeVectorPoint], optional=True
            ),
            "plan one route per start point to its goal point (GOAL_POINTS), paired by an 'id' field "
            "both layers have, else by feature order; instead of START/GOAL or PAIRS. Optional.",
        )
        self.param(
            QgsProcessingParameterFeatureSource(
                "GOAL_POINTS", "Goal points (paired with start points)", [QgsProcessing.TypeVectorPoint], optional=True
            ),
            "the goals of START_POINTS (as many, or the same ids). Optional.",
        )
        self.param(
            QgsProcessingParameterFeatureSource(
                "VIAS", "Via points (in order)", [QgsProcessing.TypeVectorPoint], optional=True
            ),
            "points to pass through, in feature order. Optional.",
        )
        self.param(enum_parameter("MODE", "Planner", PLAN_MODES, defaults.INTERACTIVE_PLAN_MODE), MODE_HELP)
        add_cli_options(self, PLANNER + TERRAIN)
        add_overrides(self, OVERRIDES_HELP + " The costmap file is not changed.")
        self.param(
            QgsProcessingParameterBoolean("SMOOTH", "Smooth the route (straight line-of-sight segments)", False),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterNumber(
                "SMOOTH_TOLERANCE",
                "Smoothing: most extra cost allowed (0.01 = 1 %)",
                QgsProcessingParameterNumber.Double,
                0.01,
                minValue=0.0,
                maxValue=1.0,
            ),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterVectorDestination("OUTPUT", "Path", QgsProcessing.TypeVectorLine),
            "a .gpkg (costmap's CRS), .geojson (WGS 84) or any other vector file.",
        )
        self.addOutput(QgsProcessingOutputFile("GEOJSON", "Path GeoJSON (WGS 84; input of Export path)"))
        self.addOutput(QgsProcessingOutputNumber("COST", "Path cost"))
        self.addOutput(QgsProcessingOutputNumber("LENGTH_M", "Path length (m)"))
        self.addOutput(QgsProcessingOutputNumber("ROUTES", "Routes planned (with PAIRS)"))

    def route_args(self, parameters, context, crs) -> list[str]:
        """``--start x y``, ``--via x y`` per via point, ``--goal x y``, all in ``crs``."""
        args = self.point_arg("START", self.point_in(parameters, "START", context, crs))
        for via in self.via_points(parameters, "VIAS", context, crs):
            args += self.point_arg("VIAS", via)
        return args + self.point_arg("GOAL", self.point_in(parameters, "GOAL", context, crs))

    def costmap_crs(self, parameters, context, costmap: str):
        """The costmap layer's CRS; one that has none cannot take points (said so, rather than
        "not a CRS: ''", which blames the point)."""
        crs = self.parameterAsRasterLayer(parameters, "COSTMAP", context).crs()
        if not crs.isValid():
            raise QgsProcessingException(
                f"the costmap {Path(costmap).name} has no CRS, so start and goal cannot be placed on it: "
                "assign one (Layer Properties › Source, or gdal_edit.py -a_srs EPSG:XXXX)"
            )
        return crs

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec plan --json``; the path loads named after its cost and length."""
        costmap = self.raster_file(parameters, "COSTMAP", context)
        crs = self.costmap_crs(parameters, context, costmap)
        names = ("START", "GOAL", "PAIRS", "START_POINTS", "GOAL_POINTS")
        given = {name: parameters.get(name) not in (None, "") for name in names}
        ways = [given["START"] or given["GOAL"], given["PAIRS"], given["START_POINTS"] or given["GOAL_POINTS"]]
        if sum(ways) > 1:
            raise QgsProcessingException("give START and GOAL, or PAIRS, or START_POINTS and GOAL_POINTS: one of them")
        if given["PAIRS"]:
            return self.plan_pairs(costmap, parameters, context, feedback)
        if ways[2]:
            pairs = self.point_pairs_file(parameters, context, crs)
            return self.plan_pairs(costmap, parameters, context, feedback, str(pairs))
        if not (given["START"] and given["GOAL"]):
            raise QgsProcessingException("give START and GOAL (or PAIRS: a layer of start -> goal lines)")
        route = self.route_args(parameters, context, crs)
        dest = vector_output(self, parameters, "OUTPUT", context)
        suffix = Path(dest).suffix.lower()
        geojson = Path(dest) if suffix in GEOJSON_SUFFIXES else temp_file(runfiles.PATH)
        args = [costmap, *route, "--crs", jobs.crs_text(crs), *self.arg("OUTPUT", geojson), "--json"]
        args += self.arg("MODE", self.enum_value(parameters, "MODE", context))
        args += cli_args(self, parameters, context, PLANNER + TERRAIN)
        native = None
        if suffix not in GEOJSON_SUFFIXES:
            native = dest if suffix == ".gpkg" else str(temp_file("path.gpkg"))  # a scratch name, not a run folder's
            args += ["--native-out", native]
        args += override_args(self, parameters, context, feedback)
        if self.parameterAsBool(parameters, "SMOOTH", context):
            args += self.arg("SMOOTH_TOLERANCE", repr(self.parameterAsDouble(parameters, "SMOOTH_TOLERANCE", context)))
        doc = self.cli(args, feedback, weights={"plan": 1.0})
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        if native is not None and native != dest:
            convert_vector(f"{native}|layername=path", dest, context)
        cost, length = path_figures(geojson)
        prov = Provenance(run_dir=str(Path(costmap).parent), prompt=str(doc.get("prompt") or ""), stage="plan")
        loading.name_destination(
            context, dest, loading.path_name(cost, length), loading.StyleLayer("path", "path", prov)
        )
        return {"OUTPUT": dest, "GEOJSON": str(geojson), "COST": cost, "LENGTH_M": length, "ROUTES": 1}

    def point_pairs_file(self, parameters, context, crs) -> Path:
        """START_POINTS and GOAL_POINTS paired (:func:`..pairsfile.point_pairs`) and written as the
        CLI's pairs CSV in the costmap's CRS ``crs`` (a temporary file)."""
        from .. import pairsfile

        starts = self.parameterAsSource(parameters, "START_POINTS", context)
        goals = self.parameterAsSource(parameters, "GOAL_POINTS", context)
        if starts is None or goals is None:
            raise QgsProcessingException("START_POINTS needs GOAL_POINTS (and GOAL_POINTS START_POINTS)")
        try:
            ctx = context.transformContext()
            pairs = pairsfile.point_pairs(
                starts, goals, pairsfile.transform_to(starts, crs, ctx), pairsfile.transform_to(goals, crs, ctx)
            )
            return pairsfile.write_pairs(pairs, temp_file("start-goal.csv"))
        except (jobs.OverseecError, OSError) as exc:
            raise QgsProcessingException(str(exc)) from None

    def plan_pairs(self, costmap: str, parameters, context, feedback, pairs: str | None = None) -> dict:
        """``overseec plan --pairs``: one route per line of PAIRS (or per pair of ``pairs``, a CSV
        in the costmap's CRS) into one layer (a GeoPackage, converted when OUTPUT asks for another
        format); COST and LENGTH_M are the routes' sums."""
        if pairs is None:
            pairs = self.vector_file(parameters, "PAIRS", context, feedback)
        dest = vector_output(self, parameters, "OUTPUT", context)
        gpkg = dest if Path(dest).suffix.lower() == ".gpkg" else str(temp_file("routes.gpkg"))
        args = [costmap, *self.arg("PAIRS", pairs), *self.arg("OUTPUT", gpkg), "--json"]
        args += self.arg("MODE", self.enum_value(parameters, "MODE", context))
        args += cli_args(self, parameters, context, PLANNER)
        args += override_args(self, parameters, context, feedback)
        doc = self.cli(args, feedback, weights={"pairs": 1.0})
        routes = doc.get("routes") or []
        for route in routes:
            if route.get("error"):
                feedback.pushWarning(str(route["error"]))
        if gpkg != dest:
            convert_vector(f"{gpkg}|layername={runfiles.PAIRS_LAYER}", dest, context)
        planned = [r for r in routes if r.get("total_cost") is not None]
        cost = float(sum(r["total_cost"] for r in planned))
        length = float(sum(r["length_m"] for r in planned))
        prov = Provenance(run_dir=str(Path(costmap).parent), stage="plan")
        name = f"routes — {len(planned)} of {len(routes)} pairs"
        loading.name_destination(context, dest, name, loading.StyleLayer("path", "path", prov))
        return {"OUTPUT": dest, "GEOJSON": "", "COST": cost, "LENGTH_M": length, "ROUTES": len(planned)}
