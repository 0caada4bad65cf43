"""Default settings of the stages, in one light module (standard library only).

The stages' option dataclasses (``segment.SegmentOptions``, ``refine.RefineOptions``,
``pipeline.PipelineOptions``, ``plan.stage.PlanOptions``), the CLI and the QGIS plugin's
``jobs.Params`` take their defaults from here. The plugin imports this module when it loads,
before the core's dependencies (rasterio, scipy) are known to be importable, so nothing here may
import them.
"""

from __future__ import annotations

#: Segmentation tile size (px) and the default overlap between tiles.
TILE_SIZE = 512


def overlap_for(tile_size: int) -> int:
    """The default overlap (px) of tiles of ``tile_size``: an eighth of a tile."""
    return tile_size // 8


#: Device: ``auto`` picks CUDA, then MPS, then CPU.
DEVICE = "auto"
#: Binarisation threshold of an entity without its own, by geometry.
THRESHOLDS: dict[str, float] = {"linear": 0.4, "areal": 0.8}
#: SAM refinement runs after segmentation unless switched off (``--no-refine``).
REFINE = True
#: Planner mode of batch runs (`overseec run`, `overseec plan`): the exact search.
PLAN_MODE = "exact"
#: Planner mode of interactive planning (the QGIS map tool and the dock's defaults): a click
#: re-plans at once, so the coarse-to-fine search is used there; "exact" stays one choice away.
INTERACTIVE_PLAN_MODE = "fast"
