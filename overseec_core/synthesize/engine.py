"""The block engine: a checked cost program + entity layers -> costmap.tif and its lethal sidecar.

The program is evaluated on each block plus a halo equal to its spatial reach
(:meth:`Program.halo`), so the costmap equals a whole-image evaluation exactly while memory stays
bounded by the block size: no entity layer is ever read at full size.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator, Mapping, Sequence
from contextlib import ExitStack
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np
import rasterio
from rasterio.windows import Window

from overseec_core import defaults, runfiles
from overseec_core.costlang import Program, evaluate_program
from overseec_core.costlang.kernels import Poll, never_cancelled
from overseec_core.errors import CostProgramError, InputError
from overseec_core.io.grid import Grid
from overseec_core.io.write import RasterWriter, check_output_path
from overseec_core.progress import NullProgress, Progress, check_cancelled
from overseec_core.synthesize.layers import LayerSource
from overseec_core.synthesize.overrides import OverrideCounts, OverrideSet, apply_to_block
from overseec_core.synthesize.terrain import TerrainSource

#: Pixels per side of a composition block (``defaults.COMPOSE_BLOCK``).
DEFAULT_BLOCK = defaults.COMPOSE_BLOCK
#: Largest halo (pixels on each side) a program may need on a given grid.
MAX_HALO_PX = 2048
#: Most pixels one extended window (block + halo) may hold when blocks grow to amortise a halo
#: wider than the block: the window of a default block with the largest halo, the most
#: composition ever reads at once anyway.
MAX_WINDOW_PX = (DEFAULT_BLOCK + 2 * MAX_HALO_PX) ** 2
#: Above this ratio of pixels read (blocks with their halos) to pixels written, compose says so
#: before it starts, since the time grows with it.
HALO_NOTICE_RATIO = 4.0
#: GDAL block cache while composing (bytes). GDAL's default, 5% of RAM, lets the cache of the
#: inputs and of the two outputs grow with the image; this keeps composition's memory bounded.
GDAL_CACHE_BYTES = 256 * 2**20
#: Value of keep-out cells in the lethal sidecar (1 = lethal or no data): zones a rule forbids (a
#: distance rule, a never-cross rule, an obstacle), impassable wherever a route exists without
#: them (see plan.grid).
KEEP_OUT_FLAG = 2
#: Tags on the costmap that name its sidecars (file names, relative to the costmap).
TAG_PROGRAM = "OVERSEEC_PROGRAM_FILE"
TAG_LETHAL = "OVERSEEC_LETHAL_FILE"
# --------------------------------------------------------------------------------------------
# Block-wise composition
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ComposeStats:
    """What a composition produced: where, on what, and a summary of the costmap."""

    cost_path: Path
    lethal_path: Path
    halo: tuple[int, int]
    block_size: int
    blocks: int
    valid_pixels: int
    lethal_pixels: int
    mean_cost: float | None
    seconds: float
    keep_out_pixels: int = 0
    #: Cells the override polygons changed (overrides.OverrideCounts), None without overrides.
    overrides: OverrideCounts | None = None
    #: Cells the DEM left without elevation (nodata in the costmap); 0 without terrain.
    terrain_missing_pixels: int = 0


def blocks(grid: Grid, block_size: int, halo: tuple[int, int]) -> Iterator[tuple[Window, Window]]:
    """(core, extended) windows covering the grid; extended = core + halo, clipped to the grid."""
    hr, hc = halo
    for r0 in range(0, grid.height, block_size):
        r1 = min(r0 + block_size, grid.height)
        for c0 in range(0, grid.width, block_size):
            c1 = min(c0 + block_size, grid.width)
            er0, er1 = max(r0 - hr, 0), min(r1 + hr, grid.height)
            ec0, ec1 = max(c0 - hc, 0), min(c1 + hc, grid.width)
            yield (Window(c0, r0, c1 - c0, r1 - r0), Window(ec0, er0, ec1 - ec0, er1 - er0))


def check_entities(program: Program, source_names: Sequence[str]) -> None:
    """Every entity the program reads must have a layer."""
    missing = [e for e in program.entities if e not in source_names]
    if missing:
        raise InputError(
            f"the program uses {', '.join(repr(m) for m in missing)} but the layers "
            f"have only {', '.join(source_names) or 'none'}; segment those entities or "
            "add them with --vector/--labels"
        )


def compute_halo(program: Program, grid: Grid) -> tuple[int, int]:
    """The program's halo on this grid, refused when it exceeds :data:`MAX_HALO_PX`."""
    px, py = grid.pixel_size_m()
    halo = program.halo((px, py))
    if max(halo) > MAX_HALO_PX:
        widest = max(program.statements, key=lambda s: s.value.reach[0])
        raise CostProgramError(
            f"the program looks {program.reach_m:g} m around each pixel, {max(halo)} pixels at "
            f"{min(px, py):.3g} m per pixel; at most {MAX_HALO_PX} pixels are allowed, use smaller radii",
            widest.line,
            widest.col,
        )
    return halo


