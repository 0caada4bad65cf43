"""Fast mode's coarse level: block size, block costs and the block-hop lower bound's hops.

Fast mode plans on a block-averaged copy of the costmap (k x k blocks), then runs the exact search
restricted to a corridor of blocks around that coarse path (:class:`~overseec_core.plan.planner.Planner`).
Its cost comes with a guaranteed lower bound on the optimum, from a Dijkstra over block hops
(:func:`hop_offsets` says why it is one). This module holds the pure array maths of that level.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from scipy import ndimage

from overseec_core.plan.paths import finite_range, octile_m

#: Coarse grids aim at this many blocks along the longer side.
COARSE_TARGET = 512


def auto_coarse_factor(shape: tuple[int, int]) -> int:
    """Block size so the coarse grid has about COARSE_TARGET blocks along its longer side."""
    return max(4, math.ceil(max(shape) / COARSE_TARGET))


def hop_offsets(hops: int, k: int, dx: float, dy: float) -> tuple[np.ndarray, np.ndarray]:
    """Block offsets at Chebyshev distance ``hops`` and the least ground length of such a hop.

    Why the hop search is a lower bound: follow any path and mark a checkpoint each time it
    first reaches a block at Chebyshev distance R = ``hops`` from the previous checkpoint's
    block. Between checkpoints the path stays within distance R of that block, so every step
    costs at least mu (the least cost + base over the (2R+1)^2 blocks around it) per metre, and
    it must travel at least the ground distance between the nearest cells of the two blocks:
    (|a| - 1) k + 1 pixels along an axis where the blocks are |a| > 0 apart (octile metric,
    which 8-connected paths cannot beat). After the last checkpoint the path ends within R - 1
    blocks of it. So the cheapest checkpoint chain, a Dijkstra over these hops ending within
    R - 1 blocks of the goal's block, never exceeds the cost of any path.
    """
    offs, lens = [], []
    for a in range(-hops, hops + 1):
        for b in range(-hops, hops + 1):
            if max(abs(a), abs(b)) != hops:
                continue
            ny = 0 if a == 0 else (abs(a) - 1) * k + 1
            nx = 0 if b == 0 else (abs(b) - 1) * k + 1
            offs.append((a, b))
            lens.append(octile_m(ny, nx, dx, dy))
    return np.array(offs, dtype=np.int64), np.array(lens, dtype=np.float64)


def block_costs(cost: np.ndarray, k: int, threads: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The coarse costmap of ``k`` x ``k`` blocks and each block's cheapest cell.

    Returns (coarse cost (Hc, Wc) float32, +inf for a block without a passable cell; cheapest
    cell (Hc, Wc) float64, +inf likewise). Works in strips of block rows, so the temporary
    memory stays bounded whatever the costmap's size; the strips are shared among ``threads``
    threads (default: one per core, at most 4; numpy's partition and reductions release the
    GIL), each with its own strip buffer.
    """
    h, w = cost.shape
    top = np.float32(max(1.0, finite_range(cost)[1]))
    hc, wc = -(-h // k), -(-w // k)
    coarse_cost = np.empty((hc, wc), dtype=np.float32)
    mins = np.empty((hc, wc), dtype=np.float64)
    band = max(1, 256 // k)  # block rows per strip: bounds the temporary memory
    starts = list(range(0, hc, band))
    n = max(1, min(threads or min(4, os.cpu_count() or 1), len(starts)))

    def strips(first: int) -> None:
        padded = np.empty((band * k, wc * k), dtype=np.float32)
        for b0 in starts[first::n]:
            nb = min(band, hc - b0)
            rows = cost[b0 * k : min(h, (b0 + nb) * k)]
            part = padded[: nb * k]
            part[: rows.shape[0], :w] = rows
            part[rows.shape[0] :] = np.inf  # the padding past the costmap's last row and column
            part[:, w:] = np.inf
            np.nan_to_num(part, copy=False, nan=np.inf, posinf=np.inf)
            cells = part.reshape(nb, k, wc, k).transpose(0, 2, 1, 3).reshape(nb, wc, k * k)
            cheapest = np.partition(cells, k - 1, axis=-1)[..., :k]
            mins[b0 : b0 + nb] = cheapest.min(axis=-1)
            # Cost of crossing a block ~ the mean of its k cheapest cells (a crossing takes about
            # k steps): a 2-pixel road keeps its block cheap where a plain mean would average it
            # away. Impassable cells among them count as the costliest value, so mostly-lethal
            # blocks look expensive; blocks with no passable cell are impassable.
            coarse_cost[b0 : b0 + nb] = np.where(np.isfinite(cheapest), cheapest, top).mean(axis=-1)

    if n == 1:
        strips(0)
    else:
        with ThreadPoolExecutor(n, thread_name_prefix="overseec-coarse") as pool:
            for done in [pool.submit(strips, i) for i in range(n)]:
                done.result()
    coarse_cost[~np.isfinite(mins)] = np.inf
    return coarse_cost, mins


def hop_mu(mins: np.ndarray, base_cost_per_m: float, hops: int) -> np.ndarray:
    """Least (cost + base) per metre over the (2 hops + 1)^2 blocks around each block (C order)."""
    mu = ndimage.minimum_filter(mins + base_cost_per_m, size=2 * hops + 1, mode="constant", cval=np.inf)
    return np.ascontiguousarray(mu)
