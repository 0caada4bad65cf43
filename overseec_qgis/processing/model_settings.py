"""The segmenter's settings Segment entities and Run full pipeline add to the shared segmentation
parameters: the processing resolution (GSD -> ``--gsd``) and boxes+sam's box score threshold and
cap (BOX_THRESHOLD -> ``--box-threshold``, MAX_BOXES -> ``--max-boxes``).

All three are optional and advanced: left empty, the command's defaults hold (the image's own
resolution; the detector's threshold, 16 boxes). A GSD that is neither a positive number nor
``auto`` is refused before any worker starts, with the core's one-line message.
"""

from __future__ import annotations

from dataclasses import replace

from qgis.core import QgsProcessingException, QgsProcessingParameterNumber, QgsProcessingParameterString

from overseec_core.errors import InputError
from overseec_core.locate.gsd import parse_gsd

from .. import params
from .base import OverseecAlgorithm

#: Parameter -> the CLI flag it feeds (into the algorithm's FLAGS).
MODEL_SETTINGS_FLAGS = {"GSD": "--gsd", "BOX_THRESHOLD": "--box-threshold", "MAX_BOXES": "--max-boxes"}
GSD_HELP = (
    "ground metres per pixel the segmenter works at: tiles are resampled to it and the masks written on "
    "the image's grid; 'auto': the model's trained resolution where it names one (semantic models), else "
    "the image's own. Empty: the image's own resolution."
)


def add_model_settings(alg: OverseecAlgorithm) -> None:
    """GSD, BOX_THRESHOLD and MAX_BOXES, optional and advanced."""
    gsd = QgsProcessingParameterString("GSD", "Processing resolution (m/px or auto)", optional=True)
    alg.param(gsd, GSD_HELP, advanced=True)
    alg.param(
        QgsProcessingParameterNumber(
            "BOX_THRESHOLD",
            "boxes+sam: box score threshold",
            QgsProcessingParameterNumber.Double,
            None,
            optional=True,
            minValue=0.0,
            maxValue=0.99,
        ),
        "detector score a box needs; default: OWLv2 0.1, Grounding DINO 0.3.",
        advanced=True,
    )
    alg.param(
        QgsProcessingParameterNumber(
            "MAX_BOXES", "boxes+sam: boxes per entity and tile", QgsProcessingParameterNumber.Integer, None, True, 1
        ),
        "boxes kept per entity and tile, best first; default 16.",
        advanced=True,
    )


def with_model_settings(alg: OverseecAlgorithm, parameters, context, p: params.Params) -> params.Params:
    """``p`` with the GSD and box settings the parameters give (absent or empty: the defaults)."""
    gsd = (alg.optional_str(parameters, "GSD", context) or "").strip().replace(",", ".")
    try:
        parse_gsd(gsd)
    except InputError as exc:
        raise QgsProcessingException(f"GSD: {exc}") from None
    given = {name: parameters.get(name) not in (None, "") for name in ("BOX_THRESHOLD", "MAX_BOXES")}
    threshold = alg.parameterAsDouble(parameters, "BOX_THRESHOLD", context) if given["BOX_THRESHOLD"] else 0.0
    boxes = alg.parameterAsInt(parameters, "MAX_BOXES", context) if given["MAX_BOXES"] else 0
    return replace(p, gsd=gsd, box_threshold=threshold, max_boxes=boxes)
