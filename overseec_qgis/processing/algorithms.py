"""overseec's Processing algorithms: each one is an ``overseec`` command run by the worker.

=======================  ===========================  ==========  ===============================
algorithm id             CLI                          group       loads (when asked to)
=======================  ===========================  ==========  ===============================
overseec:extractimagery  (in-process, QGIS renders)  Pipeline    the GeoTIFF
overseec:interpret       ``overseec interpret``       Pipeline    (a JSON file)
overseec:segment         ``overseec segment``         Pipeline    masks, probabilities (a group)
overseec:costmap         ``overseec costmap``         Pipeline    'costmap — <prompt>'
overseec:plan            ``overseec plan``            Pipeline    'path — cost C, L m|km'
overseec:run             ``overseec run``             Pipeline    path, costmap, masks (a group)
overseec:evaluate        ``overseec eval``            Evaluate    evaluated paths
overseec:compare         ``overseec compare``         Evaluate    (files, difference raster)
overseec:exportcostmap   ``overseec export costmap``  Export      (files)
overseec:exportpath      ``overseec export path``     Export      (a file)
=======================  ===========================  ==========  ===============================

Why through the worker (:mod:`.base`; all but Extract imagery, which needs QGIS's renderer):
the QGIS process has no compiled planner kernel, no torch and no plotting stack; progress and
Cancel work the same for every algorithm; and a result is byte for byte what the CLI writes.
Outputs are Processing outputs (layers, files, numbers), so the algorithms chain in the Graphical
Modeler; destination outputs take any path Processing offers, the default temporary output
included, in the format that path asks for.
"""

from __future__ import annotations

import json
from pathlib import Path

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsProcessing,
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
    QgsProcessingUtils,
)

from .. import jobs
from ..layers import Provenance
from ..settings import load_api_key
from . import loading
from .base import OverseecAlgorithm, alias_args, parse_aliases, point_args, route_args

PLAN_MODES = ("fast", "exact")
DEVICES = ("auto", "cpu", "cuda", "mps")
OVERRIDES_LABEL = "Override polygons (fields: cost 0-1, or prefer, or lethal)"
OVERRIDES_HELP = (
    "polygon layers (any CRS) drawn over the costmap: a 'cost' field (0-1) sets the cost inside, "
    "prefer=1 makes it the cheapest, lethal=1 impassable. Optional."
)
MODE_HELP = (
    "fast: coarse-to-fine in a corridor, with a lower bound on the optimum; exact: the optimal 8-connected path."
)
POINT_HELP = "a point in any CRS (Processing reprojects it to the raster's)."
PRIORS_HELP = (
    'a JSON object of entity -> prior level in (0.5, 1] or "lethal"/"obstacle" replacing the built-in '
    'priors of unsaid hazards, e.g. {"building": 0.9, "water": "lethal"}. Default: the built-in table.'
)
NO_PRIORS_HELP = "no priors: what the prompt does not mention is neutral ground (0.5). Not with PRIORS."


# --------------------------------------------------------------------------------------------
# Shared parameter sets
# --------------------------------------------------------------------------------------------


def add_segment_parameters(alg: OverseecAlgorithm, tiles_and_thresholds: bool = True) -> None:
    """The segmentation options of Segment (all) and Run (those `overseec run` takes); all
    advanced: the defaults are the CLI's."""
    d = jobs.Params()
    alg.param(
        QgsProcessingParameterString("BANDS", "Bands to read as R,G,B (e.g. 4,3,2)", optional=True),
        "default: the image's first three bands (or its single band).",
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterNumber(
            "TILE_SIZE", "Tile size (px)", QgsProcessingParameterNumber.Integer, d.tile_size, minValue=32
        ),
        "pixels per tile side fed to CLIPSeg.",
        advanced=True,
    )
    if tiles_and_thresholds:
        alg.param(
            QgsProcessingParameterNumber(
                "OVERLAP", "Tile overlap (px)", QgsProcessingParameterNumber.Integer, d.overlap, minValue=0
            ),
            "pixels shared by neighbouring tiles (blended, no seams).",
            advanced=True,
        )
        for name, label, value in (
            ("TAU_LINEAR", "Mask threshold, linear entities", d.tau_linear),
            ("TAU_AREAL", "Mask threshold, areal entities", d.tau_areal),
        ):
            alg.param(
                QgsProcessingParameterNumber(
                    name, label, QgsProcessingParameterNumber.Double, value, minValue=0.0, maxValue=1.0
                ),
                "probability at and above which a pixel is in the mask (entities without their own).",
                advanced=True,
            )
    alg.param(
        QgsProcessingParameterBoolean("REFINE", "Refine masks with SAM", d.refine),
        "sharper masks, several times slower.",
        advanced=True,
    )
    alg.param(QgsProcessingParameterEnum("DEVICE", "Device", DEVICES, defaultValue=0), "", advanced=True)
    alg.param(
        QgsProcessingParameterString("CLIPSEG_MODEL", "CLIPSeg model (hub id or folder)", optional=True),
        "default: the CLI's model.",
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterString("SAM_MODEL", "SAM model (hub id or folder)", optional=True),
        "default: the CLI's model.",
        advanced=True,
    )


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


