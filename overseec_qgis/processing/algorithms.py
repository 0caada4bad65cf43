"""overseec's Processing algorithms; parameters mirror the CLI's options.

=================  ====================  =======================================================
algorithm id       CLI                   runs
=================  ====================  =======================================================
overseec:interpret ``overseec interpret``  ``pipeline.run_interpret`` in-process (offline or LLM)
overseec:segment   ``overseec segment``    the worker process (torch stays out of QGIS)
overseec:costmap   ``overseec costmap``    ``pipeline.run_costmap`` in-process
overseec:plan      ``overseec plan``       ``pipeline.run_plan`` in-process
overseec:run       ``overseec run``        the worker process (the whole pipeline)
overseec:evaluate  ``overseec eval``       ``pipeline.run_evaluate`` in-process
overseec:exportcostmap ``overseec export costmap``  ``interop.export_costmap`` in-process
overseec:exportpath    ``overseec export path``     ``interop.export_path`` in-process
overseec:compare   ``overseec compare``    ``compare.run_compare`` in-process
=================  ====================  =======================================================

Every algorithm reports progress through ``feedback.setProgress`` and stops when
``feedback.isCanceled()`` (in-process stages poll it through the core's Progress protocol; worker
runs are terminated). Core errors become ``QgsProcessingException`` with the core's one-line
message. Outputs are Processing outputs (raster/vector layers, files, numbers) so the algorithms
chain in the Graphical Modeler.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from qgis.core import (
    QgsProcessing,
    QgsProcessingAlgorithm,
    QgsProcessingException,
    QgsProcessingOutputFile,
    QgsProcessingOutputNumber,
    QgsProcessingOutputRasterLayer,
    QgsProcessingOutputString,
    QgsProcessingOutputVectorLayer,
    QgsProcessingParameterAuthConfig,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterEnum,
    QgsProcessingParameterFeatureSource,
    QgsProcessingParameterFile,
    QgsProcessingParameterFileDestination,
    QgsProcessingParameterFolderDestination,
    QgsProcessingParameterMultipleLayers,
    QgsProcessingParameterNumber,
    QgsProcessingParameterPoint,
    QgsProcessingParameterRasterDestination,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
    QgsProcessingParameterVectorDestination,
    QgsProcessingParameterVectorLayer,
)
from qgis.PyQt.QtGui import QIcon

from .. import jobs
from ..layers import icon_path
from ..settings import PluginSettings, load_api_key
from ..task import QgisProgress
from ..worker import event_reporter, run_worker

PLAN_MODES = ("fast", "exact")
OVERRIDES_LABEL = "Override polygons (fields: cost 0-1, or prefer, or lethal)"

DEVICES = ("auto", "cpu", "cuda", "mps")


# --------------------------------------------------------------------------------------------
# Shared plumbing
# --------------------------------------------------------------------------------------------


class OverseecAlgorithm(QgsProcessingAlgorithm):
    """Names, help and the error contract shared by every overseec algorithm."""

    ID = ""
    DISPLAY = ""
    HELP = ""

    def name(self) -> str:
        return self.ID

    def displayName(self) -> str:  # noqa: N802
        return self.DISPLAY

    def group(self) -> str:
        return "overseec"

    def groupId(self) -> str:  # noqa: N802
        return "overseec"

    def shortHelpString(self) -> str:  # noqa: N802
        return self.HELP

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def createInstance(self):  # noqa: N802
        return type(self)()

    # -- helpers ---------------------------------------------------------------------------

    def raster_file(self, parameters, name: str, context, required: bool = True) -> str | None:
        """The GeoTIFF (or other GDAL file) behind a raster parameter."""
        layer = self.parameterAsRasterLayer(parameters, name, context)
        if layer is None:
            if required:
                raise QgsProcessingException(f"{name}: choose a raster layer or file")
            return None
        path = jobs.layer_file(layer)
        if not path:
            raise QgsProcessingException(f"{name}: {layer.source()} is not a raster file; save it as a GeoTIFF first")
        return path

    def vector_file(self, parameters, name: str, context, feedback) -> str | None:
        """A vector parameter as a file the core reads (memory layers exported to GeoJSON)."""
        if parameters.get(name) in (None, ""):
            return None
        path = self.parameterAsCompatibleSourceLayerPath(
            parameters, name, context, ["geojson", "gpkg", "shp", "json"], "geojson", feedback
        )
        return path.split("|")[0] or None

    def optional_str(self, parameters, name: str, context) -> str | None:
        value = self.parameterAsString(parameters, name, context).strip()
        return value or None

    def polygon_files(self, parameters, name: str, context, feedback) -> tuple[Path, ...]:
        """The files behind a multiple-layer parameter, in layer order: a layer's own file when it
        is a plain OGR file layer, else (memory, unsaved edits, a filter) a temporary GeoPackage
        written in the layer's CRS (the core reprojects)."""
        from qgis.core import QgsProcessingUtils, QgsVectorFileWriter

        files = []
        for i, layer in enumerate(self.parameterAsLayerList(parameters, name, context) or []):
            source = layer.source().split("|")[0]
            if (
                layer.providerType() == "ogr"
                and not layer.subsetString()
                and not layer.isModified()
                and Path(source).is_file()
            ):
                files.append(Path(source))
                continue
            out = Path(QgsProcessingUtils.tempFolder()) / f"overrides_{i}_{layer.id()}.gpkg"
            options = QgsVectorFileWriter.SaveVectorOptions()
            options.driverName = "GPKG"
            error, message, *_ = QgsVectorFileWriter.writeAsVectorFormatV3(
                layer, str(out), context.transformContext(), options
            )
            if error != QgsVectorFileWriter.NoError:
                raise QgsProcessingException(f"{name}: cannot save layer {layer.name()} ({message})")
            feedback.pushInfo(f"{layer.name()}: saved to {out} for overseec")
            files.append(out)
        return tuple(files)

    def optional_file(self, parameters, name: str, context) -> Path | None:
        value = self.parameterAsFile(parameters, name, context).strip()
        return Path(value) if value else None

    def core(self, fn: Callable[..., Any], *args, feedback=None, with_progress: bool = True, **kwargs) -> Any:
        """Call into the core (a pipeline function gets Processing's feedback as its Progress);
        the core's one-line errors become QgsProcessingException."""
        from overseec_core.errors import Cancelled, OverseecError

        if with_progress:
            kwargs["progress"] = QgisProgress(feedback) if feedback is not None else None
        try:
            return fn(*args, **kwargs)
        except Cancelled as exc:
            raise QgsProcessingException(str(exc)) from None
        except OverseecError as exc:
            raise QgsProcessingException(str(exc)) from None

    def worker(self, argv: list[str], env: dict[str, str], weights: dict[str, float], feedback) -> None:
        """Run the worker CLI; progress to ``feedback``; cancel = terminate the process."""
        on_event = event_reporter(weights, feedback.setProgress, feedback.setProgressText, feedback.pushInfo)
        feedback.pushCommandInfo(" ".join(argv))
        try:
            res = run_worker(argv, on_event=on_event, is_cancelled=feedback.isCanceled, env=env)
        except OSError as exc:
            raise QgsProcessingException(
                f"cannot start the overseec worker {argv[0]} ({exc.strerror or exc})"
            ) from None
        if res.cancelled:
            raise QgsProcessingException("cancelled; partial outputs were discarded")
        if not res.ok:
            if res.stderr.strip():
                feedback.reportError(res.stderr.strip(), False)
            raise QgsProcessingException(res.summary())
        feedback.setProgress(100.0)

    def find_worker(self) -> Path:
        settings = PluginSettings.load()
        worker = jobs.find_worker_for(settings)
        if worker is None:
            report = jobs.check_worker_env(None)
            raise QgsProcessingException(report.problems[0] + ". To fix: " + "; ".join(report.advice))
        return worker


