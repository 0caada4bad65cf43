"""The one orchestration of overseec's stages, shared by the CLI, the QGIS task and Processing.

Each stage function takes plain arguments (paths, option dataclasses, a Progress), writes its
outputs into a run directory with a manifest entry, and returns a frozen result. Stages read and
write files on the image's grid, so any one can be re-run alone: re-prompting re-uses the masks.

    image ─ info ─ interpret ─ segment (+ refine) ─ costmap ─ plan ─ evaluate
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Sequence

from .manifest import RunDir
from .progress import Progress
from .raster import RasterInfo, read_info


def run_info(image: str | os.PathLike, bands: Sequence[int] | str | None = None,
             assume_crs: str | None = None) -> RasterInfo:
    """Describe an image: georeferencing, layout and how the pipeline will read it."""
    return read_info(image, bands=bands, assume_crs=assume_crs)


# --- stage: interpret ---


# --- stage: segment ---


# --- stage: costmap ---


# --- stage: plan ---


# --- stage: evaluate ---
def run_evaluate(options: "EvaluateOptions", progress: Progress | None = None,
                 command_args: dict | None = None) -> "EvaluateResult":
    """Evaluate paths and masks into ``options.out_dir``: RRPI over sampled start-goal pairs with
    its KDE centre of mass and fit, Hausdorff distance to reference paths, IoU per class, plots,
    metrics.json and report.md; inputs (hashed), parameters and timing go to the manifest."""
    from dataclasses import asdict

    from .evaluate import check_options, evaluate

    check_options(options)
    run = RunDir(options.out_dir, command="eval", args=command_args)
    for role, path in options.inputs().items():
        run.record_input(f"eval_{role}", path, hash_file=role != "image")  # the image is only drawn
    params = {k: v for k, v in asdict(options).items()
              if not isinstance(v, Path) and k not in ("masks", "labels", "classes", "costmap",
                                                       "reference", "paths", "image")}
    run.update_parameters(evaluate=params)
    with run.stage("evaluate"):
        result = evaluate(options, progress)
    run.set("evaluation", {k: Path(v).name for k, v in result.files.items()})
    run.save()
    return result


# --- full pipeline ---