def window_pixels(block_size: int, halo: tuple[int, int], grid: Grid) -> int:
    """Pixels of the largest extended window (block + halo on each side, clipped to the grid)."""
    hr, hc = halo
    return min(block_size + 2 * hr, grid.height) * min(block_size + 2 * hc, grid.width)


def pixels_read(block_size: int, halo: tuple[int, int], grid: Grid) -> int:
    """Pixels read and evaluated over all blocks of the grid (halos counted with each block)."""
    return sum(int(ext.width) * int(ext.height) for _, ext in blocks(grid, block_size, halo))


def grown_block_size(block_size: int, halo: tuple[int, int], grid: Grid) -> int:
    """The block size to compose with: ``block_size``, grown in whole multiples of itself while the
    halo is more than half a block wide, as long as a window stays within :data:`MAX_WINDOW_PX`
    (or the requested block's own window, when that is larger).

    Why: every block is evaluated on its window, so a halo of 2000 pixels around 1024-pixel
    blocks reads each pixel about 25 times; blocks at least twice the halo read each at most about
    4 times. The result is the same whatever the block size (block-wise evaluation is exact), and
    memory stays bounded by the window budget.
    """
    budget = max(MAX_WINDOW_PX, window_pixels(block_size, halo, grid))
    size = block_size
    while (
        size < 2 * max(halo)
        and size < max(grid.height, grid.width)
        and window_pixels(size + block_size, halo, grid) <= budget
    ):
        size += block_size
    return size