def add_segment_parameters(alg: QgsProcessingAlgorithm, tiles_and_thresholds: bool = True) -> None:
    """The segmentation options of Segment (all) and Run (those `overseec run` takes)."""
    d = jobs.Params()
    alg.addParameter(QgsProcessingParameterString("BANDS", "Bands to read as R,G,B (e.g. 4,3,2)", optional=True))
    alg.addParameter(
        QgsProcessingParameterNumber(
            "TILE_SIZE", "Tile size (px)", QgsProcessingParameterNumber.Integer, d.tile_size, minValue=32
        )
    )
    if tiles_and_thresholds:
        alg.addParameter(
            QgsProcessingParameterNumber(
                "OVERLAP", "Tile overlap (px)", QgsProcessingParameterNumber.Integer, d.overlap, minValue=0
            )
        )
        alg.addParameter(
            QgsProcessingParameterNumber(
                "TAU_LINEAR",
                "Mask threshold, linear entities",
                QgsProcessingParameterNumber.Double,
                d.tau_linear,
                minValue=0.0,
                maxValue=1.0,
            )
        )
        alg.addParameter(
            QgsProcessingParameterNumber(
                "TAU_AREAL",
                "Mask threshold, areal entities",
                QgsProcessingParameterNumber.Double,
                d.tau_areal,
                minValue=0.0,
                maxValue=1.0,
            )
        )
    alg.addParameter(QgsProcessingParameterBoolean("REFINE", "Refine masks with SAM", d.refine))
    alg.addParameter(QgsProcessingParameterEnum("DEVICE", "Device", DEVICES, defaultValue=0))
    alg.addParameter(QgsProcessingParameterString("CLIPSEG_MODEL", "CLIPSeg model (hub id or folder)", optional=True))
    alg.addParameter(QgsProcessingParameterString("SAM_MODEL", "SAM model (hub id or folder)", optional=True))


