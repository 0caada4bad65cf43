"""``overseec:segment``: each entity found in the image by the chosen segmenter (CLIPSeg by default)
and refined by SAM (``overseec segment``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessingException,
    QgsProcessingOutputRasterLayer,
    QgsProcessingParameterFile,
    QgsProcessingParameterFolderDestination,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
)

from overseec_core import runfiles

from .. import jobs
from . import loading
from .base import OverseecAlgorithm
from .model_settings import MODEL_SETTINGS_FLAGS, add_model_settings, with_model_settings
from .parameters import SEGMENT_FLAGS, SEGMENT_INVERTED, add_segment_parameters, segment_params


def entities_input(interp_file: Path | None, entities: str | None):
    """The entities to segment, from an interpretation file or typed (exactly one of them);
    a mistake in them is an error before any worker starts."""
    try:
        if interp_file is not None and entities is None:
            return jobs.entities_from_file(interp_file)
        if entities is not None and interp_file is None:
            return jobs.edited_interpretation(None, "", jobs.parse_entities(entities), "")
    except jobs.OverseecError as exc:
        raise QgsProcessingException(str(exc)) from None
    raise QgsProcessingException("give either INTERPRETATION (a JSON file) or ENTITIES")


class SegmentAlgorithm(OverseecAlgorithm):
    """Segment entities: probabilities and masks (one band per entity) into a folder."""

    ID = "segment"
    TAGS = ("segment", "clipseg", "sam", "masks", "open vocabulary", "segmentation")
    DISPLAY = "Segment entities"
    HELP = (
        "Finds each entity in the image with the SEGMENTER (CLIPSeg by default; boxes+sam, semantic) on "
        "overlapping tiles (and SAM when Refine "
        f"is on). Writes {runfiles.PROBS} and {runfiles.MASKS} (one band per entity) into the output folder; "
        "loaded as one layer per entity in a group. Same as `overseec segment`.\n"
        "Needs: INPUT and either INTERPRETATION or ENTITIES."
    )
    COMMAND = "segment"
    #: The worker client (:func:`overseec_qgis.jobs.segment_command`) builds the argv, as for the
    #: dock; INTERPRETATION / ENTITIES and the mask thresholds reach it as an entities file.
    FLAGS = {**SEGMENT_FLAGS, **MODEL_SETTINGS_FLAGS, "OVERLAP": "--overlap", "OUTPUT_DIR": "--out"}
    INVERTED = SEGMENT_INVERTED

    def initAlgorithm(self, config=None) -> None:
        """INPUT, the entities (from an interpretation or typed), segmentation options, the folder."""
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
        add_model_settings(self)
        self.param(QgsProcessingParameterFolderDestination("OUTPUT_DIR", "Output folder"), "")
        self.addOutput(QgsProcessingOutputRasterLayer("MASKS", "Masks"))
        self.addOutput(QgsProcessingOutputRasterLayer("PROBS", "Probabilities"))

    def processAlgorithm(self, parameters, context, feedback):
        """Check the entities, then run ``overseec segment`` and load masks and probabilities."""
        image = self.raster_file(parameters, "INPUT", context)
        out_dir = Path(self.parameterAsString(parameters, "OUTPUT_DIR", context))
        interp = entities_input(
            self.optional_file(parameters, "INTERPRETATION", context),
            self.optional_str(parameters, "ENTITIES", context),
        )
        out_dir.mkdir(parents=True, exist_ok=True)
        params = with_model_settings(self, parameters, context, segment_params(self, parameters, context))
        argv, env = jobs.segment_command(
            self.find_worker(), image, out_dir, interp, params, self.optional_str(parameters, "BANDS", context)
        )
        self.run_argv(argv, env, jobs.stage_weights("segment", params), feedback)
        names = ", ".join(e.name for e in interp.entities)
        title = f"overseec segment — {loading.short_text(names)}"
        loading.load_run_layers(context, out_dir, "", roles=("mask", "probability"), title=title)
        return {
            "OUTPUT_DIR": str(out_dir),
            "MASKS": str(runfiles.first_existing(out_dir, "mask")),
            "PROBS": str(runfiles.first_existing(out_dir, "probability")),
        }