def add_llm_parameters(alg: OverseecAlgorithm) -> None:
    alg.param(
        QgsProcessingParameterString("LLM_URL", "LLM endpoint (OpenAI-compatible)", optional=True),
        "e.g. http://localhost:11434/v1; empty: the offline interpreter.",
        advanced=True,
    )
    alg.param(QgsProcessingParameterString("LLM_MODEL", "LLM model", optional=True), "", advanced=True)
    alg.param(
        QgsProcessingParameterAuthConfig("LLM_AUTHCFG", "LLM API key (authentication configuration)", optional=True),
        "kept in QGIS's authentication database; reaches the worker through its environment.",
        advanced=True,
    )


def llm_config(alg: OverseecAlgorithm, parameters, context) -> jobs.LlmSettings:
    url = alg.optional_str(parameters, "LLM_URL", context)
    if not url:
        return jobs.LlmSettings()
    authcfg = alg.parameterAsString(parameters, "LLM_AUTHCFG", context)
    return jobs.LlmSettings(
        endpoint=url, model=alg.optional_str(parameters, "LLM_MODEL", context) or "", api_key=load_api_key(authcfg)
    )


def llm_args(llm: jobs.LlmSettings) -> list[str]:
    """The interpreter's CLI options: ``--offline`` or none (the LLM goes in :func:`llm_env`)."""
    return jobs.llm_cli(llm)[0]


def llm_env(llm: jobs.LlmSettings) -> dict[str, str]:
    """The worker's environment with the LLM endpoint, model and key (never its command line)."""
    return jobs.worker_env(jobs.llm_cli(llm)[1])


def add_priors_parameters(alg: OverseecAlgorithm) -> None:
    """PRIORS and NO_PRIORS of the algorithms that read prompts (`--priors FILE`, `--no-priors`)."""
    alg.param(
        QgsProcessingParameterFile("PRIORS", "Priors of unsaid hazards (JSON file)", extension="json", optional=True),
        PRIORS_HELP,
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterBoolean("NO_PRIORS", "No priors (unsaid hazards are neutral)", False),
        NO_PRIORS_HELP,
        advanced=True,
    )


def priors_choice(alg: OverseecAlgorithm, parameters, context) -> jobs.Priors:
    """PRIORS / NO_PRIORS as given; both given reach the command, whose own error says so."""
    path = alg.optional_file(parameters, "PRIORS", context)
    return jobs.Priors(str(path) if path else "", alg.parameterAsBool(parameters, "NO_PRIORS", context))


def add_layer_sources(alg: OverseecAlgorithm) -> None:
    """Entity layers of Build costmap and Compare: a segment folder and/or a class raster."""
    alg.param(
        QgsProcessingParameterFile(
            "MASKS",
            "Entity layers: segment output folder (holds masks.tif)",
            behavior=QgsProcessingParameterFile.Folder,
            optional=True,
        ),
        "the OUTPUT_DIR of Segment entities or Run. Give this, or LABELS + CLASSES, or both.",
    )
    alg.param(
        QgsProcessingParameterRasterLayer("LABELS", "Entity layers: class raster (integer ids)", optional=True),
        "a classified raster whose classes act as entities; needs CLASSES.",
    )
    alg.param(
        QgsProcessingParameterFile(
            "CLASSES", "Entity layers: classes.json of the class raster", extension="json", optional=True
        ),
        'class id -> name, e.g. {"1": "road", "2": "grass"}; needed with LABELS.',
    )


def layer_source_args(alg: OverseecAlgorithm, parameters, context) -> list[str]:
    masks = alg.optional_file(parameters, "MASKS", context)
    labels = alg.raster_file(parameters, "LABELS", context, required=False)
    classes = alg.optional_file(parameters, "CLASSES", context)
    if masks is None and labels is None:
        raise QgsProcessingException("give MASKS (a segment output folder) and/or LABELS + CLASSES")
    if bool(labels) != bool(classes):
        raise QgsProcessingException("LABELS and CLASSES go together (a class raster and its classes.json)")
    args = ["--masks", str(masks)] if masks else []
    if labels:
        args += ["--labels", labels, "--classes", str(classes)]
    return args


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