def segment_params(alg: OverseecAlgorithm, parameters, context) -> jobs.Params:
    d = jobs.Params()

    def number(name, default, as_type):
        if alg.parameterDefinition(name) is None:
            return default
        return as_type(parameters, name, context)

    return jobs.Params(
        tile_size=alg.parameterAsInt(parameters, "TILE_SIZE", context),
        overlap=number("OVERLAP", d.overlap, alg.parameterAsInt),
        tau_linear=number("TAU_LINEAR", d.tau_linear, alg.parameterAsDouble),
        tau_areal=number("TAU_AREAL", d.tau_areal, alg.parameterAsDouble),
        refine=alg.parameterAsBool(parameters, "REFINE", context),
        device=DEVICES[alg.parameterAsEnum(parameters, "DEVICE", context)],
        clipseg_model=alg.optional_str(parameters, "CLIPSEG_MODEL", context) or "",
        sam_model=alg.optional_str(parameters, "SAM_MODEL", context) or "",
    )


def add_llm_parameters(alg: QgsProcessingAlgorithm) -> None:
    alg.addParameter(
        QgsProcessingParameterString(
            "LLM_URL", "LLM endpoint (OpenAI-compatible; empty = offline interpreter)", optional=True
        )
    )
    alg.addParameter(QgsProcessingParameterString("LLM_MODEL", "LLM model", optional=True))
    alg.addParameter(
        QgsProcessingParameterAuthConfig("LLM_AUTHCFG", "LLM API key (authentication configuration)", optional=True)
    )


def llm_config(alg: OverseecAlgorithm, parameters, context) -> jobs.LlmSettings:
    url = alg.optional_str(parameters, "LLM_URL", context)
    if not url:
        return jobs.LlmSettings()
    authcfg = alg.parameterAsString(parameters, "LLM_AUTHCFG", context)
    return jobs.LlmSettings(
        endpoint=url, model=alg.optional_str(parameters, "LLM_MODEL", context) or "", api_key=load_api_key(authcfg)
    )


# --------------------------------------------------------------------------------------------
# Algorithms
# --------------------------------------------------------------------------------------------


