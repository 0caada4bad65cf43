"""``overseec:extractimagery``: any raster layer (XYZ, WMS/WMTS, VRT, file) to a GeoTIFF at a GSD.

The Processing face of :mod:`overseec_qgis.extract`: the same plan (projected CRS in metres,
extent snapped to the GSD grid, pixel limit) and the same tiled rendering, in-process (no worker:
it needs QGIS's renderer and nothing of the core's ML stack). The layer is cloned in
``prepareAlgorithm`` (the main thread in the GUI) and the clone rendered in ``processAlgorithm``
(Processing's background thread), as QGIS's own "Convert map to raster" does.
"""

from __future__ import annotations

import os
from pathlib import Path

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsProcessingAlgorithm,
    QgsProcessingException,
    QgsProcessingParameterCrs,
    QgsProcessingParameterDefinition,
    QgsProcessingParameterExtent,
    QgsProcessingParameterNumber,
    QgsProcessingParameterRasterDestination,
    QgsProcessingParameterRasterLayer,
)
from qgis.PyQt.QtGui import QIcon

from overseec_core.errors import OverseecError

from ..extract import extract_layer
from ..extract_plan import DEFAULT_MAX_PIXELS, ExtractPlan, plan_extraction
from ..layers import icon_path

HELP = (
    "Renders any raster layer QGIS can draw -- an XYZ basemap, WMS/WMTS, a VRT mosaic or a file -- "
    "over EXTENT at GSD metres per pixel into a georeferenced RGB GeoTIFF that the other overseec "
    "algorithms (Segment entities, Run) take as their image.\n\n"
    "The output CRS is TARGET_CRS when given (projected, in metres), else the layer's or the "
    "project's CRS when it is projected in metres and true to scale at the extent (not Web "
    "Mercator), else the WGS 84 / UTM zone of the extent's centre. The extent is widened to whole "
    "GSD steps. The image is drawn as the layer looks on the map (its style), tile by tile; areas "
    "the layer does not cover are masked. Extents above the size limit are refused before anything "
    "is fetched, with the GSD that would fit; openstreetmap.org tiles are refused beyond 5000 tiles "
    "(its tile usage policy).\n\n"
    "Needs: INPUT, EXTENT and GSD."
)


class ExtractImageryAlgorithm(QgsProcessingAlgorithm):
    """Extract imagery from a raster layer at a ground resolution."""

    def __init__(self) -> None:
        super().__init__()
        self._plan: ExtractPlan | None = None
        self._layer = None

    def name(self) -> str:
        return "extractimagery"

    def displayName(self) -> str:
        return "Extract imagery from a raster layer"

    def group(self) -> str:
        return "Pipeline"

    def groupId(self) -> str:
        return "pipeline"

    def tags(self) -> list[str]:
        return ["xyz", "wms", "wmts", "basemap", "vrt", "gsd", "resolution", "imagery", "export", "geotiff"]

    def shortHelpString(self) -> str:
        return HELP

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def createInstance(self):
        return type(self)()

    def _add(self, param: QgsProcessingParameterDefinition, help_text: str, advanced: bool = False) -> None:
        param.setHelp(help_text)
        if advanced:
            param.setFlags(param.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(param)

    def initAlgorithm(self, config=None) -> None:
        self._add(
            QgsProcessingParameterRasterLayer("INPUT", "Raster layer (XYZ, WMS/WMTS, VRT or file)"),
            "the layer to render; drawn with its current style.",
        )
        self._add(
            QgsProcessingParameterExtent("EXTENT", "Extent"),
            "the area to extract (draw it on the canvas, or use the canvas or a layer extent).",
        )
        self._add(
            QgsProcessingParameterNumber(
                "GSD", "Ground resolution (m per pixel)", QgsProcessingParameterNumber.Double, 0.5, minValue=0.01
            ),
            "ground metres per output pixel.",
        )
        self._add(
            QgsProcessingParameterCrs("TARGET_CRS", "Output CRS (projected, metres)", optional=True),
            "empty: the layer's or project's CRS when true to scale there, else the UTM zone of the extent.",
            advanced=True,
        )
        self._add(
            QgsProcessingParameterNumber(
                "MAX_MEGAPIXELS",
                "Size limit (megapixels)",
                QgsProcessingParameterNumber.Double,
                DEFAULT_MAX_PIXELS / 1e6,
                minValue=0.001,
            ),
            "larger extractions are refused before anything is fetched.",
            advanced=True,
        )
        self._add(
            QgsProcessingParameterRasterDestination("OUTPUT", "Extracted imagery"),
            "an RGB GeoTIFF (tiled, compressed, with overviews and a mask of uncovered areas).",
        )

    def prepareAlgorithm(self, parameters, context, feedback) -> bool:
        layer = self.parameterAsRasterLayer(parameters, "INPUT", context)
        if layer is None:
            raise QgsProcessingException("INPUT: choose a raster layer")
        extent = self.parameterAsExtent(parameters, "EXTENT", context)
        extent_crs = self.parameterAsExtentCrs(parameters, "EXTENT", context)
        if not extent_crs.isValid():  # "xmin,xmax,ymin,ymax" with no [CRS] and no project CRS
            extent_crs = layer.crs()
        target = self.parameterAsCrs(parameters, "TARGET_CRS", context)
        project = context.project()
        try:
            self._plan = plan_extraction(
                layer,
                extent,
                extent_crs,
                self.parameterAsDouble(parameters, "GSD", context),
                max_pixels=int(self.parameterAsDouble(parameters, "MAX_MEGAPIXELS", context) * 1e6),
                target_crs=target if target.isValid() else None,
                project_crs=project.crs() if project is not None else QgsCoordinateReferenceSystem(),
            )
        except OverseecError as exc:
            raise QgsProcessingException(str(exc)) from None
        self._layer = layer.clone()  # rendered on Processing's thread; the project's layer stays the GUI's
        return True

    def processAlgorithm(self, parameters, context, feedback):
        plan = self._plan
        if plan is None or self._layer is None:
            raise QgsProcessingException("the extraction was not prepared")
        out = self.parameterAsOutputLayer(parameters, "OUTPUT", context)
        if Path(out).suffix.lower() not in (".tif", ".tiff"):
            raise QgsProcessingException(f"OUTPUT {out}: extracted imagery is written as a GeoTIFF (.tif)")
        feedback.pushInfo(f"extracting {plan.describe()}")
        try:
            path = extract_layer(self._layer, plan, out, feedback)
        except OverseecError as exc:
            raise QgsProcessingException(str(exc)) from None
        return {"OUTPUT": os.fspath(path)}