def temp_file(name: str) -> Path:
    """A new file name in Processing's temporary folder (its own sub-folder each call)."""
    return Path(QgsProcessingUtils.generateTempFilename(name))


def load_run_layers(
    context, folder: Path, prompt: str, roles=loading.ROLE_ORDER, path_label: str = "", title: str = ""
) -> None:
    """Ask Processing to load a run folder's outputs into one group named after the run."""
    group = loading.RunGroup(title or loading.run_title(prompt))
    prov = Provenance.from_run_dir(folder)
    for role in roles:
        found = jobs.first_existing(folder, role)
        if found is None:
            continue
        name = {"costmap": loading.costmap_name(prompt), "path": path_label or "path"}.get(role, role)
        style = {"path": "path", "costmap": "costmap", "mask": "mask"}.get(role, "probability")
        post = loading.StyleLayer(
            style, role, Provenance(**{**prov.__dict__, "stage": role}), group, bands=role in ("mask", "probability")
        )
        loading.load_on_completion(context, str(found), name, role.upper(), post)


def path_figures(geojson: Path) -> tuple[float, float]:
    """Cost and length (m) of the line a path GeoJSON holds (the smoothed one when smoothed)."""
    try:
        props = json.loads(geojson.read_text(encoding="utf-8"))["features"][0]["properties"]
        return float(props["total_cost"]), float(props["length_m"])
    except (OSError, ValueError, LookupError, TypeError) as exc:  # a worker that is not overseec's
        raise QgsProcessingException(f"the worker reported success but {geojson} holds no path ({exc})") from None


# --------------------------------------------------------------------------------------------
# Pipeline
# --------------------------------------------------------------------------------------------


