"""Seeded start-goal pairs: over the passable cells of a costmap (the default), or uniform over
the whole image as the OVerSeeC paper draws its 50 evaluation pairs."""

from __future__ import annotations

import math

import numpy as np

from overseec_core.errors import EvaluateError

Pixel = tuple[int, int]

#: Pairs are drawn with a separation of at least this fraction of the map diagonal by default.
DEFAULT_MIN_SEPARATION_FRACTION = 0.2


def sample_pairs(
    passable: np.ndarray,
    n: int,
    rng: np.random.Generator,
    min_separation_m: float,
    pixel_size: tuple[float, float],
    max_tries: int = 200_000,
) -> list[tuple[Pixel, Pixel]]:
    """``n`` start-goal pairs drawn uniformly over passable cells, at least ``min_separation_m`` apart.

    Cells are drawn uniformly over the whole grid and kept when passable (rejection sampling),
    so no index array of the valid cells is built (100 M cells would cost 800 MB); when fewer
    than 1 % of the cells are passable the valid cells are listed once instead. Same seed, same
    pairs. May return fewer than ``n`` pairs when the separation is hard to meet.
    """
    h, w = passable.shape
    n_valid = int(np.count_nonzero(passable))
    if n_valid < 2:
        raise EvaluateError("the costmap has fewer than 2 passable cells; nothing to sample")
    px, py = pixel_size
    max_dist = math.hypot((h - 1) * py, (w - 1) * px)
    if min_separation_m > max_dist:
        raise EvaluateError(
            f"--min-separation {min_separation_m:g} m is longer than the map diagonal ({max_dist:.1f} m)"
        )
    flat = passable.ravel()
    listed = np.flatnonzero(flat) if n_valid < 0.01 * flat.size else None
    batch = 256

    def draw() -> np.ndarray:
        if listed is not None:
            return listed[rng.integers(0, len(listed), size=batch)]
        cand = rng.integers(0, flat.size, size=batch)
        return cand[flat[cand]]

    pairs: list[tuple[Pixel, Pixel]] = []
    tries = 0
    while len(pairs) < n and tries < max_tries:
        starts = draw()
        tries += batch
        if starts.size == 0:
            continue
        sr, sc = divmod(int(starts[0]), w)
        for _ in range(8):  # a few batches of goals per start, then draw a new start
            goals = draw()
            tries += batch
            gr, gc = np.divmod(goals, w)
            far = np.hypot((gr - sr) * py, (gc - sc) * px) >= min_separation_m
            if far.any():
                k = int(np.argmax(far))
                pairs.append(((sr, sc), (int(gr[k]), int(gc[k]))))
                break
    return pairs


def sample_pairs_uniform(shape: tuple[int, int], n: int, rng: np.random.Generator) -> list[tuple[Pixel, Pixel]]:
    """``n`` start-goal pairs with start and goal drawn uniformly over every cell of a grid of
    ``shape`` (the paper's draw: no passability test, no separation; start != goal). Same seed,
    same pairs."""
    h, w = shape
    if h * w < 2:
        raise EvaluateError("the grid has fewer than 2 cells; nothing to sample")
    pairs: list[tuple[Pixel, Pixel]] = []
    while len(pairs) < n:
        a, b = (int(v) for v in rng.integers(0, h * w, size=2))
        if a != b:
            pairs.append((divmod(a, w), divmod(b, w)))
    return pairs
