"""The run folder's file names: the one place that spells them, with their roles and a lookup.

A run folder (``overseec run``, or stages run one by one into the same folder) holds::

    manifest.json          provenance (manifest.MANIFEST_NAME)
    interpretation.json    the interpreter's entities, preferences and cost program
    probs.tif  masks.tif   segmentation (CLIPSeg): probability and mask, one band per entity
    refined_probs.tif  refined_masks.tif  gated.tif
                           SAM refinement; gated = refined probability x refined mask
    costmap.tif  lethal.tif  costmap.program.txt
                           the cost stage (other costmaps: X.tif, X.lethal.tif, X.program.txt;
                           :func:`lethal_sidecar`)
    path.geojson  path_native.gpkg
                           the planned path (map CRS) and its native-CRS copy
    entities.json          the QGIS dock's edited entities, handed to `overseec segment`
    masks.gpkg             the masks as polygons, one layer per entity (`segment --vectors`,
                           `overseec vectorize`)
    paths.gpkg  overrides.gpkg
                           the QGIS map tool's routes (one table per costmap) and the operator's
                           override polygons
    evaluation/            metrics.json, report.md, pairs.csv, paths.geojson, plots
    image.tif              the QGIS dock's extracted imagery (EXTRACTED_IMAGE)

`overseec compare` writes COMPARE_FILES and one COMPARE_CANDIDATE_DIR per prompt or program.

Readers ask for a *role* (``"mask"``, ``"probability"``, ``"costmap"``, ``"path"``) and get the
preferred existing file through :func:`first_existing` (refined masks over coarse ones). Plain
standard library: the QGIS plugin imports it.
"""

from __future__ import annotations

import os
from pathlib import Path

MANIFEST = "manifest.json"
INTERPRETATION = "interpretation.json"
PROBS = "probs.tif"
MASKS = "masks.tif"
REFINED_PROBS = "refined_probs.tif"
REFINED_MASKS = "refined_masks.tif"
GATED = "gated.tif"
MASK_POLYGONS = "masks.gpkg"
COSTMAP = "costmap.tif"
LETHAL = "lethal.tif"
COSTMAP_PROGRAM = "costmap.program.txt"
PATH = "path.geojson"
PATH_NATIVE = "path_native.gpkg"
#: The entities the QGIS dock hands to `overseec segment --entities-json`.
ENTITIES = "entities.json"
#: The QGIS map tool's routes (one table per costmap) and the operator's override polygons.
PATHS_LAYER = "paths.gpkg"
OVERRIDES_LAYER = "overrides.gpkg"
#: `overseec corridor`: the least-cost corridor ratio raster's usual name, and the suffix of its
#: within-PCT mask beside it (``corridor.tif`` -> ``corridor-within.tif``).
CORRIDOR = "corridor.tif"
CORRIDOR_MASK_SUFFIX = "-within.tif"
#: `overseec plan --pairs`: the routes GeoPackage's layer, and `--matrix`'s usual file name.
PAIRS_LAYER = "routes"
COST_MATRIX = "cost_matrix.csv"
#: The lethal sidecar of a costmap not named costmap.tif: ``X.tif`` -> ``X.lethal.tif``.
LETHAL_SUFFIX = ".lethal.tif"
#: Costmap tag carrying the mission prompt it was made from (written by the cost stage, read by
#: the planner, which names every path after it).
TAG_PROMPT = "OVERSEEC_PROMPT"
#: Windows only: the hidden lock file beside the manifest (POSIX locks the folder itself).
MANIFEST_LOCK = ".manifest.lock"
#: The run folder's bookkeeping files: never an output name (compared case-insensitively, as
#: macOS and Windows file systems compare them).
BOOKKEEPING_NAMES = (MANIFEST, MANIFEST_LOCK)

#: The evaluation stage's folder inside a run folder, and what it writes there (key -> name).
EVALUATION_DIR = "evaluation"
EVALUATION_FILES = {
    "metrics": "metrics.json",
    "report": "report.md",
    "pairs_csv": "pairs.csv",
    "paths_geojson": "paths.geojson",
    "rrpi_plot": "rrpi_vs_length.png",
    "overlay_plot": "paths_overlay.png",
    "iou_plot": "iou.png",
}

#: `overseec compare`'s folder: what it writes there (key -> name; the report has the name of
#: evaluate's: each command's folder holds one report.md), and each candidate's subfolder.
COMPARE_FILES = {
    "difference": "difference.tif",
    "figure": "compare.png",
    "csv": "compare.csv",
    "json": "compare.json",
    "report": EVALUATION_FILES["report"],
}
COMPARE_CANDIDATE_DIR = "prompt_{index}"
#: The QGIS dock's extracted imagery: the image its "Extract" writes into a new run folder.
EXTRACTED_IMAGE = "image.tif"

#: (mask, probability) pairs of the segment stage's folder, in preference order.
MASK_FILES = ((REFINED_MASKS, REFINED_PROBS), (MASKS, PROBS))

#: Output files by role, in preference order.
ROLES: dict[str, tuple[str, ...]] = {
    "costmap": (COSTMAP,),
    "mask": (REFINED_MASKS, MASKS),
    "probability": (REFINED_PROBS, PROBS),
    "path": (PATH, EVALUATION_FILES["paths_geojson"]),
}

#: Everything `overseec run` writes into its folder ...
RUN_OUTPUT_NAMES = (
    MANIFEST,
    INTERPRETATION,
    PROBS,
    MASKS,
    REFINED_PROBS,
    REFINED_MASKS,
    GATED,
    COSTMAP,
    LETHAL,
    COSTMAP_PROGRAM,
    PATH,
    PATH_NATIVE,
)
#: ... and into its evaluation/ subfolder (a run scores paths, never segmented masks: no iou.png).
RUN_EVALUATION_NAMES = (MANIFEST,) + tuple(
    EVALUATION_FILES[k] for k in ("metrics", "report", "pairs_csv", "paths_geojson", "rrpi_plot", "overlay_plot")
)


def lethal_sidecar(costmap: str | os.PathLike[str]) -> Path:
    """The lethal sidecar beside ``costmap``: the run folder's ``costmap.tif`` -> ``lethal.tif``;
    any other ``X.tif`` -> ``X.lethal.tif``, so that several costmaps share a folder. The cost
    stage writes it there and the planner looks for it there (after the costmap's own tag)."""
    costmap = Path(costmap)
    if costmap.stem == Path(COSTMAP).stem:
        return costmap.with_name(LETHAL)
    return costmap.with_name(costmap.stem + LETHAL_SUFFIX)


def is_bookkeeping_name(path: str | os.PathLike[str]) -> bool:
    """True when ``path`` names one of the run folder's bookkeeping files (manifest.json ...)."""
    name = Path(path).name.casefold()
    return any(name == n.casefold() for n in BOOKKEEPING_NAMES)


def first_existing(run_dir: str | os.PathLike[str], role: str) -> Path | None:
    """The preferred existing file for ``role`` (a key of :data:`ROLES`) in a run folder, or None."""
    for name in ROLES[role]:
        if (Path(run_dir) / name).is_file():
            return Path(run_dir) / name
    return None