def evaluate_block(
    program: Program,
    source: LayerSource,
    core: Window,
    ext: Window,
    sampling: tuple[float, float],
    poll: Poll = never_cancelled,
    terrain: TerrainSource | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Cost (float32, NaN where no data) and lethal (uint8: 1 lethal or no data, 2 keep-out)
    for one core window. ``poll`` is the evaluator's cancellation check (raises to stop).
    ``terrain`` serves the terrain fields the program reads (slope, roughness); cells without
    elevation are no data, like cells without masks."""
    block = source.read(program.entities, ext)
    shape = (int(ext.height), int(ext.width))
    r0, c0 = int(core.row_off - ext.row_off), int(core.col_off - ext.col_off)
    sl = (slice(r0, r0 + int(core.height)), slice(c0, c0 + int(core.width)))
    fields = None
    if program.terrain and terrain is not None:
        t_block = terrain.read(program.terrain, ext)
        fields = t_block.fields
        block.valid &= t_block.valid
        terrain.missing_pixels += int((~t_block.valid[sl]).sum())
    result = evaluate_program(
        program, block.masks, block.probs, sampling=sampling, shape=shape, poll=poll, terrain=fields
    )
    valid = block.valid[sl]
    cost = result.cost[sl].astype(np.float32)
    cost[~valid] = np.nan
    lethal = (result.lethal[sl] | ~valid).astype(np.uint8)
    lethal[(lethal == 0) & result.keep_out[sl]] = KEEP_OUT_FLAG
    return cost, lethal


def compose_costmap(
    program: Program,
    source: LayerSource,
    out: str | os.PathLike,
    lethal_out: str | os.PathLike | None = None,
    *,
    block_size: int = DEFAULT_BLOCK,
    tags: Mapping[str, str] | None = None,
    progress: Progress | None = None,
    overrides: OverrideSet | None = None,
    terrain: TerrainSource | None = None,
) -> ComposeStats:
    """Evaluate ``program`` over ``source`` block by block into ``out`` (+ the lethal sidecar).

    Both files are written atomically on the source's exact grid: ``out`` float32 'cost' in
    [0, 1], NaN where the layers have no data; ``lethal_out`` (default from :func:`output_paths`)
    uint8, 1 where the program says lethal or there is no data. Blocks grow when the program's
    halo is wide (:func:`grown_block_size`), and ``progress`` hears up front when the blocks will
    read many times the image's pixels. A cancel is honoured between blocks and inside the
    program's operations (``progress.cancelled()`` is polled throughout). ``overrides`` (operator
    polygons, :mod:`overseec_core.synthesize.overrides`) are applied to each block after the program.
    ``terrain`` (the DEM, :mod:`overseec_core.synthesize.terrain`) serves ``slope`` and
    ``roughness`` to programs that read them; cells it leaves without elevation are no data.
    """
    progress = progress or NullProgress()
    if block_size < 16:
        raise InputError(f"block size {block_size} is too small (at least 16 pixels)")
    t0 = time.perf_counter()
    out = Path(out)
    lethal_out = Path(lethal_out) if lethal_out is not None else output_paths(out)[1]
    if out.resolve() == lethal_out.resolve():
        raise InputError(f"the costmap and the lethal sidecar would both be {out}")
    check_entities(program, source.names)
    grid = source.grid
    halo = compute_halo(program, grid)
    block_size = grown_block_size(block_size, halo, grid)
    px, py = grid.pixel_size_m()
    sampling = (py, px)
    poll = partial(check_cancelled, progress)
    all_tags = {TAG_LETHAL: lethal_out.name, **(tags or {})}
    windows = list(blocks(grid, block_size, halo))
    valid_n = lethal_n = keep_out_n = 0
    override_n = OverrideCounts()  # reported only when there are overrides
    cost_sum = 0.0
    ratio = pixels_read(block_size, halo, grid) / max(grid.width * grid.height, 1)
    if ratio > HALO_NOTICE_RATIO:
        progress.message(
            f"the program looks {program.reach_m:g} m ({max(halo)} pixels) around each "
            f"pixel: {len(windows)} block(s) of {block_size} pixels read {ratio:.1f}x "
            "the image's pixels; the time grows with it"
        )
    missing_before = terrain.missing_pixels if terrain is not None else 0
    progress.begin("costmap", len(windows), unit="block")
    try:
        with rasterio.Env(GDAL_CACHEMAX=GDAL_CACHE_BYTES), ExitStack() as stack:
            cost_w = stack.enter_context(
                RasterWriter(
                    out,
                    grid,
                    1,
                    "float32",
                    nodata=float("nan"),
                    descriptions=["cost"],
                    tags=all_tags,
                    inputs=source.inputs,
                )
            )
            lethal_w = stack.enter_context(
                RasterWriter(
                    lethal_out,
                    grid,
                    1,
                    "uint8",
                    descriptions=["lethal"],
                    tags={"OVERSEEC_COSTMAP_FILE": out.name},
                    inputs=source.inputs,
                )
            )
            for core, ext in windows:
                check_cancelled(progress)
                cost, lethal = evaluate_block(program, source, core, ext, sampling, poll, terrain)
                if overrides is not None:
                    cost, lethal, changed = apply_to_block(cost, lethal, overrides.burn(core))
                    override_n += changed
                ok = ~np.isnan(cost)
                valid_n += int(ok.sum())
                lethal_n += int(((lethal == 1) & ok).sum())
                keep_out_n += int((lethal == KEEP_OUT_FLAG).sum())
                cost_sum += float(cost[ok].sum(dtype=np.float64))
                cost_w.write(cost, int(core.row_off), int(core.col_off))
                lethal_w.write(lethal, int(core.row_off), int(core.col_off))
                progress.advance(1)
    finally:
        progress.end()
    return ComposeStats(
        cost_path=out,
        lethal_path=lethal_out,
        halo=halo,
        block_size=block_size,
        blocks=len(windows),
        valid_pixels=valid_n,
        lethal_pixels=lethal_n,
        mean_cost=cost_sum / valid_n if valid_n else None,
        seconds=time.perf_counter() - t0,
        keep_out_pixels=keep_out_n,
        overrides=override_n if overrides is not None else None,
        terrain_missing_pixels=terrain.missing_pixels - missing_before if terrain is not None else 0,
    )


def compose_array(
    program: Program,
    source: LayerSource,
    block_size: int | None = None,
    poll: Poll = never_cancelled,
    terrain: TerrainSource | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The whole costmap in memory (small grids, tests): block-wise when ``block_size`` is given
    (used as given: this is what tests block-wise exactness with). ``poll``: a cancellation check;
    ``terrain``: the DEM's fields for programs that read slope or roughness."""
    grid = source.grid
    px, py = grid.pixel_size_m()
    check_entities(program, source.names)
    halo = compute_halo(program, grid)
    size = block_size or max(grid.width, grid.height)
    cost = np.empty(grid.shape, np.float32)
    lethal = np.empty(grid.shape, np.uint8)
    for core, ext in blocks(grid, size, halo):
        c, lt = evaluate_block(program, source, core, ext, (py, px), poll, terrain)
        sl = core.toslices()
        cost[sl], lethal[sl] = c, lt
    return cost, lethal


def output_paths(out: str | os.PathLike) -> tuple[Path, Path, Path]:
    """(costmap, lethal sidecar, program text) beside each other.

    ``costmap.tif`` -> ``lethal.tif`` and ``costmap.program.txt``; any other name ``X.tif`` ->
    ``X.lethal.tif`` and ``X.program.txt``, so several costmaps can share a folder. The costmap's
    tags name both sidecars.
    """
    out = Path(out)
    if out.suffix.lower() not in (".tif", ".tiff"):
        raise InputError(f"--out {out}: the costmap is a GeoTIFF; give a .tif path")
    return out, runfiles.lethal_sidecar(out), out.with_name(f"{out.stem}.program.txt")


def check_outputs(paths: Sequence[Path], inputs: Sequence[Path]) -> None:
    """Refuse outputs that would overwrite an input (before any work is done)."""
    for p in paths:
        check_output_path(p, inputs)