class InterpretAlgorithm(OverseecAlgorithm):
    ID = "interpret"
    DISPLAY = "Interpret prompt"
    HELP = (
        "Turns a mission prompt into entities (name, linear/areal, text prompts), preferences and "
        "a cost program, with the offline interpreter or an OpenAI-compatible LLM. Writes the "
        "interpretation as JSON (input of Segment entities). Same as `overseec interpret`.\n"
        "Needs: PROMPT."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.param(
            QgsProcessingParameterString("PROMPT", "Mission prompt", multiLine=True),
            "what to prefer and avoid, e.g. 'prefer the roads, avoid the water'.",
        )
        add_priors_parameters(self)
        add_llm_parameters(self)
        self.param(
            QgsProcessingParameterFileDestination("OUTPUT", "Interpretation (JSON)", "JSON files (*.json)"),
            "the document `overseec interpret --json` prints.",
        )
        self.addOutput(QgsProcessingOutputString("PROGRAM", "Cost program"))
        self.addOutput(QgsProcessingOutputString("ENTITIES", "Entities (comma-separated)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        prompt = self.parameterAsString(parameters, "PROMPT", context).strip()
        if not prompt:
            raise QgsProcessingException("PROMPT: write a mission prompt")
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        out.parent.mkdir(parents=True, exist_ok=True)
        prompt_file = temp_file("prompt.txt")
        prompt_file.write_text(prompt, encoding="utf-8")
        llm = llm_config(self, parameters, context)
        args = ["--prompt-file", str(prompt_file), "--out", str(out), "--json", *llm_args(llm)]
        args += priors_choice(self, parameters, context).cli()
        doc = self.cli("interpret", args, feedback, env=llm_env(llm))
        for note in list(doc.get("unparsed") or []) + list(doc.get("notes") or []):
            feedback.pushInfo(str(note))
        names = ",".join(e["name"] for e in doc.get("entities", []))
        return {"OUTPUT": str(out), "PROGRAM": doc.get("program", ""), "ENTITIES": names}


class SegmentAlgorithm(OverseecAlgorithm):
    ID = "segment"
    DISPLAY = "Segment entities"
    HELP = (
        "Finds each entity in the image with CLIPSeg on overlapping tiles (and SAM when Refine "
        "is on). Writes probs.tif and masks.tif (one band per entity) into the output folder; "
        "loaded as one layer per entity in a group. Same as `overseec segment`.\n"
        "Needs: INPUT and either INTERPRETATION or ENTITIES."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.param(QgsProcessingParameterRasterLayer("INPUT", "Image"), "a georeferenced image file (GeoTIFF ...).")
        self.param(
            QgsProcessingParameterFile("INTERPRETATION", "Interpretation (JSON)", extension="json", optional=True),
            "the output of Interpret prompt. Give this or ENTITIES.",
        )
        self.param(
            QgsProcessingParameterString("ENTITIES", "Entities (name[:linear|areal], comma-separated)", optional=True),
            "e.g. 'road:linear, grass, water'. Give this or INTERPRETATION.",
        )
        add_segment_parameters(self)
        self.param(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"), "")
        self.addOutput(QgsProcessingOutputRasterLayer("MASKS", "Masks"))
        self.addOutput(QgsProcessingOutputRasterLayer("PROBS", "Probabilities"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        image = self.raster_file(parameters, "INPUT", context)
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        interp_file = self.optional_file(parameters, "INTERPRETATION", context)
        entities = self.optional_str(parameters, "ENTITIES", context)
        if (interp_file is None) == (entities is None):
            raise QgsProcessingException("give either INTERPRETATION (a JSON file) or ENTITIES")
        try:
            if interp_file is not None:
                interp = jobs.entities_from_file(interp_file)
            else:
                interp = jobs.edited_interpretation(None, "", jobs.parse_entities(entities), "")
        except jobs.OverseecError as exc:
            raise QgsProcessingException(str(exc)) from None
        out_dir.mkdir(parents=True, exist_ok=True)
        params = segment_params(self, parameters, context)
        argv, env = jobs.segment_command(
            self.find_worker(), image, out_dir, interp, params, self.optional_str(parameters, "BANDS", context)
        )
        self.run_argv(argv, env, jobs.stage_weights("segment", params), feedback)
        names = ", ".join(e.name for e in interp.entities)
        title = f"overseec segment — {loading.short_text(names)}"
        load_run_layers(context, out_dir, "", roles=("mask", "probability"), title=title)
        return {
            "OUTPUT_DIR": str(out_dir),
            "MASKS": str(jobs.first_existing(out_dir, "mask")),
            "PROBS": str(jobs.first_existing(out_dir, "probability")),
        }


class CostmapAlgorithm(OverseecAlgorithm):
    ID = "costmap"
    DISPLAY = "Build costmap"
    HELP = (
        "Composes a costmap GeoTIFF (float32 in [0, 1], lower = better) from entity layers and a "
        "prompt or cost program; also writes the lethal sidecar and the program text beside it. "
        "Only reads masks: re-prompting takes seconds. A prompt none of whose entities matches a "
        "layer is an error (add ALIASES), never a uniform costmap. Same as `overseec costmap`.\n"
        "Needs: entity layers (MASKS, or LABELS + CLASSES, or both) and exactly one of PROMPT, "
        "PROGRAM_TEXT or PROGRAM."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        add_layer_sources(self)
        self.param(
            QgsProcessingParameterString(
                "PROMPT", "Preferences: mission prompt (interpreted offline)", multiLine=True, optional=True
            ),
            "e.g. 'prefer the roads, avoid the water'. One of PROMPT, PROGRAM_TEXT, PROGRAM.",
        )
        self.param(
            QgsProcessingParameterString(
                "PROGRAM_TEXT", "Preferences: cost program (text)", multiLine=True, optional=True
            ),
            "a program in the cost language, e.g. cost = where(M['road'], 0.1, 0.5).",
        )
        self.param(
            QgsProcessingParameterFile("PROGRAM", "Preferences: cost program (file)", optional=True),
            "e.g. the .program.txt an earlier costmap wrote.",
        )
        self.param(
            QgsProcessingParameterString(
                "ALIASES", "Entity aliases for the prompt (e.g. lake=water, compound=building)", optional=True
            ),
            "the layer a prompt entity stands for when the names differ and the matching misses it.",
            advanced=True,
        )
        add_priors_parameters(self)
        self.param(
            QgsProcessingParameterMultipleLayers(
                "OVERRIDES", OVERRIDES_LABEL, QgsProcessing.TypeVectorPolygon, optional=True
            ),
            OVERRIDES_HELP,
            advanced=True,
        )
        self.param(
            QgsProcessingParameterRasterDestination("OUTPUT", "Costmap"),
            "a GeoTIFF; its lethal sidecar and program are written beside it.",
        )
        self.addOutput(QgsProcessingOutputFile("PROGRAM_FILE", "Cost program file"))
        self.addOutput(QgsProcessingOutputNumber("MEAN_COST", "Mean cost"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        layer_args = layer_source_args(self, parameters, context)
        prompt = self.optional_str(parameters, "PROMPT", context)
        text = self.optional_str(parameters, "PROGRAM_TEXT", context)
        program = self.optional_file(parameters, "PROGRAM", context)
        if sum(x is not None for x in (prompt, text, program)) != 1:
            raise QgsProcessingException("give exactly one of PROMPT, PROGRAM_TEXT or PROGRAM")
        if text is not None:
            program = temp_file("program.txt")
            program.write_text(text + "\n", encoding="utf-8")
        aliases = parse_aliases(self.optional_str(parameters, "ALIASES", context) or "")
        out = Path(self.parameterAsOutputLayer(parameters, "OUTPUT", context))
        if out.suffix.lower() not in (".tif", ".tiff"):
            raise QgsProcessingException(f"OUTPUT: the costmap is a GeoTIFF; name it .tif, not {out.name}")
        out.parent.mkdir(parents=True, exist_ok=True)
        args = ["--out", str(out), "--json", *layer_args]
        args += [f"--prompt={prompt}"] if prompt is not None else ["--program", str(program)]
        args += alias_args(aliases)
        args += priors_choice(self, parameters, context).cli()
        for f in self.polygon_files(parameters, "OVERRIDES", context, feedback):
            args += ["--override", str(f)]
        doc = self.cli("costmap", args, feedback)
        for warning in doc.get("warnings") or []:
            feedback.pushWarning(str(warning))
        name = loading.costmap_name(prompt or "", str(self.optional_file(parameters, "PROGRAM", context) or ""))
        prov = Provenance(run_dir=str(out.parent), prompt=prompt or "", program=doc.get("program", ""), stage="costmap")
        loading.name_destination(context, str(out), name, loading.StyleLayer("costmap", "costmap", prov))
        return {
            "OUTPUT": str(out),
            "PROGRAM_FILE": str(doc.get("program_file", "")),
            "MEAN_COST": doc.get("mean_cost"),
        }


class PlanAlgorithm(OverseecAlgorithm):
    ID = "plan"
    DISPLAY = "Plan path"
    HELP = (
        "Plans the least-cost path on a costmap from START through optional VIAS (a point layer, "
        "in feature order) to GOAL. Writes the path with its cost and length in metres (a "
        "GeoPackage in the costmap's CRS, GeoJSON in WGS 84, or any format QGIS writes), loaded "
        "as 'path — cost C, L m|km'. Same as `overseec plan`.\n"
        "Needs: COSTMAP, START and GOAL."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.param(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"),
            "a costmap GeoTIFF (Build costmap); its lethal sidecar is found beside it.",
        )
        self.param(QgsProcessingParameterPoint("START", "Start"), POINT_HELP)
        self.param(QgsProcessingParameterPoint("GOAL", "Goal"), POINT_HELP)
        self.param(
            QgsProcessingParameterFeatureSource(
                "VIAS", "Via points (in order)", [QgsProcessing.TypeVectorPoint], optional=True
            ),
            "points to pass through, in feature order. Optional.",
        )
        self.param(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=0), MODE_HELP)
        self.param(
            QgsProcessingParameterMultipleLayers(
                "OVERRIDES", OVERRIDES_LABEL, QgsProcessing.TypeVectorPolygon, optional=True
            ),
            OVERRIDES_HELP + " The costmap file is not changed.",
            advanced=True,
        )
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

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        costmap = self.raster_file(parameters, "COSTMAP", context)
        crs = self.parameterAsRasterLayer(parameters, "COSTMAP", context).crs()
        points = [self.point_in(parameters, "START", context, crs)]
        points += self.via_points(parameters, "VIAS", context, crs)
        points.append(self.point_in(parameters, "GOAL", context, crs))
        dest = vector_output(self, parameters, "OUTPUT", context)
        suffix = Path(dest).suffix.lower()
        geojson = Path(dest) if suffix in (".geojson", ".json") else temp_file("path.geojson")
        args = [costmap, *route_args(points), "--crs", jobs.crs_text(crs), "--out", str(geojson), "--json"]
        args += ["--mode", PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)]]
        native = None
        if suffix not in (".geojson", ".json"):
            native = dest if suffix == ".gpkg" else str(temp_file("path.gpkg"))
            args += ["--native-out", native]
        for f in self.polygon_files(parameters, "OVERRIDES", context, feedback):
            args += ["--override", str(f)]
        if self.parameterAsBool(parameters, "SMOOTH", context):
            args += ["--smooth", repr(self.parameterAsDouble(parameters, "SMOOTH_TOLERANCE", context))]
        doc = self.cli("plan", args, feedback, weights={"plan": 1.0})
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        if native is not None and native != dest:
            convert_vector(f"{native}|layername=path", dest, context)
        cost, length = path_figures(geojson)
        prov = Provenance(run_dir=str(Path(costmap).parent), prompt=str(doc.get("prompt") or ""), stage="plan")
        loading.name_destination(
            context, dest, loading.path_name(cost, length), loading.StyleLayer("path", "path", prov)
        )
        return {"OUTPUT": dest, "GEOJSON": str(geojson), "COST": cost, "LENGTH_M": length}


class RunAlgorithm(OverseecAlgorithm):
    ID = "run"
    DISPLAY = "Run full pipeline"
    HELP = (
        "Image + mission prompt -> interpretation, masks, cost program, costmap, a path when START "
        "and GOAL are given, and an evaluation when there is ground truth, into one run folder "
        "with manifest.json. The path, costmap and per-entity masks are loaded into one group "
        "named after the run. With a class raster (LABELS + CLASSES) its classes are the masks "
        "and no model runs. Same as `overseec run`.\n"
        "Needs: INPUT and PROMPT; START and GOAL together for a path; LABELS and CLASSES together."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.param(QgsProcessingParameterRasterLayer("INPUT", "Image"), "a georeferenced image file (GeoTIFF ...).")
        self.param(
            QgsProcessingParameterString("PROMPT", "Mission prompt", multiLine=True),
            "what to prefer and avoid, e.g. 'prefer the roads, avoid the water'.",
        )
        self.param(QgsProcessingParameterPoint("START", "Start", optional=True), POINT_HELP + " Optional, with GOAL.")
        self.param(QgsProcessingParameterPoint("GOAL", "Goal", optional=True), POINT_HELP + " Optional, with START.")
        self.param(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=1), MODE_HELP)
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
        add_priors_parameters(self)
        add_llm_parameters(self)
        add_segment_parameters(self, tiles_and_thresholds=False)
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
            "every output and manifest.json go here.",
        )
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
        given = [parameters.get(n) not in (None, "") for n in ("START", "GOAL")]
        if given[0] != given[1]:
            raise QgsProcessingException("START and GOAL go together (give both for a path, or neither)")
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        params = jobs.replace_params(
            segment_params(self, parameters, context),
            plan_mode=PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)],
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
        )
        self.run_argv(argv, env, jobs.stage_weights("run", params, segments=not labels), feedback)
        results = {"OUTPUT_DIR": str(out_dir), "MANIFEST": str(out_dir / "manifest.json")}
        for key, role in (("COSTMAP", "costmap"), ("MASKS", "mask"), ("PROBS", "probability"), ("PATH", "path")):
            found = jobs.first_existing(out_dir, role)
            results[key] = str(found) if found else None
        label = loading.path_name(*path_figures(Path(results["PATH"]))) if results["PATH"] else ""
        load_run_layers(context, out_dir, prompt, path_label=label)
        return results


# --------------------------------------------------------------------------------------------
# Evaluate
# --------------------------------------------------------------------------------------------


class EvaluateAlgorithm(OverseecAlgorithm):
    ID = "evaluate"
    DISPLAY = "Evaluate path(s)"
    GROUP = "evaluate"
    HELP = (
        "The OVerSeeC metrics: RRPI of paths planned between seeded start-goal pairs, their KDE "
        "centre of mass, the Hausdorff distance to reference paths, IoU of masks per class; plots "
        "and report.md in the output folder. Same as `overseec eval`.\n"
        "Needs, per metric: RRPI: COSTMAP + LABELS + CLASSES + RANKS; Hausdorff: REFERENCE and "
        "PATHS (or COSTMAP to plan them); IoU: MASKS + LABELS + CLASSES."
    )

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
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
        self.param(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=1), MODE_HELP, advanced=True)
        self.param(
            QgsProcessingParameterRasterLayer("MASKS", "Masks (for IoU)", optional=True),
            "a masks raster (one named band per entity) or a class raster.",
            advanced=True,
        )
        self.param(QgsProcessingParameterBoolean("PLOTS", "Write plots", True), "", advanced=True)
        self.param(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"), "")
        self.addOutput(QgsProcessingOutputFile("METRICS", "metrics.json"))
        self.addOutput(QgsProcessingOutputFile("REPORT", "report.md"))
        self.addOutput(QgsProcessingOutputVectorLayer("PATHS_OUT", "Evaluated paths", QgsProcessing.TypeVectorLine))
        self.addOutput(QgsProcessingOutputNumber("MEAN_HAUSDORFF", "Mean Hausdorff (fraction of the diagonal)"))
        self.addOutput(QgsProcessingOutputNumber("MEAN_IOU", "Mean IoU"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        args = ["--out", str(out_dir), "--json"]
        for name, flag in (("COSTMAP", "--costmap"), ("LABELS", "--labels"), ("MASKS", "--masks")):
            path = self.raster_file(parameters, name, context, required=False)
            if path:
                args += [flag, path]
        for name, flag in (("PATHS", "--paths"), ("REFERENCE", "--reference")):
            path = self.vector_file(parameters, name, context, feedback)
            if path:
                args += [flag, path]
        classes = self.optional_file(parameters, "CLASSES", context)
        if classes:
            args += ["--classes", str(classes)]
        ranks = self.optional_str(parameters, "RANKS", context)
        if ranks:
            args += [f"--ranks={ranks}"]
        args += ["--pairs", str(self.parameterAsInt(parameters, "PAIRS", context))]
        args += ["--seed", str(self.parameterAsInt(parameters, "SEED", context))]
        args += ["--mode", PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)]]
        if not self.parameterAsBool(parameters, "PLOTS", context):
            args += ["--no-plots"]
        metrics = self.cli("eval", args, feedback)
        for note in metrics.get("notes", []):
            feedback.pushInfo(str(note))
        paths = out_dir / "paths.geojson"
        if paths.is_file():
            post = loading.StyleLayer("path", "path", Provenance(run_dir=str(out_dir), stage="evaluate"))
            loading.load_on_completion(context, str(paths), "evaluated paths", "PATHS_OUT", post)
        return {
            "OUTPUT_DIR": str(out_dir),
            "METRICS": str(out_dir / "metrics.json"),
            "REPORT": str(out_dir / "report.md"),
            "PATHS_OUT": str(paths) if paths.is_file() else None,
            "MEAN_HAUSDORFF": (metrics.get("hausdorff") or {}).get("mean_normalised"),
            "MEAN_IOU": (metrics.get("iou") or {}).get("mean_iou"),
        }


class CompareAlgorithm(OverseecAlgorithm):
    ID = "compare"
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

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
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
        self.param(QgsProcessingParameterEnum("MODE", "Planner", PLAN_MODES, defaultValue=1), MODE_HELP, advanced=True)
        self.param(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"), "")
        self.addOutput(QgsProcessingOutputRasterLayer("DIFFERENCE", "Cost difference"))
        self.addOutput(QgsProcessingOutputFile("FIGURE", "Side-by-side figure (PNG)"))
        self.addOutput(QgsProcessingOutputFile("TABLE", "Route table (CSV)"))
        self.addOutput(QgsProcessingOutputFile("REPORT", "Report (Markdown)"))
        self.addOutput(QgsProcessingOutputNumber("MAX_HAUSDORFF_M", "Largest Hausdorff distance between routes (m)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        args = layer_source_args(self, parameters, context)
        text = self.parameterAsString(parameters, "PROMPTS", context)
        args += [f"--prompt={line.strip()}" for line in text.splitlines() if line.strip()]
        for p in self.parameterAsFileList(parameters, "PROGRAMS", context):
            if p.strip():  # an unset parameter gives [""]
                args += ["--program", p]
        args += alias_args(parse_aliases(self.optional_str(parameters, "ALIASES", context) or ""))
        args += priors_choice(self, parameters, context).cli()
        # the points in the start's own CRS (the goal reprojected to it)
        crs = self.parameterAsPointCrs(parameters, "START", context)
        raw = parameters.get("START")
        if not crs.isValid() or (isinstance(raw, str) and "[" not in raw):
            crs = QgsCoordinateReferenceSystem()  # bare "x,y": the layers' CRS, as the CLI takes it
        start = self.point_in(parameters, "START", context, crs)
        goal = self.point_in(parameters, "GOAL", context, crs)
        args += point_args("--start", start) + point_args("--goal", goal)
        if crs.isValid():
            args += ["--crs", jobs.crs_text(crs)]
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        args += ["--mode", PLAN_MODES[self.parameterAsEnum(parameters, "MODE", context)], "--out", str(out_dir)]
        doc = self.cli("compare", [*args, "--json"], feedback)
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        for row in doc.get("prompts") or []:
            feedback.pushInfo(
                f"{row['name']} ({row.get('prompt') or row.get('kind')}): "
                f"{row['length_m']:.1f} m, cost {row['cost']:.4g}"
            )
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


# --------------------------------------------------------------------------------------------
# Export
# --------------------------------------------------------------------------------------------


class ExportCostmapAlgorithm(OverseecAlgorithm):
    ID = "exportcostmap"
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
    FORMATS = ("nav2", "costmap2d", "npy")
    NAV2_MODES = ("trinary", "scale")
    SUFFIX = {"nav2": ".yaml", "costmap2d": ".tif", "npy": ".npy"}

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.param(QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"), "a costmap GeoTIFF.")
        self.param(QgsProcessingParameterEnum("FORMAT", "Format", self.FORMATS, defaultValue=0), "")
        self.param(
            QgsProcessingParameterEnum("NAV2_MODE", "Nav2 map mode", self.NAV2_MODES, defaultValue=0),
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
                "Nav2 map (*.yaml);;GeoTIFF (*.tif);;NumPy (*.npy)",
            ),
            "the suffix follows FORMAT.",
        )
        self.addOutput(QgsProcessingOutputString("FILES", "Files written (comma-separated)"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        costmap = self.raster_file(parameters, "COSTMAP", context)
        layer = self.parameterAsRasterLayer(parameters, "COSTMAP", context)
        to = self.FORMATS[self.parameterAsEnum(parameters, "FORMAT", context)]
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        if out.suffix.lower() != self.SUFFIX[to]:
            out = out.with_suffix(self.SUFFIX[to])
        out.parent.mkdir(parents=True, exist_ok=True)
        args = ["costmap", costmap, "--to", to, "--out", str(out), "--json"]
        args += ["--nav2-mode", self.NAV2_MODES[self.parameterAsEnum(parameters, "NAV2_MODE", context)]]
        if parameters.get("LOCAL_ORIGIN") not in (None, ""):
            args += point_args("--local-origin", self.point_in(parameters, "LOCAL_ORIGIN", context, layer.crs()))
        doc = self.cli("export", args, feedback)
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        return {"OUTPUT": str(out), "FILES": ",".join(str(p) for p in (doc.get("outputs") or {}).values())}


class ExportPathAlgorithm(OverseecAlgorithm):
    ID = "exportpath"
    DISPLAY = "Export path (GPX, KML, CSV)"
    GROUP = "export"
    HELP = (
        "Writes a planned path (the GeoJSON Plan path writes, its GEOJSON output) as GPX for "
        "handheld GPS, KML for Google Earth, or CSV (x, y, cumulative ground length, cell cost) in "
        "the costmap's CRS or in the local frame of an exported Nav2 map. Same as "
        "`overseec export path`.\n"
        "Needs: PATH."
    )
    FORMATS = ("gpx", "kml", "csv")
    FRAMES = ("crs", "nav2")

    def initAlgorithm(self, config=None) -> None:  # noqa: N802
        self.param(
            QgsProcessingParameterFile("PATH", "Path (GeoJSON from Plan path)", extension="geojson"),
            "Plan path's GEOJSON output (WGS 84, with the path's properties).",
        )
        self.param(QgsProcessingParameterEnum("FORMAT", "Format", self.FORMATS, defaultValue=0), "")
        self.param(
            QgsProcessingParameterEnum("FRAME", "CSV coordinates", self.FRAMES, defaultValue=0),
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
            QgsProcessingParameterFileDestination("OUTPUT", "Output", "GPX (*.gpx);;KML (*.kml);;CSV (*.csv)"),
            "the suffix follows FORMAT.",
        )

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        to = self.FORMATS[self.parameterAsEnum(parameters, "FORMAT", context)]
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        if out.suffix.lower() != f".{to}":
            out = out.with_suffix(f".{to}")
        out.parent.mkdir(parents=True, exist_ok=True)
        args = ["path", self.parameterAsFile(parameters, "PATH", context), "--to", to, "--out", str(out), "--json"]
        args += ["--frame", self.FRAMES[self.parameterAsEnum(parameters, "FRAME", context)]]
        nav2 = self.optional_file(parameters, "NAV2_YAML", context)
        if nav2:
            args += ["--nav2-yaml", str(nav2)]
        costmap = self.raster_file(parameters, "COSTMAP", context, required=False)
        if costmap:
            args += ["--costmap", costmap]
        doc = self.cli("export", args, feedback)
        for note in doc.get("notes") or []:
            feedback.pushInfo(str(note))
        return {"OUTPUT": str(out)}


def _extract_imagery():
    from .extract_algorithm import ExtractImageryAlgorithm  # in-process: QGIS's renderer

    return ExtractImageryAlgorithm


ALGORITHMS = (
    _extract_imagery(),
    InterpretAlgorithm,
    SegmentAlgorithm,
    CostmapAlgorithm,
    PlanAlgorithm,
    RunAlgorithm,
    EvaluateAlgorithm,
    CompareAlgorithm,
    ExportCostmapAlgorithm,
    ExportPathAlgorithm,
)
