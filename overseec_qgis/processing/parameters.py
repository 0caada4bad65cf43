"""Parameter sets several overseec algorithms share: the parameters, the flags they feed, their readers.

Segmentation options (Segment entities, Run), the interpreter's LLM (Interpret, Run), priors of
unsaid hazards (Interpret, Build costmap, Run, Compare), entity layers (Build costmap, Compare)
and override polygons (Build costmap, Plan path). Each ``add_*`` adds the parameters to an
algorithm; the matching ``*_FLAGS`` mapping goes into that algorithm's ``FLAGS``, from which the
readers here build the argv.
"""

from __future__ import annotations

from qgis.core import (
    QgsProcessing,
    QgsProcessingException,
    QgsProcessingParameterAuthConfig,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterFile,
    QgsProcessingParameterMultipleLayers,
    QgsProcessingParameterNumber,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
)

from overseec_core import defaults, runfiles
from overseec_core.locate.refiners import describe_refiners
from overseec_core.locate.segmenters import describe_segmenters

from .. import jobs, params
from ..settings import load_api_key
from .base import OverseecAlgorithm, enum_parameter
from .cli_options import CliOption

#: Planner modes, in the plugin's order (saved models and ``qgis_process`` calls hold the index);
#: the same set as ``overseec plan --mode``'s choices.
PLAN_MODES = params.PLAN_MODES
#: Devices offered for the models (the CLI also takes ``cuda:N``).
DEVICES = defaults.DEVICES
#: The coarse segmenters, the core registry's order (default first; saved models hold the index).
SEGMENTERS = params.SEGMENTERS
SEGMENTER_HELP = describe_segmenters() + "."

#: The refiners, the core table's order (default first; saved models hold the index).
REFINERS = params.REFINERS
REFINER_HELP = f"with REFINE: {describe_refiners()}. SAM_MODEL names its checkpoint (default: its own)."

MODE_HELP = (
    "fast: coarse-to-fine in a corridor, with a lower bound on the optimum; exact: the optimal 8-connected path."
)
POINT_HELP = "a point in any CRS (Processing reprojects it to the raster's)."
OVERRIDES_LABEL = "Override polygons (fields: cost 0-1, or prefer, or lethal)"
OVERRIDES_HELP = (
    "polygon layers (any CRS) drawn over the costmap: a 'cost' field (0-1) sets the cost inside, "
    "prefer=1 makes it the cheapest, lethal=1 impassable. Optional."
)
PRIORS_HELP = (
    'a JSON object of entity -> prior level in (0.5, 1] or "lethal"/"obstacle" replacing the built-in '
    'priors of unsaid hazards, e.g. {"building": 0.9, "water": "lethal"}. Default: the built-in table.'
)
NO_PRIORS_HELP = "no priors: what the prompt does not mention is neutral ground (0.5). Not with PRIORS."

#: The segmentation options `overseec segment` and `overseec run` share (Segment adds OVERLAP;
#: its mask thresholds go into the entities file, not on the command line).
SEGMENT_FLAGS = {
    "BANDS": "--bands",
    "TILE_SIZE": "--tile-size",
    "REFINE": "--no-refine",
    "DEVICE": "--device",
    "SEGMENTER": "--segmenter",
    "MODEL": "--model",
    "CLIPSEG_MODEL": "--clipseg-model",
    "SAM_MODEL": "--sam-model",
    "REFINER": "--refiner",
}
#: REFINE is on unless ``--no-refine`` is given.
SEGMENT_INVERTED = frozenset({"REFINE"})
PRIORS_FLAGS = {"PRIORS": "--priors", "NO_PRIORS": "--no-priors"}
LAYER_FLAGS = {"MASKS": "--masks", "LABELS": "--labels", "CLASSES": "--classes"}
OVERRIDES_FLAGS = {"OVERRIDES": "--override"}
#: ALIASES ('lake=water, woods=tree') feeds one ``--alias=lake=water`` per alias.
ALIASES_FLAGS = {"ALIASES": "--alias"}
#: NEIGHBOURS (``--neighbours``): the planner's steps, 8 or 16 (Plan path, Run, Cost matrix).
STEPS = CliOption("--neighbours", "Steps")
#: The options of `overseec plan` that price a costmap's cells, for every route kind (Plan path,
#: Cost matrix); parameters, defaults and help generated from the CLI's declarations.
PLANNER = (
    STEPS,
    CliOption("--base-cost-per-m", "Cost per metre travelled"),
    CliOption("--lethal-threshold", "Impassable from this cost on (lethal threshold)"),
)


