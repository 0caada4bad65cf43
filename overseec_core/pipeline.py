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


# --- full pipeline ---
