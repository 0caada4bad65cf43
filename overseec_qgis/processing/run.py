"""``overseec:run``: the whole pipeline into one run folder (``overseec run``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessing,
    QgsProcessingException,
    QgsProcessingOutputFile,
    QgsProcessingOutputRasterLayer,
    QgsProcessingOutputVectorLayer,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterFile,
    QgsProcessingParameterFolderDestination,
    QgsProcessingParameterPoint,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
    QgsProcessingParameterVectorLayer,
)

from overseec_core import defaults, runfiles

from .. import jobs
from . import loading
from .base import OverseecAlgorithm, enum_parameter, path_figures
from .cli_options import add_cli_options, cli_flags
from .model_settings import MODEL_SETTINGS_FLAGS, add_model_settings, with_model_settings
from .parameters import (
    MODE_HELP,
    PLAN_MODES,
    POINT_HELP,
    PRIORS_FLAGS,
    SEGMENT_FLAGS,
    SEGMENT_INVERTED,
    STEPS,
    add_llm_parameters,
    add_priors_parameters,
    add_segment_parameters,
    llm_config,
    priors_choice,
    segment_params,
)

#: Result outputs -> the role of the run folder's file they name.
OUTPUT_ROLES = {"COSTMAP": "costmap", "MASKS": "mask", "PROBS": "probability", "PATH": "path"}


class RunAlgorithm(OverseecAlgorithm):
    """Run full pipeline: interpretation, masks, costmap, a path and an evaluation in one folder."""

    ID = "run"
    TAGS = ("run", "pipeline", "prompt", "costmap", "route", "mission")
    DISPLAY = "Run full pipeline"
    HELP = (
        "Image + mission prompt -> interpretation, masks (by the SEGMENTER, CLIPSeg by default), cost "
        "program, costmap, a path when START "
        "and GOAL are given, and an evaluation when there is ground truth, into one run folder "
        f"with {runfiles.MANIFEST}. The path, costmap and per-entity masks are loaded into one group "
        "named after the run. With a class raster (LABELS + CLASSES) its classes are the masks "
        "and no model runs. Same as `overseec run`.\n"
        "Needs: INPUT and PROMPT; START and GOAL together for a path; LABELS and CLASSES together."
    )
    COMMAND = "run"
    #: The worker client (:func:`overseec_qgis.jobs.run_command`) builds the argv, as for the dock.
    FLAGS = {
        "PROMPT": "--prompt",
        "START": "--start",
        "GOAL": "--goal",
        "MODE": "--mode",
        **cli_flags((STEPS,)),
        "LABELS": "--labels",
        "CLASSES": "--classes",
        "DEM": "--dem",
        **PRIORS_FLAGS,
        **SEGMENT_FLAGS,
        **MODEL_SETTINGS_FLAGS,
        "REFERENCE": "--reference",
        "EVALUATE": "--no-eval",
        "OUTPUT_DIR": "--out",
    }
    INVERTED = SEGMENT_INVERTED | {"EVALUATE"}

    def initAlgorithm(self, config=None) -> None:
        """INPUT, PROMPT, optional points, the planner, a class raster, priors, LLM, models, evaluation."""
        self.param(QgsProcessingParameterRasterLayer("INPUT", "Image"), "a georeferenced image file (GeoTIFF ...).")
        self.param(
            QgsProcessingParameterString("PROMPT", "Mission prompt", multiLine=True),
            "what to prefer and avoid, e.g. 'prefer the roads, avoid the water'.",
        )
        self.param(QgsProcessingParameterPoint("START", "Start", optional=True), POINT_HELP + " Optional, with GOAL.")
        self.param(QgsProcessingParameterPoint("GOAL", "Goal", optional=True), POINT_HELP + " Optional, with START.")
        self.param(enum_parameter("MODE", "Planner", PLAN_MODES, defaults.PLAN_MODE), MODE_HELP)
        add_cli_options(self, (STEPS,))
        self.param(
            QgsProcessingParameterRasterLayer(
                "LABELS", "Class raster to use as masks (no segmentation)", optional=True
            ),
            "a classified raster whose classes act as entities; needs CLASSES.",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterFile("CLASSES", "classes.json of the class raster", extension="json", optional=True),
            "class id -> name; needed with LABELS.",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterRasterLayer("DEM", "Elevation model (DEM) for slope and roughness", optional=True),
            "as Build costmap's DEM: any CRS and resolution; the costmap gets slopes above 15 degrees "
            "costlier, and an LLM is offered slope and roughness.",
            advanced=True,
        )
        add_priors_parameters(self)
        add_llm_parameters(self)
        add_segment_parameters(self, tiles_and_thresholds=False)
        add_model_settings(self)
        self.param(
            QgsProcessingParameterVectorLayer(
                "REFERENCE",
                "Reference paths (for the Hausdorff distance)",
                [QgsProcessing.TypeVectorLine],
                optional=True,
            ),
            "human-drawn routes to compare the planned path with.",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterBoolean("EVALUATE", "Evaluate (with a class raster or reference paths)", True),
            "",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Run folder"),
            f"every output and {runfiles.MANIFEST} go here.",
        )
        self.addOutput(QgsProcessingOutputRasterLayer("COSTMAP", "Costmap"))
        self.addOutput(QgsProcessingOutputRasterLayer("MASKS", "Masks"))
        self.addOutput(QgsProcessingOutputRasterLayer("PROBS", "Probabilities"))
        self.addOutput(QgsProcessingOutputVectorLayer("PATH", "Path", QgsProcessing.TypeVectorLine))
        self.addOutput(QgsProcessingOutputFile("MANIFEST", "Manifest"))

    def processAlgorithm(self, parameters, context, feedback):
        """Check what goes together, run ``overseec run`` and load its layers into one group."""
        image = self.raster_file(parameters, "INPUT", context)
        prompt = self.parameterAsString(parameters, "PROMPT", context).strip()
        if not prompt:
            raise QgsProcessingException("PROMPT: write a mission prompt")
        labels = self.optional_raster_file(parameters, "LABELS", context)
        classes = self.optional_file(parameters, "CLASSES", context)
        if bool(labels) != bool(classes):
            raise QgsProcessingException("LABELS and CLASSES go together (a class raster and its classes.json)")
        given = [parameters.get(n) not in (None, "") for n in ("START", "GOAL")]
        if given[0] != given[1]:
            raise QgsProcessingException("START and GOAL go together (give both for a path, or neither)")
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        params = jobs.replace_params(
            with_model_settings(self, parameters, context, segment_params(self, parameters, context)),
            plan_mode=self.enum_value(parameters, "MODE", context),
            plan_neighbours=int(self.enum_value(parameters, "NEIGHBOURS", context)),
        )
        crs = self.parameterAsRasterLayer(parameters, "INPUT", context).crs()
        points = [self.point_in(parameters, n, context, crs) for n in ("START", "GOAL")] if all(given) else []
        out_dir.mkdir(parents=True, exist_ok=True)
        argv, env = jobs.run_command(
            self.find_worker(),
            image,
            out_dir,
            prompt,
            params,
            llm_config(self, parameters, context),
            self.optional_str(parameters, "BANDS", context),
            points,
            jobs.crs_text(crs),
            labels,
            str(classes) if classes else None,
            self.vector_file(parameters, "REFERENCE", context, feedback),
            self.parameterAsBool(parameters, "EVALUATE", context),
            priors_choice(self, parameters, context),
            dem=self.optional_raster_file(parameters, "DEM", context),
        )
        self.run_argv(argv, env, jobs.stage_weights("run", params, segments=not labels), feedback)
        found = {key: runfiles.first_existing(out_dir, role) for key, role in OUTPUT_ROLES.items()}
        path = found["PATH"]
        label = loading.path_name(*path_figures(path)) if path is not None else ""
        loading.load_run_layers(context, out_dir, prompt, path_label=label)
        results: dict[str, str | None] = {"OUTPUT_DIR": str(out_dir), "MANIFEST": str(out_dir / runfiles.MANIFEST)}
        results.update({key: str(f) if f is not None else None for key, f in found.items()})
        return results