# -- segmentation --------------------------------------------------------------------------------


def add_segment_parameters(alg: OverseecAlgorithm, tiles_and_thresholds: bool = True) -> None:
    """The segmentation options of Segment (all) and Run (those `overseec run` takes); all
    advanced: the defaults are the CLI's."""
    d = params.Params()
    alg.param(enum_parameter("SEGMENTER", "Segmenter", SEGMENTERS, d.segmenter), SEGMENTER_HELP, advanced=True)
    alg.param(
        QgsProcessingParameterString("BANDS", "Bands to read as R,G,B (e.g. 4,3,2)", optional=True),
        "default: the image's first three bands (or its single band).",
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterNumber(
            "TILE_SIZE", "Tile size (px)", QgsProcessingParameterNumber.Integer, d.tile_size, minValue=32
        ),
        "pixels per tile side fed to the segmenter.",
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
    alg.param(enum_parameter("REFINER", "Refiner", REFINERS, d.refiner), REFINER_HELP, advanced=True)
    alg.param(enum_parameter("DEVICE", "Device", DEVICES, d.device), "", advanced=True)
    alg.param(
        QgsProcessingParameterString("MODEL", "Segmenter model (hub id, folder or file)", optional=True),
        "the SEGMENTER's model; default: that segmenter's own (`overseec models list`). For clipseg, "
        "CLIPSEG_MODEL names it too.",
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterString("CLIPSEG_MODEL", "CLIPSeg model (hub id or folder)", optional=True),
        "default: the CLI's model.",
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterString("SAM_MODEL", "Refiner model (hub id or folder)", optional=True),
        "the REFINER's checkpoint; default: that refiner's own (`overseec models list`).",
        advanced=True,
    )


def segment_params(alg: OverseecAlgorithm, parameters, context) -> params.Params:
    """The segmentation options as the worker client's ``Params`` (defaults for those absent)."""
    d = params.Params()

    def number(name, default, as_type):
        if alg.parameterDefinition(name) is None:
            return default
        return as_type(parameters, name, context)

    segmenter = alg.enum_value(parameters, "SEGMENTER", context)
    model = alg.optional_str(parameters, "MODEL", context) or ""
    clipseg_model = alg.optional_str(parameters, "CLIPSEG_MODEL", context) or ""
    return params.Params(
        segmenter=segmenter,
        # Params keeps CLIPSeg's model apart from the others' (the dock's settings do)
        model=model if segmenter != "clipseg" else "",
        clipseg_model=(model or clipseg_model) if segmenter == "clipseg" else clipseg_model,
        tile_size=alg.parameterAsInt(parameters, "TILE_SIZE", context),
        overlap=number("OVERLAP", d.overlap, alg.parameterAsInt),
        tau_linear=number("TAU_LINEAR", d.tau_linear, alg.parameterAsDouble),
        tau_areal=number("TAU_AREAL", d.tau_areal, alg.parameterAsDouble),
        refine=alg.parameterAsBool(parameters, "REFINE", context),
        device=alg.enum_value(parameters, "DEVICE", context),
        sam_model=alg.optional_str(parameters, "SAM_MODEL", context) or "",
        refiner=alg.enum_value(parameters, "REFINER", context),
    )


# -- the interpreter's LLM -----------------------------------------------------------------------


def add_llm_parameters(alg: OverseecAlgorithm) -> None:
    """LLM_URL, LLM_MODEL and LLM_AUTHCFG (they reach the worker through its environment)."""
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


def llm_config(alg: OverseecAlgorithm, parameters, context) -> params.LlmSettings:
    """The LLM parameters as settings; no endpoint means the offline interpreter."""
    url = alg.optional_str(parameters, "LLM_URL", context)
    if not url:
        return params.LlmSettings()
    authcfg = alg.parameterAsString(parameters, "LLM_AUTHCFG", context)
    return params.LlmSettings(
        endpoint=url, model=alg.optional_str(parameters, "LLM_MODEL", context) or "", api_key=load_api_key(authcfg)
    )


def llm_args(llm: params.LlmSettings) -> list[str]:
    """The interpreter's CLI options: ``--offline`` or none (the LLM goes in :func:`llm_env`)."""
    return jobs.llm_cli(llm)[0]


def llm_env(llm: params.LlmSettings) -> dict[str, str]:
    """The worker's environment with the LLM endpoint, model and key (never its command line)."""
    return jobs.worker_env(jobs.llm_cli(llm)[1])


# -- priors of unsaid hazards --------------------------------------------------------------------


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


def priors_choice(alg: OverseecAlgorithm, parameters, context) -> params.Priors:
    """PRIORS / NO_PRIORS as given; both given reach the command, whose own error says so."""
    path = alg.optional_file(parameters, "PRIORS", context)
    return params.Priors(str(path) if path else "", alg.parameterAsBool(parameters, "NO_PRIORS", context))


def priors_args(alg: OverseecAlgorithm, parameters, context) -> list[str]:
    """``--priors=FILE`` and/or ``--no-priors`` (both when both are given: the command refuses them)."""
    choice = priors_choice(alg, parameters, context)
    return alg.arg("PRIORS", choice.path, joined=True) + alg.arg("NO_PRIORS", choice.off)


# -- entity layers -------------------------------------------------------------------------------


def add_layer_sources(alg: OverseecAlgorithm) -> None:
    """Entity layers of Build costmap and Compare: a segment folder and/or a class raster."""
    alg.param(
        QgsProcessingParameterFile(
            "MASKS",
            f"Entity layers: segment output folder (holds {runfiles.MASKS})",
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
    """``--masks DIR`` and/or ``--labels FILE --classes FILE``; an error when neither is given
    or a class raster comes without its classes (or the other way round)."""
    masks = alg.optional_file(parameters, "MASKS", context)
    labels = alg.optional_raster_file(parameters, "LABELS", context)
    classes = alg.optional_file(parameters, "CLASSES", context)
    if masks is None and labels is None:
        raise QgsProcessingException("give MASKS (a segment output folder) and/or LABELS + CLASSES")
    if bool(labels) != bool(classes):
        raise QgsProcessingException("LABELS and CLASSES go together (a class raster and its classes.json)")
    return alg.arg("MASKS", masks) + alg.arg("LABELS", labels) + alg.arg("CLASSES", classes)


# -- override polygons ---------------------------------------------------------------------------


def add_overrides(alg: OverseecAlgorithm, help: str = OVERRIDES_HELP) -> None:
    """OVERRIDES: polygon layers whose cost, prefer or lethal fields are drawn over the costmap."""
    alg.param(
        QgsProcessingParameterMultipleLayers(
            "OVERRIDES", OVERRIDES_LABEL, QgsProcessing.TypeVectorPolygon, optional=True
        ),
        help,
        advanced=True,
    )


def override_args(alg: OverseecAlgorithm, parameters, context, feedback) -> list[str]:
    """``--override FILE`` per layer of OVERRIDES, in layer order."""
    files = alg.polygon_files(parameters, "OVERRIDES", context, feedback)
    return [a for f in files for a in alg.arg("OVERRIDES", f)]


# -- entity aliases ------------------------------------------------------------------------------


def parse_aliases(text: str) -> tuple[tuple[str, str], ...]:
    """'lake=water, woods=tree' -> (('lake', 'water'), ('woods', 'tree')); a mistake is one
    line naming ALIASES (checked here, before a worker starts)."""
    from overseec_core.interpret.matching import parse_aliases as parse

    try:
        return parse(text)
    except ValueError as exc:
        raise QgsProcessingException(f"ALIASES: {exc}") from None


def aliases_args(alg: OverseecAlgorithm, parameters, context) -> list[str]:
    """``--alias=entity=layer`` per alias of ALIASES; a mistake is an error before a worker starts."""
    aliases = parse_aliases(alg.optional_str(parameters, "ALIASES", context) or "")
    return [a for entity, layer in aliases for a in alg.arg("ALIASES", f"{entity}={layer}", joined=True)]
