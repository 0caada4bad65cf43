"""Fast mode's coarse level: what a :class:`~overseec_core.plan.planner.Planner` builds once to
plan on a block-averaged copy of its costmap and search a corridor of blocks around that route.

The level holds a coarse planner (always the kernel's) on ``k x k`` block costs
(:func:`.coarse.block_costs`), the block-hop lower bound's arrays (:func:`.coarse.hop_mu`,
:func:`.coarse.hop_offsets`), the corridor's scratch buffers and the coarse shortest-path trees
kept for re-plans. The planner decides when to use it (``Planner._leg_fast``); these functions
only build and read it, so the search itself stays in one place.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Generic, Protocol, TypeVar

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from overseec_core.plan.backend import UNVISITED, _kernel
from overseec_core.plan.coarse import auto_coarse_factor, block_costs, hop_mu, hop_offsets
from overseec_core.plan.grid import PlanningGrid


class CoarsePlanner(Protocol):
    """What the level needs of its coarse planner (a :class:`~.planner.Planner`)."""

    @property
    def shape(self) -> tuple[int, int]: ...

    @property
    def buffers(self) -> dict[str, npt.NDArray[Any]]: ...

    def memory_bytes(self) -> dict[str, float]: ...


P = TypeVar("P", bound=CoarsePlanner)


@dataclass
class FastLevel(Generic[P]):
    """What fast mode needs, built once per planner (about 1/k^2 of the fine memory)."""

    k: int
    coarse: P
    mu: npt.NDArray[Any]  # (Hc, Wc) float64: min over a (2R+1)^2 block neighbourhood of (cost + base)
    valid: npt.NDArray[Any]  # (Hc*Wc) uint8: block holds a passable cell
    hop_offsets: npt.NDArray[Any]  # (K, 2) int64
    hop_lengths: npt.NDArray[Any]  # (K,) float64 metres
    hop_dist: npt.NDArray[Any]
    hop_state: npt.NDArray[Any]
    seed: npt.NDArray[Any]  # (Hc, Wc) uint8 scratch: coarse path cells
    region: npt.NDArray[Any]  # (Hc, Wc) uint8 scratch: corridor
    #: Coarse shortest-path trees by root block (see Planner's ``coarse_trees``), most recent last.
    trees: OrderedDict[tuple[int, int], P] = field(default_factory=OrderedDict)

    def nbytes(self) -> int:
        """Bytes held: its arrays, the coarse planner and the kept trees."""
        arrays = (self.mu, self.valid, self.hop_offsets, self.hop_lengths, self.hop_dist, self.hop_state)
        own = sum(a.nbytes for a in (*arrays, self.seed, self.region))
        trees = sum(int(t.memory_bytes()["total"]) for t in self.trees.values())
        return own + int(self.coarse.memory_bytes()["total"]) + trees


def build_fast_level(
    cost: npt.NDArray[Any],
    pixel_size_m: tuple[float, float],
    base_cost_per_m: float,
    bound_hops: int,
    coarse_factor: int | None,
    make_planner: Callable[[PlanningGrid], P],
) -> FastLevel[P]:
    """The coarse level of a costmap (``coarse_factor`` None: :func:`.coarse.auto_coarse_factor`);
    ``make_planner`` builds the coarse planner on the block costs' grid."""
    h, w = cost.shape
    dx, dy = pixel_size_m
    k = coarse_factor or auto_coarse_factor((h, w))
    coarse_cost, mins = block_costs(cost, k)
    hc, wc = coarse_cost.shape
    coarse = make_planner(PlanningGrid.from_array(coarse_cost, None, pixel_size_m=(k * dx, k * dy)))
    offs, lens = hop_offsets(bound_hops, k, dx, dy)
    n = hc * wc
    return FastLevel(
        k=k,
        coarse=coarse,
        mu=hop_mu(mins, base_cost_per_m, bound_hops),
        valid=np.isfinite(mins).astype(np.uint8).ravel(),
        hop_offsets=offs,
        hop_lengths=lens,
        hop_dist=np.empty(n, dtype=np.float64),
        hop_state=np.zeros(n, dtype=np.uint8),
        seed=np.zeros((hc, wc), dtype=np.uint8),
        region=np.zeros((hc, wc), dtype=np.uint8),
    )


def trace_tree(tree: CoarsePlanner, end: tuple[int, int]) -> npt.NDArray[Any] | None:
    """Cells from a grown tree's root to ``end`` (None when ``end`` is unreachable from it)."""
    h, w = tree.shape
    i = end[0] * w + end[1]
    buffers = tree.buffers
    if buffers["dist"][i] >= UNVISITED:
        return None
    return _kernel.trace(buffers["state"], h, w, i)


def corridor_region(fl: FastLevel[Any], coarse_pixels: npt.NDArray[Any], radius: int) -> npt.NDArray[Any]:
    """Blocks within ``radius`` of the coarse route, in the level's region buffer (filtered only
    around the route)."""
    hc, wc = fl.seed.shape
    r0, c0 = (max(0, int(v) - radius) for v in coarse_pixels.min(axis=0))
    r1, c1 = (int(v) + radius + 1 for v in coarse_pixels.max(axis=0))
    r1, c1 = min(hc, r1), min(wc, c1)
    fl.region.fill(0)
    seed = fl.seed[r0:r1, c0:c1]
    seed.fill(0)
    seed[coarse_pixels[:, 0] - r0, coarse_pixels[:, 1] - c0] = 1
    ndimage.maximum_filter(seed, size=2 * radius + 1, output=fl.region[r0:r1, c0:c1], mode="constant")
    return fl.region


def hop_bound(fl: FastLevel[Any], a: tuple[int, int], b: tuple[int, int], bound_hops: int, workspace: object) -> float:
    """The block-hop lower bound on the optimal cost from ``a`` to ``b`` (:func:`.coarse.hop_offsets`;
    0 where the hops find none)."""
    k, hops = fl.k, bound_hops
    _hc, wc = fl.mu.shape
    start = (a[0] // k) * wc + a[1] // k
    br, bc = b[0] // k, b[1] // k
    target = np.array([br - (hops - 1), br + (hops - 1), bc - (hops - 1), bc + (hops - 1)], dtype=np.int64)
    hop = _kernel.hop_bound(
        fl.mu, fl.valid, fl.hop_dist, fl.hop_state, workspace, fl.hop_offsets, fl.hop_lengths, start, target
    )
    return float(hop) if np.isfinite(hop) else 0.0
