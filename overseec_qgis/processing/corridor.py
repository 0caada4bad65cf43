"""``overseec:corridor``: the least-cost corridor between two points (``overseec corridor``).

Two rasters come back on the costmap's grid: the ratio of each cell's best-through-cell route
cost to the optimum (1.0 on the optimal route, nodata where no route passes) and the mask of the
cells within WITHIN % of it. Loaded, the ratio is styled from ``corridor.qml`` with its colour
ramp stretched over 1.0 (green) to 1 + WITHIN % (red), beyond which cells are not drawn; the
mask from ``corridor_mask.qml``.
"""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsMapLayer,
    QgsProcessingContext,
    QgsProcessingException,
    QgsProcessingFeedback,
    QgsProcessingOutputNumber,
    QgsProcessingParameterNumber,
    QgsProcessingParameterPoint,
    QgsProcessingParameterRasterDestination,
    QgsProcessingParameterRasterLayer,
)

from overseec_core import runfiles

from .. import jobs
from ..layers import Provenance
from . import loading
from .base import OverseecAlgorithm
from .parameters import OVERRIDES_FLAGS, OVERRIDES_HELP, POINT_HELP, add_overrides, override_args

#: WITHIN's default in the dialog (the CLI has none: --within is required there).
DEFAULT_WITHIN_PCT = 10.0
TIFF_SUFFIXES = (".tif", ".tiff")


def stretch_corridor_style(layer: QgsMapLayer, within_pct: float) -> bool:
    """Stretch the corridor style's colour ramp (1.0 .. 1.1 in ``corridor.qml``) over 1.0 ..
    1 + ``within_pct`` %; False when the layer is not drawn with a pseudocolour ramp."""
    from qgis.core import QgsColorRampShader, QgsSingleBandPseudoColorRenderer

    renderer = layer.renderer()
    if not isinstance(renderer, QgsSingleBandPseudoColorRenderer) or renderer.shader() is None:
        return False
    ramp = renderer.shader().rasterShaderFunction()
    items = ramp.colorRampItemList()
    if len(items) < 2:
        return False
    lo, hi = items[0].value, items[-1].value
    top = 1.0 + within_pct / 100.0
    stretched = []
    for i, item in enumerate(items):
        value = 1.0 + (item.value - lo) / (hi - lo) * (top - 1.0)
        label = (
            "1.0 optimal" if i == 0 else (f"{top:.4g} (+{within_pct:g} %)" if i == len(items) - 1 else f"{value:.4g}")
        )
        stretched.append(QgsColorRampShader.ColorRampItem(value, item.color, label))
    ramp.setColorRampItemList(stretched)
    ramp.setMinimumValue(1.0)
    ramp.setMaximumValue(top)
    renderer.setClassificationMin(1.0)
    renderer.setClassificationMax(top)
    layer.triggerRepaint()
    return True


class CorridorStyle(loading.StyleLayer):
    """The ratio raster's post-processor: ``corridor.qml``, then its ramp stretched to WITHIN."""

    def __init__(self, within_pct: float, prov: Provenance) -> None:
        super().__init__("corridor", "corridor", prov)
        self.within_pct = within_pct

    def postProcessLayer(
        self, layer: QgsMapLayer, context: QgsProcessingContext, feedback: QgsProcessingFeedback
    ) -> None:
        super().postProcessLayer(layer, context, feedback)
        try:
            stretch_corridor_style(layer, self.within_pct)
        except Exception as exc:  # a style problem must not lose the result layer
            feedback.reportError(f"overseec: could not style {layer.name()}: {exc}", False)


def corridor_name(within_pct: float, optimum: float) -> str:
    """'corridor — within 10 % of cost 412.3'."""
    return f"corridor — within {within_pct:g} % of cost {optimum:.4g}"


