"""``overseec:vectorize``: masks (or a class raster) as polygons in a GeoPackage, one layer per
entity (``overseec vectorize``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessingException,
    QgsProcessingOutputNumber,
    QgsProcessingParameterFile,
    QgsProcessingParameterFileDestination,
    QgsProcessingParameterNumber,
    QgsProcessingParameterRasterLayer,
)

from overseec_core import runfiles

from ..layers import Provenance
from . import loading
from .base import OverseecAlgorithm

#: Raster rows the CLI reads at a time unless told otherwise (`overseec vectorize --block-rows`).
BLOCK_ROWS = 512


def with_gpkg_suffix(out: Path) -> Path:
    """``out`` named ``*.gpkg`` (a temporary output or a typed name may carry another suffix)."""
    return out if out.suffix.lower() == ".gpkg" else out.with_suffix(".gpkg")


class VectorizeAlgorithm(OverseecAlgorithm):
    """Vectorize masks: one polygon layer per entity, with area (m²) and mean probability."""

    ID = "vectorize"
    TAGS = ("vectorize", "polygons", "raster to vector", "masks")
    DISPLAY = "Vectorize masks (polygons per entity)"
    HELP = (
        f"Turns a segment folder's masks ({runfiles.REFINED_MASKS}, else {runfiles.MASKS}) or a class "
        "raster into polygons: a GeoPackage with one layer per entity, each polygon with area_m2 "
        "(ground square metres, in any CRS), mean_prob (mean probability over its pixels; 1 for a class "
        "raster) and pixels, in the raster's CRS. Edges follow the pixels exactly unless SIMPLIFY gives "
        "a tolerance in ground metres (geometries stay valid). Loaded as one styled layer per entity. "
        "Same as `overseec vectorize`.\n"
        "Needs: MASKS, or LABELS + CLASSES."
    )
    COMMAND = "vectorize"
    #: MASKS is the positional argument.
    FLAGS = {
        "LABELS": "--labels",
        "CLASSES": "--classes",
        "SIMPLIFY": "--simplify",
        "BLOCK_ROWS": "--block-rows",
        "OUTPUT": "--out",
    }

    def initAlgorithm(self, config=None) -> None:
        """MASKS or LABELS + CLASSES, the simplification, the strip height and the GeoPackage."""
        self.param(
            QgsProcessingParameterFile(
                "MASKS",
                f"Segment output folder (holds {runfiles.MASKS})",
                behavior=QgsProcessingParameterFile.Folder,
                optional=True,
            ),
            "the OUTPUT_DIR of Segment entities or Run. Give this, or LABELS + CLASSES.",
        )
        self.param(
            QgsProcessingParameterRasterLayer("LABELS", "Class raster (integer ids)", optional=True),
            "a classified raster: one layer per class name of CLASSES (background classes left out).",
        )
        self.param(
            QgsProcessingParameterFile("CLASSES", "classes.json of the class raster", extension="json", optional=True),
            'class id -> name, e.g. {"1": "road", "2": "grass"}; needed with LABELS.',
        )
        self.param(
            QgsProcessingParameterNumber(
                "SIMPLIFY",
                "Simplification tolerance (ground metres)",
                QgsProcessingParameterNumber.Double,
                0.0,
                minValue=0.0,
            ),
            "0: the exact pixel edges (areas are the pixel counts).",
        )
        self.param(
            QgsProcessingParameterNumber(
                "BLOCK_ROWS", "Raster rows read at a time", QgsProcessingParameterNumber.Integer, BLOCK_ROWS, minValue=1
            ),
            "bounds the memory; the polygons do not depend on it.",
            advanced=True,
        )
        self.param(QgsProcessingParameterFileDestination("OUTPUT", "Polygons", "GeoPackage (*.gpkg)"), "")
        self.addOutput(QgsProcessingOutputNumber("POLYGONS", "Polygons written"))

    def source_args(self, parameters, context) -> list[str]:
        """``DIR`` or ``--labels FILE --classes FILE``: exactly one source."""
        masks = self.optional_file(parameters, "MASKS", context)
        labels = self.optional_raster_file(parameters, "LABELS", context)
        classes = self.optional_file(parameters, "CLASSES", context)
        if (masks is None) == (labels is None):
            raise QgsProcessingException("give MASKS (a segment output folder) or LABELS + CLASSES, not both")
        if bool(labels) != bool(classes):
            raise QgsProcessingException("LABELS and CLASSES go together (a class raster and its classes.json)")
        return [str(masks)] if masks is not None else self.arg("LABELS", labels) + self.arg("CLASSES", classes)

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec vectorize --json``; the GeoPackage loads as one styled layer per entity."""
        args = self.source_args(parameters, context)
        out = with_gpkg_suffix(Path(self.parameterAsFileOutput(parameters, "OUTPUT", context)))
        out.parent.mkdir(parents=True, exist_ok=True)
        args += self.arg("OUTPUT", out) + ["--json"]
        args += self.arg("SIMPLIFY", repr(self.parameterAsDouble(parameters, "SIMPLIFY", context)))
        args += self.arg("BLOCK_ROWS", self.parameterAsInt(parameters, "BLOCK_ROWS", context))
        doc = self.cli(args, feedback)
        for warning in doc.get("warnings") or []:
            feedback.pushWarning(str(warning))
        for layer in doc.get("layers") or []:
            feedback.pushInfo(f"{layer['name']}: {layer['polygons']} polygon(s), {layer['area_m2']:.6g} m²")
        prov = Provenance.from_run_dir(out.parent, stage="vectorize")
        post = loading.PolygonLayers(prov, loading.RunGroup(f"overseec polygons — {out.stem}"))
        loading.load_on_completion(context, str(out), out.stem, "OUTPUT", post)
        return {"OUTPUT": str(out), "POLYGONS": doc.get("polygons")}