class InterpretAlgorithm(OverseecAlgorithm):
    ID = "interpret"
    DISPLAY = "Interpret prompt"
    HELP = (
        "Turns a mission prompt into entities (name, linear/areal, text prompts), preferences "
        "and a cost program, with the offline interpreter or an OpenAI-compatible LLM. Writes "
        "the interpretation as JSON (input of Segment and Build costmap). Same as "
        "`overseec interpret`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(QgsProcessingParameterString("PROMPT", "Mission prompt", multiLine=True))
        add_llm_parameters(self)
        self.addParameter(
            QgsProcessingParameterFileDestination("OUTPUT", "Interpretation (JSON)", "JSON files (*.json)")
        )
        self.addOutput(QgsProcessingOutputString("PROGRAM", "Cost program"))
        self.addOutput(QgsProcessingOutputString("ENTITIES", "Entities (comma-separated)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        prompt = self.parameterAsString(parameters, "PROMPT", context).strip()
        if not prompt:
            raise QgsProcessingException("PROMPT: write a mission prompt")
        out = self.parameterAsFileOutput(parameters, "OUTPUT", context)
        interp = self.core(jobs.interpret, prompt, llm_config(self, parameters, context), out=out, feedback=feedback)
        for note in tuple(interp.unparsed) + tuple(interp.notes):
            feedback.pushInfo(note)
        return {"OUTPUT": out, "PROGRAM": interp.program, "ENTITIES": ",".join(e.name for e in interp.entities)}


class SegmentAlgorithm(OverseecAlgorithm):
    ID = "segment"
    DISPLAY = "Segment entities"
    HELP = (
        "Finds each entity in the image with CLIPSeg on overlapping tiles (and SAM when "
        "Refine is on), in the overseec worker process. Entities come from an interpretation "
        "JSON (Interpret prompt) or a list like 'road:linear, grass, water:areal'. Writes "
        "probs.tif and masks.tif (one band per entity) into the output folder. Same as "
        "`overseec segment`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("INPUT", "Image"))
        self.addParameter(
            QgsProcessingParameterFile("INTERPRETATION", "Interpretation (JSON)", extension="json", optional=True)
        )
        self.addParameter(
            QgsProcessingParameterString("ENTITIES", "Entities (name[:linear|areal], comma-separated)", optional=True)
        )
        add_segment_parameters(self)
        self.addParameter(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"))
        self.addOutput(QgsProcessingOutputRasterLayer("MASKS", "Masks"))
        self.addOutput(QgsProcessingOutputRasterLayer("PROBS", "Probabilities"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        image = self.raster_file(parameters, "INPUT", context)
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        interp_file = self.optional_file(parameters, "INTERPRETATION", context)
        entities = self.optional_str(parameters, "ENTITIES", context)
        if (interp_file is None) == (entities is None):
            raise QgsProcessingException("give either INTERPRETATION (a JSON file) or ENTITIES")
        if interp_file is not None:
            interp = self.core(jobs.entities_from_file, interp_file, with_progress=False)
        else:
            interp = self.core(
                jobs.edited_interpretation,
                None,
                "",
                self.core(jobs.parse_entities, entities, with_progress=False),
                "",
                with_progress=False,
            )
        out_dir.mkdir(parents=True, exist_ok=True)
        params = segment_params(self, parameters, context)
        argv, env = jobs.segment_command(
            self.find_worker(), image, out_dir, interp, params, self.optional_str(parameters, "BANDS", context)
        )
        self.worker(argv, env, jobs.stage_weights("segment", params), feedback)
        return {
            "OUTPUT_DIR": str(out_dir),
            "MASKS": str(jobs.first_existing(out_dir, "mask")),
            "PROBS": str(jobs.first_existing(out_dir, "probability")),
        }


def parse_aliases(text: str) -> tuple[tuple[str, str], ...]:
    """'lake=water, woods=tree' -> (('lake', 'water'), ('woods', 'tree')), one line per mistake."""
    from overseec_core.interpret.matching import parse_aliases as parse

    try:
        return parse(text)
    except ValueError as exc:
        raise QgsProcessingException(f"ALIASES: {exc}") from None


class CostmapAlgorithm(OverseecAlgorithm):
    ID = "costmap"
    DISPLAY = "Build costmap"
    HELP = (
        "Composes a costmap GeoTIFF (float32 in [0, 1], lower = better) from entity layers -- "
        "a segment output folder and/or a class raster with classes.json -- and a cost "
        "program (text or file) or a prompt (interpreted offline). Also writes the lethal "
        "sidecar and the program text beside it. Only reads masks: re-prompting takes "
        "seconds. Same as `overseec costmap`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(
            QgsProcessingParameterFile(
                "MASKS",
                "Segment output folder (holds masks.tif)",
                behavior=QgsProcessingParameterFile.Folder,
                optional=True,
            )
        )
        self.addParameter(QgsProcessingParameterRasterLayer("LABELS", "Class raster (integer ids)", optional=True))
        self.addParameter(
            QgsProcessingParameterFile("CLASSES", "classes.json (class id -> name)", extension="json", optional=True)
        )
        self.addParameter(
            QgsProcessingParameterString(
                "PROMPT", "Mission prompt (interpreted offline)", multiLine=True, optional=True
            )
        )
        self.addParameter(
            QgsProcessingParameterString("PROGRAM_TEXT", "Cost program (text)", multiLine=True, optional=True)
        )
        self.addParameter(QgsProcessingParameterFile("PROGRAM", "Cost program (file)", optional=True))
        self.addParameter(
            QgsProcessingParameterString(
                "ALIASES", "Entity aliases for the prompt (e.g. lake=water, compound=building)", optional=True
            )
        )
        self.addParameter(
            QgsProcessingParameterMultipleLayers(
                "OVERRIDES", OVERRIDES_LABEL, QgsProcessing.TypeVectorPolygon, optional=True
            )
        )
        self.addParameter(QgsProcessingParameterRasterDestination("OUTPUT", "Costmap"))
        self.addOutput(QgsProcessingOutputFile("PROGRAM_FILE", "Cost program file"))
        self.addOutput(QgsProcessingOutputNumber("MEAN_COST", "Mean cost"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        from overseec_core.compose import CostmapOptions
        from overseec_core.pipeline import run_costmap

        out = Path(self.parameterAsOutputLayer(parameters, "OUTPUT", context))
        if out.suffix.lower() not in (".tif", ".tiff"):
            out = out.with_suffix(".tif")
        out.parent.mkdir(parents=True, exist_ok=True)
        options = CostmapOptions(
            out=out,
            masks=self.optional_file(parameters, "MASKS", context),
            labels=Path(p) if (p := self.raster_file(parameters, "LABELS", context, required=False)) else None,
            classes=self.optional_file(parameters, "CLASSES", context),
            prompt=self.optional_str(parameters, "PROMPT", context),
            program=self.optional_file(parameters, "PROGRAM", context),
            program_text=self.optional_str(parameters, "PROGRAM_TEXT", context),
            aliases=parse_aliases(self.optional_str(parameters, "ALIASES", context) or ""),
            overrides=self.polygon_files(parameters, "OVERRIDES", context, feedback),
        )
        if options.masks is None and options.labels is None:
            raise QgsProcessingException("give MASKS (a segment output folder) and/or LABELS + CLASSES")
        result = self.core(run_costmap, options, feedback=feedback)
        for note in tuple(result.notes) + tuple(result.warnings):
            feedback.pushInfo(note)
        return {"OUTPUT": str(result.costmap), "PROGRAM_FILE": str(result.program_file), "MEAN_COST": result.mean_cost}


class PlanAlgorithm(OverseecAlgorithm):
    ID = "plan"
    DISPLAY = "Plan path"
    HELP = (
        "Plans the least-cost path on a costmap from START through optional VIAS (a point "
        "layer, in feature order) to GOAL; points in any CRS. 'fast' plans in a coarse "
        "corridor first; 'exact' is the optimal 8-connected path. Writes GeoJSON with the "
        "path's cost and length in metres. Same as `overseec plan`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"))
        self.addParameter(QgsProcessingParameterPoint("START", "Start"))
        self.addParameter(QgsProcessingParameterPoint("GOAL", "Goal"))
        self.addParameter(
            QgsProcessingParameterFeatureSource(
                "VIAS", "Via points (in order)", [QgsProcessing.TypeVectorPoint], optional=True
            )
        )
        self.addParameter(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=0))
        self.addParameter(
            QgsProcessingParameterMultipleLayers(
                "OVERRIDES", OVERRIDES_LABEL, QgsProcessing.TypeVectorPolygon, optional=True
            )
        )
        self.addParameter(
            QgsProcessingParameterBoolean("SMOOTH", "Smooth the route (straight line-of-sight segments)", False)
        )
        self.addParameter(
            QgsProcessingParameterNumber(
                "SMOOTH_TOLERANCE",
                "Smoothing: most extra cost allowed (0.01 = 1 %)",
                QgsProcessingParameterNumber.Double,
                0.01,
                minValue=0.0,
                maxValue=1.0,
            )
        )
        self.addParameter(
            QgsProcessingParameterVectorDestination("OUTPUT", "Path", QgsProcessing.TypeVectorLine, defaultValue=None)
        )
        self.addOutput(QgsProcessingOutputNumber("COST", "Path cost"))
        self.addOutput(QgsProcessingOutputNumber("LENGTH_M", "Path length (m)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        from overseec_core.pipeline import run_plan
        from overseec_core.plan.stage import PlanOptions

        costmap = self.raster_file(parameters, "COSTMAP", context)
        crs = self.parameterAsRasterLayer(parameters, "COSTMAP", context).crs()
        start = self.parameterAsPoint(parameters, "START", context, crs)
        goal = self.parameterAsPoint(parameters, "GOAL", context, crs)
        points = [(start.x(), start.y())]
        vias = self.parameterAsSource(parameters, "VIAS", context)
        if vias is not None:
            from qgis.core import QgsCoordinateTransform

            ct = QgsCoordinateTransform(vias.sourceCrs(), crs, context.transformContext())
            for f in vias.getFeatures():
                p = ct.transform(f.geometry().asPoint())
                points.append((p.x(), p.y()))
        points.append((goal.x(), goal.y()))
        out = Path(self.parameterAsOutputLayer(parameters, "OUTPUT", context))
        if out.suffix.lower() not in (".geojson", ".json"):
            out = out.with_suffix(".geojson")
        out.parent.mkdir(parents=True, exist_ok=True)
        mode = PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)]
        options = self.core(
            PlanOptions,
            costmap=Path(costmap),
            points=tuple(points),
            out=out,
            crs=jobs.crs_text(crs),
            mode=mode,
            overrides=self.polygon_files(parameters, "OVERRIDES", context, feedback),
            smooth=self.parameterAsDouble(parameters, "SMOOTH_TOLERANCE", context)
            if self.parameterAsBool(parameters, "SMOOTH", context)
            else None,
            with_progress=False,
        )
        run = self.core(run_plan, options, feedback=feedback)
        for note in run.result.notes:
            feedback.pushInfo(note)
        drawn = run.smoothed if run.smoothed is not None else run.result  # the line written
        return {"OUTPUT": str(run.outputs["geojson"]), "COST": float(drawn.cost), "LENGTH_M": float(drawn.length_m)}


class RunAlgorithm(OverseecAlgorithm):
    ID = "run"
    DISPLAY = "Run full pipeline"
    HELP = (
        "Image + mission prompt -> interpretation, masks, cost program, costmap, a path when "
        "START and GOAL are given, and an evaluation when there is ground truth, in the "
        "overseec worker process, into one run folder with manifest.json. With a class raster "
        "(LABELS + CLASSES) its classes are the masks and no model runs. Same as `overseec run`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("INPUT", "Image"))
        self.addParameter(QgsProcessingParameterString("PROMPT", "Mission prompt", multiLine=True))
        add_llm_parameters(self)
        add_segment_parameters(self, tiles_and_thresholds=False)
        self.addParameter(
            QgsProcessingParameterRasterLayer("LABELS", "Class raster to use as masks (no segmentation)", optional=True)
        )
        self.addParameter(
            QgsProcessingParameterFile("CLASSES", "classes.json of the class raster", extension="json", optional=True)
        )
        self.addParameter(QgsProcessingParameterPoint("START", "Start (optional)", optional=True))
        self.addParameter(QgsProcessingParameterPoint("GOAL", "Goal (optional)", optional=True))
        self.addParameter(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=1))
        self.addParameter(
            QgsProcessingParameterVectorLayer(
                "REFERENCE",
                "Reference paths (for the Hausdorff distance)",
                [QgsProcessing.TypeVectorLine],
                optional=True,
            )
        )
        self.addParameter(
            QgsProcessingParameterBoolean("EVALUATE", "Evaluate (with a class raster or reference paths)", True)
        )
        self.addParameter(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Run folder"))
        self.addOutput(QgsProcessingOutputRasterLayer("COSTMAP", "Costmap"))
        self.addOutput(QgsProcessingOutputRasterLayer("MASKS", "Masks"))
        self.addOutput(QgsProcessingOutputRasterLayer("PROBS", "Probabilities"))
        self.addOutput(QgsProcessingOutputVectorLayer("PATH", "Path", QgsProcessing.TypeVectorLine))
        self.addOutput(QgsProcessingOutputFile("MANIFEST", "Manifest"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        image = self.raster_file(parameters, "INPUT", context)
        prompt = self.parameterAsString(parameters, "PROMPT", context).strip()
        if not prompt:
            raise QgsProcessingException("PROMPT: write a mission prompt")
        labels = self.raster_file(parameters, "LABELS", context, required=False)
        classes = self.optional_file(parameters, "CLASSES", context)
        if bool(labels) != bool(classes):
            raise QgsProcessingException("LABELS and CLASSES go together (a class raster and its classes.json)")
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        params = jobs.replace_params(
            segment_params(self, parameters, context),
            plan_mode=PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)],
        )
        crs = self.parameterAsRasterLayer(parameters, "INPUT", context).crs()
        points = []
        if parameters.get("START") not in (None, "") and parameters.get("GOAL") not in (None, ""):
            for name in ("START", "GOAL"):
                p = self.parameterAsPoint(parameters, name, context, crs)
                points.append((p.x(), p.y()))
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
        )
        self.worker(argv, env, jobs.stage_weights("run", params, segments=not labels), feedback)
        results = {"OUTPUT_DIR": str(out_dir), "MANIFEST": str(out_dir / "manifest.json")}
        for key, role in (("COSTMAP", "costmap"), ("MASKS", "mask"), ("PROBS", "probability"), ("PATH", "path")):
            found = jobs.first_existing(out_dir, role)
            results[key] = str(found) if found else None
        return results


class EvaluateAlgorithm(OverseecAlgorithm):
    ID = "evaluate"
    DISPLAY = "Evaluate path(s)"
    HELP = (
        "The OVerSeeC metrics: RRPI of paths planned between seeded start-goal pairs (needs "
        "the class raster, classes.json and ranks), their KDE centre of mass, the Hausdorff "
        "distance to reference paths, IoU of masks per class; plots and report.md. Same as "
        "`overseec eval`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(QgsProcessingParameterRasterLayer("COSTMAP", "Costmap", optional=True))
        self.addParameter(
            QgsProcessingParameterVectorLayer(
                "PATHS", "Paths to evaluate", [QgsProcessing.TypeVectorLine], optional=True
            )
        )
        self.addParameter(
            QgsProcessingParameterVectorLayer(
                "REFERENCE", "Reference paths (human-drawn)", [QgsProcessing.TypeVectorLine], optional=True
            )
        )
        self.addParameter(QgsProcessingParameterRasterLayer("LABELS", "Ground-truth class raster", optional=True))
        self.addParameter(QgsProcessingParameterFile("CLASSES", "classes.json", extension="json", optional=True))
        self.addParameter(QgsProcessingParameterString("RANKS", "Ranks (road=1,grass=2,...)", optional=True))
        self.addParameter(
            QgsProcessingParameterNumber(
                "PAIRS", "Start-goal pairs to sample", QgsProcessingParameterNumber.Integer, 50, minValue=0
            )
        )
        self.addParameter(QgsProcessingParameterNumber("SEED", "Sampler seed", QgsProcessingParameterNumber.Integer, 0))
        self.addParameter(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=1))
        self.addParameter(QgsProcessingParameterRasterLayer("MASKS", "Masks (for IoU)", optional=True))
        self.addParameter(QgsProcessingParameterBoolean("PLOTS", "Write plots", True))
        self.addParameter(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"))
        self.addOutput(QgsProcessingOutputFile("METRICS", "metrics.json"))
        self.addOutput(QgsProcessingOutputFile("REPORT", "report.md"))
        self.addOutput(QgsProcessingOutputVectorLayer("PATHS_OUT", "Evaluated paths", QgsProcessing.TypeVectorLine))
        self.addOutput(QgsProcessingOutputNumber("MEAN_HAUSDORFF", "Mean Hausdorff (fraction of the diagonal)"))
        self.addOutput(QgsProcessingOutputNumber("MEAN_IOU", "Mean IoU"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        from overseec_core.evaluate import EvaluateOptions
        from overseec_core.pipeline import run_evaluate

        def raster(name):
            p = self.raster_file(parameters, name, context, required=False)
            return Path(p) if p else None

        def vector(name):
            p = self.vector_file(parameters, name, context, feedback)
            return Path(p) if p else None

        options = EvaluateOptions(
            out_dir=Path(self.parameterAsString(parameters, "OUTPUT_DIR", context)),
            labels=raster("LABELS"),
            classes=self.optional_file(parameters, "CLASSES", context),
            ranks=self.optional_str(parameters, "RANKS", context),
            costmap=raster("COSTMAP"),
            pairs=self.parameterAsInt(parameters, "PAIRS", context),
            seed=self.parameterAsInt(parameters, "SEED", context),
            plan_mode=PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)],
            reference=vector("REFERENCE"),
            paths=vector("PATHS"),
            masks=raster("MASKS"),
            plots=self.parameterAsBool(parameters, "PLOTS", context),
        )
        result = self.core(run_evaluate, options, feedback=feedback)
        m = result.metrics
        for note in m.get("notes", []):
            feedback.pushInfo(note)
        files = result.files
        hausdorff = (m.get("hausdorff") or {}).get("mean_normalised")
        iou = (m.get("iou") or {}).get("mean_iou")
        return {
            "OUTPUT_DIR": str(options.out_dir),
            "METRICS": str(files["metrics"]),
            "REPORT": str(files["report"]),
            "PATHS_OUT": str(files["paths_geojson"]) if "paths_geojson" in files else None,
            "MEAN_HAUSDORFF": hausdorff,
            "MEAN_IOU": iou,
        }


class ExportCostmapAlgorithm(OverseecAlgorithm):
    ID = "exportcostmap"
    DISPLAY = "Export costmap (Nav2, costmap_2d, NumPy)"
    HELP = (
        "Writes a costmap and its lethal sidecar for other planners: a ROS 2 Nav2 map (YAML + "
        "PGM, or a grey+alpha PNG in 'scale' mode; needs a projected grid with square ground "
        "cells), a costmap_2d uint8 GeoTIFF (0-252 passable, 254 lethal, 255 unknown) or a "
        ".npy array with a JSON sidecar (transform, CRS, ground pixel size, cost scale). "
        "Same as `overseec export costmap`."
    )
    FORMATS = ("nav2", "costmap2d", "npy")
    SUFFIX = {"nav2": ".yaml", "costmap2d": ".tif", "npy": ".npy"}

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        from overseec_core.interop import NAV2_MODES

        self.addParameter(QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"))
        self.addParameter(QgsProcessingParameterEnum("FORMAT", "Format", self.FORMATS, defaultValue=0))
        self.addParameter(QgsProcessingParameterEnum("NAV2_MODE", "Nav2 map mode", NAV2_MODES, defaultValue=0))
        self.addParameter(
            QgsProcessingParameterPoint(
                "LOCAL_ORIGIN", "Nav2 local frame origin (default: the lower-left corner)", optional=True
            )
        )
        self.addParameter(
            QgsProcessingParameterFileDestination(
                "OUTPUT",
                "Output (map.yaml, costmap2d.tif or cost.npy)",
                "Nav2 map (*.yaml);;GeoTIFF (*.tif);;NumPy (*.npy)",
            )
        )
        self.addOutput(QgsProcessingOutputString("FILES", "Files written (comma-separated)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        from overseec_core.interop import NAV2_MODES, CostmapExportOptions, export_costmap

        layer = self.parameterAsRasterLayer(parameters, "COSTMAP", context)
        costmap = self.raster_file(parameters, "COSTMAP", context)
        to = self.FORMATS[self.parameterAsEnum(parameters, "FORMAT", context)]
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        if out.suffix.lower() != self.SUFFIX[to]:
            out = out.with_suffix(self.SUFFIX[to])
        out.parent.mkdir(parents=True, exist_ok=True)
        origin = None
        if parameters.get("LOCAL_ORIGIN") not in (None, ""):
            p = self.parameterAsPoint(parameters, "LOCAL_ORIGIN", context, layer.crs())
            origin = (p.x(), p.y())
        options = CostmapExportOptions(
            costmap=Path(costmap),
            to=to,
            out=out,
            local_origin=origin,
            nav2_mode=NAV2_MODES[self.parameterAsEnum(parameters, "NAV2_MODE", context)],
        )
        result = self.core(export_costmap, options, feedback=feedback)
        for note in result.notes:
            feedback.pushInfo(note)
        return {"OUTPUT": str(out), "FILES": ",".join(str(p) for p in result.outputs.values())}


class ExportPathAlgorithm(OverseecAlgorithm):
    ID = "exportpath"
    DISPLAY = "Export path (GPX, KML, CSV)"
    HELP = (
        "Writes a planned path (the GeoJSON Plan path writes) as GPX for handheld GPS, KML for "
        "Google Earth, or CSV (x, y, cumulative ground length, cell cost) in the costmap's CRS "
        "or in the local frame of an exported Nav2 map. Same as `overseec export path`."
    )
    FORMATS = ("gpx", "kml", "csv")

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        from overseec_core.interop import FRAMES

        self.addParameter(QgsProcessingParameterFile("PATH", "Path (GeoJSON from Plan path)", extension="geojson"))
        self.addParameter(QgsProcessingParameterEnum("FORMAT", "Format", self.FORMATS, defaultValue=0))
        self.addParameter(QgsProcessingParameterEnum("FRAME", "CSV coordinates", FRAMES, defaultValue=0))
        self.addParameter(
            QgsProcessingParameterFile("NAV2_YAML", "Nav2 map (for the nav2 frame)", extension="yaml", optional=True)
        )
        self.addParameter(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap (default: the one the path names)", optional=True)
        )
        self.addParameter(
            QgsProcessingParameterFileDestination("OUTPUT", "Output", "GPX (*.gpx);;KML (*.kml);;CSV (*.csv)")
        )

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        from overseec_core.interop import FRAMES, PathExportOptions, export_path

        to = self.FORMATS[self.parameterAsEnum(parameters, "FORMAT", context)]
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        if out.suffix.lower() != f".{to}":
            out = out.with_suffix(f".{to}")
        out.parent.mkdir(parents=True, exist_ok=True)
        costmap = self.raster_file(parameters, "COSTMAP", context, required=False)
        options = PathExportOptions(
            path=Path(self.parameterAsFile(parameters, "PATH", context)),
            to=to,
            out=out,
            frame=FRAMES[self.parameterAsEnum(parameters, "FRAME", context)],
            nav2_yaml=self.optional_file(parameters, "NAV2_YAML", context),
            costmap=Path(costmap) if costmap else None,
        )
        result = self.core(export_path, options, feedback=feedback)
        for note in result.notes:
            feedback.pushInfo(note)
        return {"OUTPUT": str(out)}


class CompareAlgorithm(OverseecAlgorithm):
    ID = "compare"
    DISPLAY = "Compare prompts"
    HELP = (
        "Two or more prompts (one per line) and/or cost program files on the same entity layers "
        "and points: each gets its costmap and route (prompt_1/, prompt_2/ ... in the output "
        "folder), plus a difference raster (cost of prompt k minus prompt 1), a side-by-side "
        "figure, and a table of route length, cost, share of the route per class (with a class "
        "raster) and the Hausdorff distance between routes. Same as `overseec compare`."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.addParameter(
            QgsProcessingParameterString("PROMPTS", "Prompts (one per line)", multiLine=True, optional=True)
        )
        self.addParameter(
            QgsProcessingParameterMultipleLayers(
                "PROGRAMS", "Cost program files", QgsProcessing.TypeFile, optional=True
            )
        )
        self.addParameter(
            QgsProcessingParameterFile(
                "MASKS",
                "Segment output folder (holds masks.tif)",
                behavior=QgsProcessingParameterFile.Folder,
                optional=True,
            )
        )
        self.addParameter(QgsProcessingParameterRasterLayer("LABELS", "Class raster (integer ids)", optional=True))
        self.addParameter(
            QgsProcessingParameterFile("CLASSES", "classes.json (class id -> name)", extension="json", optional=True)
        )
        self.addParameter(
            QgsProcessingParameterString("ALIASES", "Entity aliases for the prompts (e.g. lake=water)", optional=True)
        )
        self.addParameter(QgsProcessingParameterPoint("START", "Start"))
        self.addParameter(QgsProcessingParameterPoint("GOAL", "Goal"))
        self.addParameter(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=1))
        self.addParameter(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"))
        self.addOutput(QgsProcessingOutputRasterLayer("DIFFERENCE", "Cost difference"))
        self.addOutput(QgsProcessingOutputFile("FIGURE", "Side-by-side figure (PNG)"))
        self.addOutput(QgsProcessingOutputFile("TABLE", "Route table (CSV)"))
        self.addOutput(QgsProcessingOutputFile("REPORT", "Report (Markdown)"))
        self.addOutput(QgsProcessingOutputNumber("MAX_HAUSDORFF_M", "Largest Hausdorff distance between routes (m)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        from qgis.core import QgsCoordinateReferenceSystem

        from overseec_core.compare import CompareOptions, make_candidates, run_compare

        text = self.parameterAsString(parameters, "PROMPTS", context)
        items = [("prompt", line.strip()) for line in text.splitlines() if line.strip()]
        items += [
            ("program", p) for p in self.parameterAsFileList(parameters, "PROGRAMS", context) if p.strip()
        ]  # an unset parameter gives [""]
        labels = self.raster_file(parameters, "LABELS", context, required=False)
        layer = self.parameterAsRasterLayer(parameters, "LABELS", context)
        crs = layer.crs() if layer is not None else QgsCoordinateReferenceSystem("EPSG:4326")
        start = self.parameterAsPoint(parameters, "START", context, crs)
        goal = self.parameterAsPoint(parameters, "GOAL", context, crs)
        options = self.core(
            CompareOptions,
            out_dir=Path(self.parameterAsString(parameters, "OUTPUT_DIR", context)),
            candidates=self.core(make_candidates, items, with_progress=False),
            points=((start.x(), start.y()), (goal.x(), goal.y())),
            crs=jobs.crs_text(crs),
            mode=PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)],
            masks=self.optional_file(parameters, "MASKS", context),
            labels=Path(labels) if labels else None,
            classes=self.optional_file(parameters, "CLASSES", context),
            aliases=parse_aliases(self.optional_str(parameters, "ALIASES", context) or ""),
            with_progress=False,
        )
        result = self.core(run_compare, options, feedback=feedback)
        for note in result.notes:
            feedback.pushInfo(note)
        for row in result.rows:
            feedback.pushInfo(f"{row.name} ({row.prompt}): {row.length_m:.1f} m, cost {row.cost:.4g}")
        farthest = max((d for row in result.hausdorff_m for d in row), default=0.0)
        files = result.files
        return {
            "OUTPUT_DIR": str(options.out_dir),
            "DIFFERENCE": str(files["difference"]),
            "FIGURE": str(files["figure"]),
            "TABLE": str(files["csv"]),
            "REPORT": str(files["report"]),
            "MAX_HAUSDORFF_M": float(farthest),
        }


ALGORITHMS = (
    InterpretAlgorithm,
    SegmentAlgorithm,
    CostmapAlgorithm,
    PlanAlgorithm,
    RunAlgorithm,
    EvaluateAlgorithm,
    ExportCostmapAlgorithm,
    ExportPathAlgorithm,
    CompareAlgorithm,
)
