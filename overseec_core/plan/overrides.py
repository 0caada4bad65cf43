"""Override polygons on the planning grid: a plan's in-memory edits of a loaded costmap (the
costmap file stays as it is), and the override properties a planned path carries.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from rasterio.windows import Window

from overseec_core.errors import InputError
from overseec_core.plan.grid import PlanningGrid
from overseec_core.synthesize.overrides import (
    LETHAL_BURN,
    STRIP_ROWS,
    TAG_OVERRIDES,
    OverrideCounts,
    OverrideSet,
    load_overrides,
)


def apply_to_planning_grid(grid: PlanningGrid, overrides: OverrideSet) -> tuple[PlanningGrid, OverrideCounts]:
    """The planner's side: ``grid`` with the overrides applied, strip by strip.

    Same outcome as composing with them and loading the result: lethal overrides make cells
    +inf, the others set their cost and clear lethal and keep-out (a ``lethal_threshold`` the
    grid was loaded with applies to the new costs too); NaN (no data) stays. The cost array is
    changed in place — the grid was just loaded, and a copy would double the planner's memory —
    and the returned grid carries the updated keep-out cells.
    """
    if grid.grid is None:
        raise InputError("--override needs a georeferenced costmap")
    cost = grid.cost
    keep_out = grid.keep_out
    total = OverrideCounts()
    for r0 in range(0, grid.height, STRIP_ROWS):
        h = min(STRIP_ROWS, grid.height - r0)
        burn = overrides.burn(Window(0, r0, grid.width, h))
        strip = cost[r0 : r0 + h]
        hit = ~np.isnan(burn) & ~np.isnan(strip)
        if not hit.any():
            continue
        to_lethal = hit & (burn >= LETHAL_BURN)
        to_cost = hit & ~to_lethal
        blocked = np.isposinf(strip)
        total = total + OverrideCounts(
            covered=int(hit.sum()),
            lethal=int((to_lethal & ~blocked).sum()),
            cost=int((to_cost & (blocked | (strip != burn))).sum()),
            unblocked=int((to_cost & blocked).sum()),
        )
        strip[to_lethal] = np.inf
        strip[to_cost] = burn[to_cost]
        if grid.lethal_threshold is not None:
            strip[to_cost & (strip >= grid.lethal_threshold)] = np.inf
        if keep_out is not None:
            keep_out[r0 : r0 + h][hit] = False
    if keep_out is not None and not keep_out.any():
        keep_out = None  # as load_costmap gives for a sidecar without keep-out cells
    return replace(grid, cost=cost, keep_out=keep_out), total


def path_override_properties(tags: Mapping[str, str], plan_summary: dict[str, Any] | None) -> dict[str, Any]:
    """The path's ``overrides_applied`` / ``overrides`` properties: what the costmap had baked
    in (its :data:`TAG_OVERRIDES` tag) and what ``plan --override`` applied."""
    import json

    records = []
    baked = tags.get(TAG_OVERRIDES)
    if baked:
        try:
            records.append(json.loads(baked))
        except ValueError:
            records.append({"stage": "costmap", "tag": baked})
    if plan_summary is not None:
        records.append(plan_summary)
    return {"overrides_applied": bool(records), "overrides": records}


def with_overrides(
    grid: PlanningGrid, files: Sequence[str | os.PathLike]
) -> tuple[PlanningGrid, OverrideSet | None, OverrideCounts | None]:
    """The planning grid with the override polygons of ``files`` applied in memory (the costmap
    file stays as it is), the overrides and their counts; ``grid`` itself and None, None without
    files. A costmap without georeferencing has no grid for polygons: load_overrides refuses it
    with a one-line InputError."""
    if not files:
        return grid, None, None
    overrides = load_overrides(files, grid.grid)  # type: ignore[arg-type]
    applied, counts = apply_to_planning_grid(grid, overrides)
    return applied, overrides, counts
