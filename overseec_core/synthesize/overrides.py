"""Override polygons: an operator's direct corrections to a costmap, applied after the program.

The paper's GUI lets operators correct a costmap by painting on it. Here the edits are a vector
layer (GeoPackage, GeoJSON, any OGR format, any CRS: reprojected to the costmap's) whose polygon
features carry exactly one of

- ``cost``: a number in [0, 1] on the costmap's scale (0.5 neutral, lower = better);
- ``prefer`` = true/1: the most preferred cost, :data:`PREFER_COST` (0.0, the scale's bottom);
- ``lethal`` = true/1: impassable (lethal sidecar 1, cost 1.0).

A flag that is false/0/empty counts as absent. Rules (README "Correcting a costmap by hand"):

- A cell is covered when its centre lies inside the polygon (``all_touched=False``, rasterio's
  default, the same rule compose uses for polygon layers).
- An override replaces what the program said: a non-lethal override makes a cell the program
  made lethal (1) or keep-out (2) passable at its cost (the point of a correction); a lethal one
  makes any cell lethal (1), keep-out cells included.
- Cells without data (NaN cost) stay without data: an override corrects costs, it does not
  extend the map.
- Overlapping overrides: lethal wins, then the highest cost. The rule is the cautious one and
  does not depend on feature or file order (QGIS may rewrite a layer in another order), so the
  same edits always give the same costmap; to carve a cheaper corridor through an avoided
  override, cut that polygon.

``costmap --override`` applies them block by block while composing (:func:`apply_to_block`);
``plan --override`` applies them to the loaded :class:`~overseec_core.plan.grid.PlanningGrid`
in memory (:func:`apply_to_planning_grid`) and leaves the costmap file untouched. Both give the
same route.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.windows import Window

from overseec_core.errors import InputError
from overseec_core.io.grid import Grid
from overseec_core.io.vectors import read_vector
from overseec_core.synthesize.override_rules import (  # the rules live there (no GIS imports)
    KINDS,
    LETHAL_COST,
    PREFER_COST,  # noqa: F401  (part of this module's API)
    classify,
    geometry_problem,
    parse_cost,  # noqa: F401
    parse_flag,  # noqa: F401
)

#: Burn value standing for "lethal" in an override raster (above every cost, so it wins).
LETHAL_BURN = 2.0
#: Lethal-sidecar flags (compose.KEEP_OUT_FLAG is 2; 1 = lethal or no data).
LETHAL_FLAG, FREE_FLAG = 1, 0
#: Costmap tag recording the overrides baked into it (JSON summary).
TAG_OVERRIDES = "OVERSEEC_OVERRIDES"
#: Most features one override file may hold (a hand-edited layer holds a few dozen).
MAX_FEATURES = 100_000
#: Rows per strip when applying to a loaded grid (bounds the temporary override raster).
STRIP_ROWS = 1024
#: The overlap rule, as summaries state it.
RULE = "lethal wins, then the highest cost; cells by centre (all_touched=False)"


@dataclass(frozen=True)
class Override:
    """One checked override feature: where it came from, what it sets, its polygon (grid CRS)."""

    source: Path
    fid: str
    kind: str  # one of KINDS
    cost: float  # the cost it sets; LETHAL_COST for lethal
    geometry: Any  # shapely Polygon/MultiPolygon in the costmap's CRS

    @property
    def burn(self) -> float:
        """Value burnt into an override raster: the cost, or :data:`LETHAL_BURN`."""
        return LETHAL_BURN if self.kind == "lethal" else self.cost

    @property
    def priority(self) -> tuple[bool, float]:
        """Sort key of the overlap rule: lethal above all, then the higher cost."""
        return (self.kind == "lethal", self.cost)


@dataclass(frozen=True)
class OverrideCounts:
    """Cells an override application touched, by outcome.

    ``covered``: cells with data under some override; ``lethal``: cells made lethal that were
    not; ``cost``: cells given an override cost that differs from what they had (or that were
    blocked); ``unblocked``: of those, cells the program had made lethal or keep-out.
    """

    covered: int = 0
    lethal: int = 0
    cost: int = 0
    unblocked: int = 0

    def __add__(self, other: OverrideCounts) -> OverrideCounts:
        return OverrideCounts(
            self.covered + other.covered,
            self.lethal + other.lethal,
            self.cost + other.cost,
            self.unblocked + other.unblocked,
        )

    def to_json(self) -> dict[str, int]:
        return {"covered": self.covered, "lethal": self.lethal, "cost": self.cost, "unblocked": self.unblocked}


# --------------------------------------------------------------------------------------------
# Reading and checking features
# --------------------------------------------------------------------------------------------


def check_geometry(geom: Any) -> str | None:
    """Why a feature's (shapely) geometry cannot be an override (None when it can: a non-empty
    polygon); the rule is :func:`~.override_rules.geometry_problem`."""
    if geom is None:
        return geometry_problem(None, True)
    return geometry_problem(geom.geom_type, geom.is_empty)


def read_overrides(path: str | os.PathLike, grid: Grid) -> tuple[Override, ...]:
    """Every feature of one override file, checked and in the grid's CRS.

    Raises a one-line :class:`InputError` naming the file and the feature (fid) for a feature
    with none or several of cost/lethal/prefer, a cost outside [0, 1] or a non-polygon geometry.
    """
    p = Path(path)
    checked: list[Override] = []
    for feature in read_vector(p, grid.crs, label="--override", max_features=MAX_FEATURES):
        fid, geom = feature.fid, feature.geometry
        why = check_geometry(geom)
        if why is None:
            try:
                kind, cost = classify(feature.properties)
            except ValueError as exc:
                why = str(exc)
        if why is not None:
            raise InputError(
                f"--override {p}: feature fid {fid} {why}"
                if why.startswith(("has", "is"))
                else f"--override {p}: feature fid {fid}: {why}"
            )
        checked.append(Override(p, fid, kind, cost, geom))
    return tuple(checked)


# --------------------------------------------------------------------------------------------
# A set of overrides on a grid
# --------------------------------------------------------------------------------------------


class OverrideSet:
    """The overrides of one or more files on one grid, rasterised window by window.

    Features are held in priority order (:attr:`Override.priority`, ties in file order) and
    burnt in that order, so the last one burnt into a cell is the one the overlap rule picks.
    An STRtree finds the features a window touches, so memory is bounded by the window.
    """

    def __init__(self, files: Sequence[Path], overrides: Iterable[Override], grid: Grid) -> None:
        import shapely

        self.files = tuple(Path(f) for f in files)
        self.grid = grid
        self.overrides = tuple(sorted(overrides, key=lambda o: o.priority))
        self._geoms = np.array([o.geometry for o in self.overrides], dtype=object)
        self._tree = shapely.STRtree(self._geoms)

    def features(self) -> dict[str, int]:
        """Number of features per kind."""
        return {k: sum(o.kind == k for o in self.overrides) for k in KINDS}

    def burn(self, window: Window) -> np.ndarray:
        """float32 raster of the window: the winning override's cost, :data:`LETHAL_BURN` for
        lethal, NaN where no override covers the cell centre."""
        import shapely
        from rasterio.features import rasterize
        from rasterio.windows import bounds, transform

        shape = (int(window.height), int(window.width))
        out = np.full(shape, np.nan, dtype=np.float32)
        if not len(self._geoms):
            return out
        hits = np.sort(self._tree.query(shapely.box(*bounds(window, self.grid.transform))))
        if not len(hits):
            return out
        return rasterize(
            ((self._geoms[i], self.overrides[i].burn) for i in hits),
            out_shape=shape,
            transform=transform(window, self.grid.transform),
            fill=np.nan,
            all_touched=False,
            dtype="float32",
        )

    def summary(self, counts: OverrideCounts, stage: str) -> dict[str, Any]:
        """What the manifest, the costmap tag and the path's properties record."""
        return {
            "stage": stage,
            "files": [f.name for f in self.files],
            "features": self.features(),
            "cells": counts.to_json(),
            "rule": RULE,
        }


