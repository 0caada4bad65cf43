"""Default settings of the stages, in one light module (standard library only).

The stages' option dataclasses (``segment.SegmentOptions``, ``refine.RefineOptions``,
``pipeline.PipelineOptions``, ``plan.stage.PlanOptions``), the CLI and the QGIS plugin's
``jobs.Params`` take their defaults from here. The plugin imports this module when it loads,
before the core's dependencies (rasterio, scipy) are known to be importable, so nothing here may
import them.
"""

from __future__ import annotations

from overseec_core import formats

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

# ------------------------------------------------------------------------------------------------
# Choice lists: the one definition, imported by the core modules that check them, the CLI's
# parser (``choices=``) and the plugin's menus (tests/qgis/test_adapter_contract.py checks the
# plugin against the CLI).
# ------------------------------------------------------------------------------------------------

#: Devices ``--device`` names in messages (``cuda:N``: the N-th GPU; ``locate.models.parse_device``).
DEVICE_CHOICES = ("auto", "cpu", "cuda", "cuda:N", "mps")
#: Devices a menu offers (a numbered GPU is typed, not picked).
DEVICES = tuple(d for d in DEVICE_CHOICES if d != "cuda:N")
#: Inference precisions (``--precision``): auto is bf16/fp16 autocast on GPU, fp32 on CPU.
PRECISIONS = ("auto", "fp32", "fp16", "bf16")
#: Planner modes (``--mode``): the optimal search, or coarse-to-fine in a corridor.
PLAN_MODES = ("exact", "fast")
#: Planner steps (``--neighbours``): the 8 neighbours, or 16 with knight moves (the kernel's); the
#: planner's own list (``plan.planner.NEIGHBOURS``). The first is the default.
PLAN_NEIGHBOURS = (8, 16)
#: How `eval` draws start-goal pairs (``--pair-draw``): over passable cells a separation apart
#: (the default), or uniformly over every cell of the image, as the paper draws its pairs.
PAIR_DRAWS = ("passable", "image")
#: Slope models of terrain planning (``plan --dem --slope-model``) and the id the planner kernel
#: takes for each (``_kernel.SLOPE_MODEL_IDS`` holds the same: tests/plan check it); the first
#: is the default.
SLOPE_MODEL_IDS = {"tobler": 1, "vehicle": 2}
SLOPE_MODELS = tuple(SLOPE_MODEL_IDS)
#: Pixels per side of a costmap composition block (a multiple of the writer's 512 tiles):
#: ``costmap --block-size``'s default, the compose stage's memory bound.
COMPOSE_BLOCK = 1024
#: How overlapping segmentation tiles are blended.
BLEND_MODES = ("hann", "mean", "max")
#: Costmap export formats (``export costmap --to``; the table is ``formats.FORMATS``) and Nav2
#: map modes (``--nav2-mode``).
COSTMAP_FORMATS = formats.names("costmap")
NAV2_MODES = ("trinary", "scale")
#: Path export formats (``export path --to``) and the CSV coordinate frames (``--frame``).
PATH_FORMATS = formats.names("path")
PATH_FRAMES = ("crs", "nav2")
#: Kinds of model a folder or hub id holds (``models --kind``).
MODEL_KINDS = ("clipseg", "sam")
