"""The overseec Processing provider (id ``overseec``): what the Toolbox, the Graphical Modeler
and ``qgis_process.bin run overseec:<algorithm>`` see.

The Toolbox shows one ``overseec`` entry with the groups Pipeline, Evaluate and Export under it.
Raster outputs are GeoTIFF only: the costmap's GeoTIFF tags name its lethal sidecar, which other
formats would lose.
"""

from __future__ import annotations

from qgis.core import QgsProcessingProvider
from qgis.PyQt.QtGui import QIcon

from ..layers import icon_path


class OverseecProvider(QgsProcessingProvider):
    """Interpret, segment, costmap, plan, run, evaluate, compare and export as Processing
    algorithms, each running the matching ``overseec`` command in the worker process."""

    def id(self) -> str:  # noqa: A003 -- QGIS API
        return "overseec"

    def name(self) -> str:
        return "overseec"

    def longName(self) -> str:  # noqa: N802
        from overseec_core import __version__

        return f"overseec {__version__}"

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def supportedOutputRasterLayerExtensions(self) -> list[str]:  # noqa: N802
        return ["tif"]

    def loadAlgorithms(self) -> None:  # noqa: N802
        from .algorithms import ALGORITHMS

        for cls in ALGORITHMS:
            self.addAlgorithm(cls())