def load_overrides(paths: Sequence[str | os.PathLike], grid: Grid) -> OverrideSet:
    """Read and check every override file onto ``grid`` (a file may repeat: read once)."""
    if grid is None:
        raise InputError("--override needs a georeferenced costmap")
    files: list[Path] = []
    for p in map(Path, paths):
        if all(p.resolve() != f.resolve() for f in files):
            files.append(p)
    overrides = [o for f in files for o in read_overrides(f, grid)]
    return OverrideSet(files, overrides, grid)


# --------------------------------------------------------------------------------------------
# Applying
# --------------------------------------------------------------------------------------------


def apply_to_block(
    cost: np.ndarray, lethal: np.ndarray, burn: np.ndarray
) -> tuple[np.ndarray, np.ndarray, OverrideCounts]:
    """Compose's side: a block's cost (float32, NaN = no data) and lethal flags (uint8: 1 lethal
    or no data, 2 keep-out) with the overrides of :meth:`OverrideSet.burn` applied (new arrays).

    Lethal overrides give cost 1.0 and flag 1; the others their cost and flag 0 (passable even
    where the program said lethal or keep-out). No-data cells are left alone.
    """
    hit = ~np.isnan(burn) & ~np.isnan(cost)
    if not hit.any():
        return cost, lethal, OverrideCounts()
    to_lethal = hit & (burn >= LETHAL_BURN)
    to_cost = hit & ~to_lethal
    blocked = lethal != FREE_FLAG
    counts = OverrideCounts(
        covered=int(hit.sum()),
        lethal=int((to_lethal & (lethal != LETHAL_FLAG)).sum()),
        cost=int((to_cost & (blocked | (cost != burn))).sum()),
        unblocked=int((to_cost & blocked).sum()),
    )
    new_cost, new_lethal = cost.copy(), lethal.copy()
    new_cost[to_lethal], new_lethal[to_lethal] = LETHAL_COST, LETHAL_FLAG
    new_cost[to_cost], new_lethal[to_cost] = burn[to_cost], FREE_FLAG
    return new_cost, new_lethal, counts


