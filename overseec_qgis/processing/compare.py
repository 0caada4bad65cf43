"""``overseec:compare``: prompts and cost programs side by side on the same layers and points (``overseec compare``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsProcessing,
    QgsProcessingOutputFile,
    QgsProcessingOutputNumber,
    QgsProcessingOutputRasterLayer,
    QgsProcessingParameterFolderDestination,
    QgsProcessingParameterMultipleLayers,
    QgsProcessingParameterPoint,
    QgsProcessingParameterString,
)

from overseec_core import defaults

from .. import jobs
from . import loading
from .base import OverseecAlgorithm, enum_parameter
from .parameters import (
    ALIASES_FLAGS,
    LAYER_FLAGS,
    MODE_HELP,
    PLAN_MODES,
    POINT_HELP,
    PRIORS_FLAGS,
    add_layer_sources,
    add_priors_parameters,
    aliases_args,
    layer_source_args,
    priors_args,
)


class CompareAlgorithm(OverseecAlgorithm):
    """Compare prompts: a costmap and route per prompt, a difference raster, a figure and a table."""

    ID = "compare"
    TAGS = ("compare", "prompts", "routes", "difference", "costmap")
    DISPLAY = "Compare prompts"
    GROUP = "evaluate"
    HELP = (
        "Two or more prompts (one per line) and/or cost program files on the same entity layers "
        "and points: each gets its costmap and route (prompt_1/, prompt_2/ ... in the output "
        "folder), plus a difference raster (cost of prompt k minus prompt 1), a side-by-side "
        "figure, and a table of route length, cost, share of the route per class (with a class "
        "raster) and the Hausdorff distance between routes. Same as `overseec compare`.\n"
        "Needs: entity layers (MASKS, or LABELS + CLASSES), two or more of PROMPTS/PROGRAMS, "
        "START and GOAL."
    )
    COMMAND = "compare"
    #: PROMPTS feeds one ``--prompt`` per line.
    FLAGS = {
        **LAYER_FLAGS,
        "PROMPTS": "--prompt",
        "PROGRAMS": "--program",
        **ALIASES_FLAGS,
        **PRIORS_FLAGS,
        "START": "--start",
        "GOAL": "--goal",
        "MODE": "--mode",
        "OUTPUT_DIR": "--out",
    }

    def initAlgorithm(self, config=None) -> None:
        """Entity layers, the prompts and programs, aliases, priors, the points, the planner, the folder."""
        add_layer_sources(self)
        self.param(
            QgsProcessingParameterString("PROMPTS", "Prompts (one per line)", multiLine=True, optional=True),
            "each line one mission prompt, interpreted offline.",
        )
        self.param(
            QgsProcessingParameterMultipleLayers(
                "PROGRAMS", "Cost program files", QgsProcessing.TypeFile, optional=True
            ),
            "compared after the prompts, in order.",
        )
        self.param(
            QgsProcessingParameterString("ALIASES", "Entity aliases for the prompts (e.g. lake=water)", optional=True),
            "",
            advanced=True,
        )
        add_priors_parameters(self)
        self.param(QgsProcessingParameterPoint("START", "Start"), POINT_HELP)
        self.param(QgsProcessingParameterPoint("GOAL", "Goal"), POINT_HELP)
        self.param(enum_parameter("MODE", "Planner", PLAN_MODES, defaults.PLAN_MODE), MODE_HELP, advanced=True)
        self.param(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"), "")
        self.addOutput(QgsProcessingOutputRasterLayer("DIFFERENCE", "Cost difference"))
        self.addOutput(QgsProcessingOutputFile("FIGURE", "Side-by-side figure (PNG)"))
        self.addOutput(QgsProcessingOutputFile("TABLE", "Route table (CSV)"))
        self.addOutput(QgsProcessingOutputFile("REPORT", "Report (Markdown)"))
        self.addOutput(QgsProcessingOutputNumber("MAX_HAUSDORFF_M", "Largest Hausdorff distance between routes (m)"))

    def ends_args(self, parameters, context) -> list[str]:
        """``--start``, ``--goal`` in the start's own CRS (the goal reprojected to it), and ``--crs``;
        bare ``x,y`` points stay in the layers' CRS, as the CLI takes them."""
        crs = self.parameterAsPointCrs(parameters, "START", context)
        raw = parameters.get("START")
        if not crs.isValid() or (isinstance(raw, str) and "[" not in raw):
            crs = QgsCoordinateReferenceSystem()
        args = self.point_arg("START", self.point_in(parameters, "START", context, crs))
        args += self.point_arg("GOAL", self.point_in(parameters, "GOAL", context, crs))
        return args + (["--crs", jobs.crs_text(crs)] if crs.isValid() else [])

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec compare --json``; a line per prompt goes to the log; the routes and the
        cost difference load as layers where there is a project."""
        args = layer_source_args(self, parameters, context)
        text = self.parameterAsString(parameters, "PROMPTS", context)
        for line in text.splitlines():
            args += self.arg("PROMPTS", line.strip(), joined=True)
        programs = [p for p in self.parameterAsFileList(parameters, "PROGRAMS", context) if p.strip()]
        for program in programs:  # (an unset parameter gives [""])
            args += self.arg("PROGRAMS", program)
        args += aliases_args(self, parameters, context)
        args += priors_args(self, parameters, context)
        args += self.ends_args(parameters, context)
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        args += self.arg("MODE", self.enum_value(parameters, "MODE", context)) + self.arg("OUTPUT_DIR", out_dir)
        doc = self.cli([*args, "--json"], feedback)
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        for row in doc.get("prompts") or []:
            feedback.pushInfo(
                f"{row['name']} ({row.get('prompt') or row.get('kind')}): "
                f"{row['length_m']:.1f} m, cost {row['cost']:.4g}"
            )
        loading.load_compare_layers(context, out_dir, doc)
        farthest = max((d for row in doc.get("hausdorff_m") or [] for d in row if d is not None), default=0.0)
        files = doc.get("files") or {}
        return {
            "OUTPUT_DIR": str(out_dir),
            "DIFFERENCE": files.get("difference"),
            "FIGURE": files.get("figure"),
            "TABLE": files.get("csv"),
            "REPORT": files.get("report"),
            "MAX_HAUSDORFF_M": float(farthest),
        }