class CorridorAlgorithm(OverseecAlgorithm):
    """Least-cost corridor: the ratio and within-% rasters of ``overseec corridor``, styled."""

    ID = "corridor"
    TAGS = ("corridor", "band", "near optimal", "route", "cost distance")
    DISPLAY = "Least-cost corridor"
    HELP = (
        "Every cell gets the cost of the best route from START to GOAL through it, divided by the "
        "optimal route's cost: 1.0 on the optimal route, 1.1 where the best route through the cell "
        "costs 10 % more, nodata where no route passes. Writes that ratio and a mask of the cells "
        "within WITHIN % of the optimum (the alternatives a single route hides), on the costmap's "
        "grid, exact (the planner's own step rule). Same as `overseec corridor`.\n"
        "Needs: COSTMAP, START, GOAL and WITHIN."
    )
    COMMAND = "corridor"
    FLAGS = {
        "START": "--start",
        "GOAL": "--goal",
        "WITHIN": "--within",
        **OVERRIDES_FLAGS,
        "OUTPUT": "--out",
        "MASK": "--mask-out",
    }
    OWN_DEFAULTS = {"WITHIN": "the CLI requires --within; the dialog offers 10 %"}

    def initAlgorithm(self, config=None) -> None:
        """COSTMAP, START, GOAL, WITHIN, overrides, the two rasters."""
        self.param(
            QgsProcessingParameterRasterLayer("COSTMAP", "Costmap"),
            "a costmap GeoTIFF (Build costmap); its lethal sidecar is found beside it.",
        )
        self.param(QgsProcessingParameterPoint("START", "Start"), POINT_HELP)
        self.param(QgsProcessingParameterPoint("GOAL", "Goal"), POINT_HELP)
        self.param(
            QgsProcessingParameterNumber(
                "WITHIN",
                "Within (% over the optimal cost)",
                QgsProcessingParameterNumber.Double,
                DEFAULT_WITHIN_PCT,
                minValue=1e-6,
            ),
            "the mask holds the cells some route at most this many percent dearer than the optimum passes.",
        )
        add_overrides(self, OVERRIDES_HELP + " The costmap file is not changed.")
        self.param(
            QgsProcessingParameterRasterDestination("OUTPUT", "Corridor (cost ratio to the optimum)"),
            f"a GeoTIFF (float32), e.g. {runfiles.CORRIDOR}.",
        )
        self.param(
            QgsProcessingParameterRasterDestination("MASK", "Corridor mask (within %)"),
            "a GeoTIFF (uint8, 1 = within WITHIN %).",
        )
        self.addOutput(QgsProcessingOutputNumber("OPTIMUM", "Optimal route cost"))
        self.addOutput(QgsProcessingOutputNumber("CELLS_WITHIN", "Cells within WITHIN %"))

    def _tiff(self, parameters, name: str, context) -> Path:
        out = Path(self.parameterAsOutputLayer(parameters, name, context))
        if out.suffix.lower() not in TIFF_SUFFIXES:
            raise QgsProcessingException(f"{name}: the corridor rasters are GeoTIFFs; name it .tif, not {out.name}")
        out.parent.mkdir(parents=True, exist_ok=True)
        return out

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec corridor --json``; both rasters load styled, named after the optimum."""
        costmap = self.raster_file(parameters, "COSTMAP", context)
        crs = self.parameterAsRasterLayer(parameters, "COSTMAP", context).crs()
        within = self.parameterAsDouble(parameters, "WITHIN", context)
        if not within > 0:
            raise QgsProcessingException(f"WITHIN must be a percentage > 0, not {within:g}")
        out, mask = self._tiff(parameters, "OUTPUT", context), self._tiff(parameters, "MASK", context)
        args = [costmap, *self.point_arg("START", self.point_in(parameters, "START", context, crs))]
        args += self.point_arg("GOAL", self.point_in(parameters, "GOAL", context, crs))
        args += ["--crs", jobs.crs_text(crs), *self.arg("WITHIN", repr(within))]
        args += [*self.arg("OUTPUT", out), *self.arg("MASK", mask), "--json"]
        args += override_args(self, parameters, context, feedback)
        doc = self.cli(args, feedback, weights={"corridor": 1.0})
        optimum, cells = float(doc["optimum"]), int(doc["cells_within"])
        feedback.pushInfo(f"optimal route cost {optimum:.6g}; {cells} cells within {within:g} % of it")
        prov = Provenance(run_dir=str(Path(costmap).parent), stage="corridor")
        loading.name_destination(context, str(out), corridor_name(within, optimum), CorridorStyle(within, prov))
        loading.name_destination(
            context,
            str(mask),
            f"corridor mask — within {within:g} %",
            loading.StyleLayer("corridor_mask", "corridor", prov),
        )
        return {"OUTPUT": str(out), "MASK": str(mask), "OPTIMUM": optimum, "CELLS_WITHIN": cells}