def tag_value(overrides: OverrideSet) -> str:
    """The costmap's :data:`TAG_OVERRIDES` value: which edits are baked into it (compact JSON;
    cell counts are in the manifest, known only once composed)."""
    import json

    return json.dumps(
        {
            "stage": "costmap",
            "files": [f.name for f in overrides.files],
            "features": overrides.features(),
            "rule": RULE,
        },
        separators=(",", ":"),
    )


def record_overrides(
    run: Any, overrides: OverrideSet | None, counts: OverrideCounts | None, stage: str, progress: Any = None
) -> dict[str, Any] | None:
    """Record applied overrides in a run's manifest: each file hashed (inputs
    ``<stage>_override_<i>_<name>``) and the summary under ``<stage>_overrides``; tell
    ``progress`` what changed, and warn when no override covers a cell with data. Returns the
    summary (None without overrides)."""
    if overrides is None:
        return None
    counts = counts or OverrideCounts()
    for i, path in enumerate(overrides.files):
        run.record_input(f"{stage}_override_{i + 1}_{path.name}", path)
    summary = overrides.summary(counts, stage)
    run.set(f"{stage}_overrides", summary)
    if progress is not None:
        feats = ", ".join(f"{n} {k}" for k, n in overrides.features().items() if n)
        progress.message(
            f"overrides: {feats or 'no features'}; cells made lethal {counts.lethal}, "
            f"given a cost {counts.cost} (unblocked {counts.unblocked})"
        )
        if not counts.covered:
            progress.message(
                "warning: no override polygon covers the centre of a costmap cell with data (wrong place or CRS?)"
            )
    return summary
