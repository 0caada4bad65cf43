"""The overseec Processing provider (id ``overseec``): what the Toolbox, the Graphical Modeler
and ``qgis_process.bin run overseec:<algorithm>`` see.

The Toolbox shows one ``overseec`` entry with the groups Pipeline, Evaluate and Export under it.
Raster outputs are GeoTIFF only: the costmap's GeoTIFF tags name its lethal sidecar, which other
formats would lose. One module per algorithm family:

=======================  ===========================  ==========  ===============================
algorithm id (module)    CLI                          group       loads (when asked to)
=======================  ===========================  ==========  ===============================
extractimagery (extract  (in-process, QGIS renders)  Pipeline    the GeoTIFF
_algorithm)
interpret                ``overseec interpret``       Pipeline    (a JSON file)
segment                  ``overseec segment``         Pipeline    masks, probabilities (a group)
vectorize                ``overseec vectorize``       Pipeline    polygons, one layer per entity
costmap                  ``overseec costmap``         Pipeline    'costmap — <prompt>'
plan                     ``overseec plan``            Pipeline    'path — cost C, L m|km'
costmatrix (matrix)      ``overseec plan --matrix``   Pipeline    (a CSV table)
corridor                 ``overseec corridor``        Pipeline    ratio + mask rasters, styled
run                      ``overseec run``             Pipeline    path, costmap, masks (a group)
evaluate                 ``overseec eval``            Evaluate    evaluated paths
compare                  ``overseec compare``         Evaluate    (files, difference raster)
exportcostmap (export)   ``overseec export costmap``  Export      (files)
exportpath (export)      ``overseec export path``     Export      (a file)
=======================  ===========================  ==========  ===============================

All but Extract imagery (which needs QGIS's renderer) run their command through the worker
(:mod:`.base`): the QGIS process has no compiled planner kernel, no torch and no plotting stack;
progress and Cancel work the same for every algorithm; and a result is byte for byte what the CLI
writes. Each declares the CLI flag each parameter feeds (``FLAGS``) and builds its argv from it
(Segment and Run through the dock's worker client, :mod:`overseec_qgis.jobs`). Outputs are
Processing outputs (layers, files, numbers), so the algorithms chain in the Graphical Modeler;
destination outputs take any path Processing offers, the default temporary output included, in
the format that path asks for. Shared parameter sets live in :mod:`.parameters`.
"""

from __future__ import annotations

from qgis.core import QgsProcessingAlgorithm, QgsProcessingProvider
from qgis.PyQt.QtGui import QIcon

from ..layers import icon_path


class OverseecProvider(QgsProcessingProvider):
    """Interpret, segment, vectorize, costmap, plan, run, evaluate, compare and export as Processing
    algorithms, each running the matching ``overseec`` command in the worker process."""

    def id(self) -> str:
        return "overseec"

    def name(self) -> str:
        return "overseec"

    def longName(self) -> str:
        from overseec_core import __version__

        return f"overseec {__version__}"

    def icon(self) -> QIcon:
        return QIcon(str(icon_path()))

    def supportedOutputRasterLayerExtensions(self) -> list[str]:
        return ["tif"]

    def loadAlgorithms(self) -> None:
        for cls in algorithm_classes():
            self.addAlgorithm(cls())


def algorithm_classes() -> tuple[type[QgsProcessingAlgorithm], ...]:
    """The provider's algorithms, in Toolbox order (imported when Processing loads them)."""
    from .compare import CompareAlgorithm
    from .corridor import CorridorAlgorithm
    from .costmap import CostmapAlgorithm
    from .evaluate import EvaluateAlgorithm
    from .export import ExportCostmapAlgorithm, ExportPathAlgorithm
    from .extract_algorithm import ExtractImageryAlgorithm
    from .interpret import InterpretAlgorithm
    from .matrix import CostMatrixAlgorithm
    from .plan import PlanAlgorithm
    from .run import RunAlgorithm
    from .segment import SegmentAlgorithm
    from .vectorize import VectorizeAlgorithm

    return (
        ExtractImageryAlgorithm,
        InterpretAlgorithm,
        SegmentAlgorithm,
        VectorizeAlgorithm,
        CostmapAlgorithm,
        PlanAlgorithm,
        CostMatrixAlgorithm,
        CorridorAlgorithm,
        RunAlgorithm,
        EvaluateAlgorithm,
        CompareAlgorithm,
        ExportCostmapAlgorithm,
        ExportPathAlgorithm,
    )
