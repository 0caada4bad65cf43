"""``overseec:evaluate``: the OVerSeeC metrics of planned or given paths and masks (``overseec eval``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessing,
    QgsProcessingOutputFile,
    QgsProcessingOutputNumber,
    QgsProcessingOutputVectorLayer,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterFile,
    QgsProcessingParameterFolderDestination,
    QgsProcessingParameterNumber,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
    QgsProcessingParameterVectorLayer,
)

from overseec_core import defaults, runfiles

from ..layers import Provenance
from . import loading
from .base import OverseecAlgorithm, enum_parameter
from .parameters import MODE_HELP, PLAN_MODES

#: What `overseec eval` writes into its folder.
FILES = runfiles.EVALUATION_FILES


class EvaluateAlgorithm(OverseecAlgorithm):
    """Evaluate path(s): metrics, a report, plots and the evaluated paths."""

    ID = "evaluate"
    TAGS = ("evaluate", "rrpi", "hausdorff", "iou", "metrics", "reference path")
    DISPLAY = "Evaluate path(s)"
    GROUP = "evaluate"
    HELP = (
        "The OVerSeeC metrics: RRPI of paths planned between seeded start-goal pairs, their KDE "
        "centre of mass, the Hausdorff distance to reference paths, IoU of masks per class; plots "
        f"and {FILES['report']} in the output folder. Same as `overseec eval`.\n"
        "Needs, per metric: RRPI: COSTMAP + LABELS + CLASSES + RANKS; Hausdorff: REFERENCE and "
        "PATHS (or COSTMAP to plan them); IoU: MASKS + LABELS + CLASSES."
    )
    COMMAND = "eval"
    FLAGS = {
        "COSTMAP": "--costmap",
        "PATHS": "--paths",
        "REFERENCE": "--reference",
        "LABELS": "--labels",
        "CLASSES": "--classes",
        "RANKS": "--ranks",
        "PAIRS": "--pairs",
        "SEED": "--seed",
        "PAIR_DRAW": "--pair-draw",
        "MODE": "--mode",
        "MASKS": "--masks",
        "PLOTS": "--no-plots",
        "OUTPUT_DIR": "--out",
    }
    INVERTED = frozenset({"PLOTS"})

    def initAlgorithm(self, config=None) -> None:
        """The inputs of each metric (all optional), the sampler, the planner, plots, the folder."""
        self.param(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap", optional=True),
            "the costmap to plan the sampled pairs (and reference ends) on.",
        )
        self.param(
            QgsProcessingParameterVectorLayer(
                "PATHS", "Paths to evaluate", [QgsProcessing.TypeVectorLine], optional=True
            ),
            "line layer(s) in any CRS, instead of planning them.",
        )
        self.param(
            QgsProcessingParameterVectorLayer(
                "REFERENCE", "Reference paths (human-drawn)", [QgsProcessing.TypeVectorLine], optional=True
            ),
            "for the Hausdorff distance.",
        )
        self.param(
            QgsProcessingParameterRasterLayer("LABELS", "Ground-truth class raster", optional=True),
            "integer class ids on the costmap's grid; needs CLASSES.",
        )
        self.param(
            QgsProcessingParameterFile("CLASSES", "classes.json", extension="json", optional=True),
            "class id -> name.",
        )
        self.param(
            QgsProcessingParameterString("RANKS", "Ranks (road=1,grass=2,...)", optional=True),
            "rank per class, 1 = most preferred (names or ids).",
        )
        self.param(
            QgsProcessingParameterNumber(
                "PAIRS", "Start-goal pairs to sample", QgsProcessingParameterNumber.Integer, 50, minValue=0
            ),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterNumber("SEED", "Sampler seed", QgsProcessingParameterNumber.Integer, 0),
            "",
            advanced=True,
        )
        self.param(
            enum_parameter("PAIR_DRAW", "Where pairs are drawn", defaults.PAIR_DRAWS, defaults.PAIR_DRAWS[0]),
            "passable: over passable cells, 20 % of the diagonal apart; image: uniformly over the whole "
            "image, as the paper draws its 50 pairs (pairs on impassable cells are unreachable).",
            advanced=True,
        )
        self.param(enum_parameter("MODE", "Planner", PLAN_MODES, defaults.PLAN_MODE), MODE_HELP, advanced=True)
        self.param(
            QgsProcessingParameterRasterLayer("MASKS", "Masks (for IoU)", optional=True),
            "a masks raster (one named band per entity) or a class raster.",
            advanced=True,
        )
        self.param(QgsProcessingParameterBoolean("PLOTS", "Write plots", True), "", advanced=True)
        self.param(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"), "")
        self.addOutput(QgsProcessingOutputFile("METRICS", FILES["metrics"]))
        self.addOutput(QgsProcessingOutputFile("REPORT", FILES["report"]))
        self.addOutput(QgsProcessingOutputVectorLayer("PATHS_OUT", "Evaluated paths", QgsProcessing.TypeVectorLine))
        self.addOutput(
            QgsProcessingOutputNumber("HAUSDORFF_PAPER", "Hausdorff as the paper defines it (mean distance / diagonal)")
        )
        self.addOutput(QgsProcessingOutputNumber("MEAN_HAUSDORFF", "Mean per-path maximum Hausdorff / diagonal"))
        self.addOutput(QgsProcessingOutputNumber("MEAN_IOU", "Mean IoU"))

    def eval_args(self, parameters, context, feedback, out_dir: Path) -> list[str]:
        """The argv of ``overseec eval --json`` for the parameters given."""
        args = [*self.arg("OUTPUT_DIR", out_dir), "--json"]
        for name in ("COSTMAP", "LABELS", "MASKS"):
            args += self.arg(name, self.optional_raster_file(parameters, name, context))
        for name in ("PATHS", "REFERENCE"):
            args += self.arg(name, self.vector_file(parameters, name, context, feedback))
        args += self.arg("CLASSES", self.optional_file(parameters, "CLASSES", context))
        args += self.arg("RANKS", self.optional_str(parameters, "RANKS", context), joined=True)
        for name in ("PAIRS", "SEED"):
            args += self.arg(name, self.parameterAsInt(parameters, name, context))
        args += self.arg("PAIR_DRAW", self.enum_value(parameters, "PAIR_DRAW", context))
        args += self.arg("MODE", self.enum_value(parameters, "MODE", context))
        return args + self.arg("PLOTS", self.parameterAsBool(parameters, "PLOTS", context))

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec eval``; the evaluated paths load when it wrote them."""
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        metrics = self.cli(self.eval_args(parameters, context, feedback, out_dir), feedback)
        for note in metrics.get("notes", []):
            feedback.pushInfo(str(note))
        paths = out_dir / FILES["paths_geojson"]
        if paths.is_file():
            post = loading.StyleLayer("path", "path", Provenance(run_dir=str(out_dir), stage="evaluate"))
            loading.load_on_completion(context, str(paths), "evaluated paths", "PATHS_OUT", post)
        return {
            "OUTPUT_DIR": str(out_dir),
            "METRICS": str(out_dir / FILES["metrics"]),
            "REPORT": str(out_dir / FILES["report"]),
            "PATHS_OUT": str(paths) if paths.is_file() else None,
            "HAUSDORFF_PAPER": (metrics.get("hausdorff") or {}).get("mean_paper_normalised"),
            "MEAN_HAUSDORFF": (metrics.get("hausdorff") or {}).get("mean_normalised"),
            "MEAN_IOU": (metrics.get("iou") or {}).get("mean_iou"),
        }
