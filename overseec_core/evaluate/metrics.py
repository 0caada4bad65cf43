"""Path figures: RRPI, the rank-optimal reference, the KDE centre of mass and linear fit of
(length, RRPI), and :class:`EvaluatedPath` (one path and its figures). Definitions in
:mod:`overseec_core.evaluate`."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from overseec_core.errors import EvaluateError
from overseec_core.evaluate.classes import RankTable
from overseec_core.evaluate.geometry import HausdorffResult, point_json
from overseec_core.io.grid import Grid
from overseec_core.plan import DEFAULT_BASE_COST_PER_M, Planner, PlanningGrid
from overseec_core.progress import Progress

# --------------------------------------------------------------------------------------------
# RRPI
# --------------------------------------------------------------------------------------------


def rrpi(labels: np.ndarray, pixels: np.ndarray, ranks: RankTable, nodata: float | None = None) -> int:
    """RRPI of a path: sum of ``rank - 1`` over its (row, col) pixels (see :mod:`overseec_core.evaluate`)."""
    pixels = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    if pixels.size == 0:
        return 0
    values = labels[pixels[:, 0], pixels[:, 1]]
    return int(ranks.penalties(values, nodata).sum())


# --------------------------------------------------------------------------------------------
# Rank-optimal reference
# --------------------------------------------------------------------------------------------


#: A route within this factor of the rank-optimal RRPI counts as "near optimal" in the summary.
NEAR_OPTIMAL_RATIO = 1.05


def rank_scale(ranks: RankTable) -> int:
    """K: the largest rank among the ranked classes and the unranked rank."""
    return max([ranks.unranked_rank, *ranks.ranks.values()])


def rank_costmap(labels: np.ndarray, ranks: RankTable, nodata: float | None = None) -> np.ndarray:
    """A costmap that encodes the ranks exactly: ``(rank - 1) / (K - 1)`` per pixel, float32.

    ``K`` is :func:`rank_scale` (all zeros when K == 1); unranked classes get
    ``unranked_rank``, as in :func:`rrpi`; label nodata is NaN (impassable, as nodata is to the
    planner). Built class by class into one float32 array (4 bytes per pixel, 1-byte temporaries).
    """
    k = rank_scale(ranks)
    scale = 1.0 / (k - 1) if k > 1 else 0.0
    out = np.full(labels.shape, (ranks.unranked_rank - 1) * scale, dtype=np.float32)
    for cid, rank in ranks.ranks.items():
        if nodata is not None and cid == nodata:
            continue
        out[labels == cid] = (rank - 1) * scale
    if nodata is not None and not math.isnan(nodata):
        out[labels == nodata] = np.nan
    return out


def rrpi_ratio(value: int, optimal: int) -> float:
    """``value / optimal``: 1.0 when both are 0, ``inf`` when only the optimum is 0."""
    if optimal == 0:
        return 1.0 if value == 0 else math.inf
    return value / optimal


@dataclass(frozen=True, eq=False)
class RankOptimum:
    """The rank-optimal route between two cells: its RRPI and the route itself."""

    rrpi: int
    pixels: np.ndarray  # (N, 2) (row, col)
    length_m: float
    cost: float  # on the rank costmap, base cost included


class RankOptimalPlanner:
    """Plans on :func:`rank_costmap` of the labels with the project's planner (exact mode).

    ``base_cost_per_m`` should be the evaluated planner's (default: the planner's default), so
    that both routes trade length against terrain the same way. Memory: the float32 rank costmap
    (4 bytes per pixel) plus the planner's working buffers (about 13 bytes per pixel); the labels
    are only referenced.

    The planner minimises ``sum over steps of (mean rank cost of the two cells + base) x step
    metres`` while RRPI counts pixels (a diagonal step is one pixel but 1.41 pixel lengths), so
    the route found is the planner's best on a costmap that encodes the ranks exactly, not the
    minimum-RRPI pixel chain: another route can score a somewhat lower RRPI (ratios a little
    below 1 do occur). What it guarantees instead: a costmap equal to the rank costmap scores a
    ratio of exactly 1.
    """

    def __init__(
        self,
        labels: np.ndarray,
        ranks: RankTable,
        nodata: float | None = None,
        grid: Grid | None = None,
        *,
        base_cost_per_m: float | None = None,
        pixel_size_m: tuple[float, float] | None = None,
    ) -> None:
        self.labels, self.ranks, self.nodata = labels, ranks, nodata
        cost = rank_costmap(labels, ranks, nodata)
        if pixel_size_m is None:
            pixel_size_m = grid.pixel_size_m() if grid is not None else (1.0, 1.0)
        # built directly (PlanningGrid.from_array would copy the 4 bytes/pixel array once more);
        # the values are finite and in [0, 1] or NaN by construction
        px, py = pixel_size_m
        self.grid = PlanningGrid(cost=cost, grid=grid, pixel_size_m=(float(px), float(py)), source="rank costmap")
        self.base_cost_per_m = DEFAULT_BASE_COST_PER_M if base_cost_per_m is None else float(base_cost_per_m)
        self.planner = Planner(self.grid, self.base_cost_per_m)

    def optimum(self, start: Sequence[int], goal: Sequence[int], progress: Progress | None = None) -> RankOptimum:
        """The rank-optimal route from ``start`` to ``goal`` ((row, col)); PlanError when there is
        none (an end on label nodata, or nodata cutting them apart)."""
        res = self.planner.plan([tuple(map(int, start)), tuple(map(int, goal))], mode="exact", progress=progress)
        pixels = np.asarray(res.pixels, dtype=np.int64)
        return RankOptimum(
            rrpi=rrpi(self.labels, pixels, self.ranks, self.nodata),
            pixels=pixels,
            length_m=float(res.length_m),
            cost=float(res.cost),
        )


def rank_optimal_rrpi(
    labels: np.ndarray,
    ranks: RankTable,
    start: Sequence[int],
    goal: Sequence[int],
    nodata: float | None = None,
    *,
    grid: Grid | None = None,
    base_cost_per_m: float | None = None,
    pixel_size_m: tuple[float, float] | None = None,
) -> int:
    """RRPI of the rank-optimal route between two (row, col) cells (see :class:`RankOptimalPlanner`;
    build that once to plan many pairs). Raises PlanError when no route exists."""
    return (
        RankOptimalPlanner(labels, ranks, nodata, grid, base_cost_per_m=base_cost_per_m, pixel_size_m=pixel_size_m)
        .optimum(start, goal)
        .rrpi
    )


def summarise_ratios(values: Sequence[int], optima: Sequence[int | None]) -> dict[str, Any]:
    """Summary of route RRPI against rank-optimal RRPI over paths (None: no optimum for that path).

    ``median_ratio`` and ``worst_ratio`` are null when infinite (a route off rank 1 where the
    optimum stays on it); ``n_infinite`` counts those routes.
    """
    pairs = [(int(v), int(o)) for v, o in zip(values, optima) if o is not None]
    out: dict[str, Any] = {"n": len(pairs), "n_without_optimum": sum(o is None for o in optima)}
    if not pairs:
        return out
    ratios = np.array([rrpi_ratio(v, o) for v, o in pairs], dtype=np.float64)
    median = float(np.median(ratios))
    worst = float(ratios.max())
    out.update(
        {
            "median_ratio": median if math.isfinite(median) else None,
            "share_within_5pct": float(np.mean(ratios <= NEAR_OPTIMAL_RATIO)),
            "worst_ratio": worst if math.isfinite(worst) else None,
            "best_ratio": float(ratios.min()),
            "n_infinite": int(np.isinf(ratios).sum()),
            "mean_excess_rrpi": float(np.mean([v - o for v, o in pairs])),
        }
    )
    return out


# --------------------------------------------------------------------------------------------
# KDE centre of mass and linear fit
# --------------------------------------------------------------------------------------------


KDE_GRID_SIZE = 128


@dataclass(frozen=True, eq=False)
class KdeSummary:
    """Centre of mass and mode of a KDE of (length, RRPI); grid and density kept for plotting."""

    n: int
    com: tuple[float, float]
    mode: tuple[float, float]
    note: str = ""
    xs: np.ndarray | None = None  # grid along length
    ys: np.ndarray | None = None  # grid along RRPI
    density: np.ndarray | None = None  # (len(ys), len(xs))

    def to_json(self) -> dict[str, Any]:
        return {
            "n": self.n,
            "com": {"length_m": self.com[0], "rrpi": self.com[1]},
            "mode": {"length_m": self.mode[0], "rrpi": self.mode[1]},
            "note": self.note or None,
        }


def kde_centre_of_mass(lengths: Sequence[float], values: Sequence[float], grid_size: int = KDE_GRID_SIZE) -> KdeSummary:
    """KDE centre of mass and mode of 2-D points (see :mod:`overseec_core.evaluate` for the method)."""
    from scipy.stats import gaussian_kde  # scipy.stats takes ~0.3 s to import: only when used

    pts = np.vstack([np.asarray(lengths, dtype=np.float64), np.asarray(values, dtype=np.float64)])
    n = pts.shape[1]
    if n == 0:
        raise EvaluateError("no paths to summarise (every sampled pair was unreachable?)")
    mean = pts.mean(axis=1)
    spread = pts.std(axis=1)
    scale = np.maximum(np.abs(mean), 1.0)
    active = np.flatnonzero(spread > 1e-9 * scale)
    if n < 3 or active.size == 0:
        why = "fewer than 3 points" if n < 3 else "all points equal"
        return KdeSummary(
            n=n,
            com=(float(mean[0]), float(mean[1])),
            mode=(float(mean[0]), float(mean[1])),
            note=f"KDE not defined ({why}); centre of mass is the plain mean",
        )
    try:
        kde = gaussian_kde(pts[active])
    except np.linalg.LinAlgError:
        # Perfectly correlated axes: the KDE's covariance is singular. Fall back to the mean.
        return KdeSummary(
            n=n,
            com=(float(mean[0]), float(mean[1])),
            mode=(float(mean[0]), float(mean[1])),
            note="KDE singular (points on a line); centre of mass is the plain mean",
        )
    sd = np.sqrt(np.diag(np.atleast_2d(kde.covariance)))
    axes = []
    for k, dim in enumerate(active):
        lo = max(pts[dim].min() - 3 * sd[k], 0.0)
        hi = pts[dim].max() + 3 * sd[k]
        axes.append(np.linspace(lo, hi, grid_size))
    mesh = np.meshgrid(*axes, indexing="ij")
    dens = kde(np.vstack([m.ravel() for m in mesh])).reshape(mesh[0].shape)
    total = dens.sum()
    com, mode = mean.copy(), mean.copy()
    peak = np.unravel_index(np.argmax(dens), dens.shape)
    for k, dim in enumerate(active):
        com[dim] = float((mesh[k] * dens).sum() / total)
        mode[dim] = float(mesh[k][peak])
    xs = ys = density = None
    if active.size == 2:
        xs, ys, density = axes[0], axes[1], dens.T
    note = (
        "" if active.size == 2 else f"{'length' if 0 not in active else 'RRPI'} is the same for every path; KDE is 1-D"
    )
    return KdeSummary(
        n=n,
        com=(float(com[0]), float(com[1])),
        mode=(float(mode[0]), float(mode[1])),
        note=note,
        xs=xs,
        ys=ys,
        density=density,
    )


@dataclass(frozen=True)
class LinearFit:
    """RRPI = slope * length_m + intercept (scipy.stats.linregress)."""

    slope: float  # RRPI per metre
    intercept: float
    r: float
    p: float
    stderr: float
    n: int


def linear_fit(lengths: Sequence[float], values: Sequence[float]) -> LinearFit | None:
    """Least-squares line of RRPI on path length; None with fewer than 2 distinct lengths."""
    from scipy.stats import linregress  # ~0.3 s to import: only when used

    x = np.asarray(lengths, dtype=np.float64)
    y = np.asarray(values, dtype=np.float64)
    if len(x) < 2 or np.ptp(x) == 0:
        return None
    res = linregress(x, y)
    r = float(res.rvalue) if np.isfinite(res.rvalue) else 0.0
    p = float(res.pvalue) if np.isfinite(res.pvalue) else 1.0
    return LinearFit(
        slope=float(res.slope), intercept=float(res.intercept), r=r, p=p, stderr=float(res.stderr), n=len(x)
    )


# --------------------------------------------------------------------------------------------
# One evaluated path and its figures
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class EvaluatedPath:
    """One system path and its figures; ``pixels`` is its (N, 2) (row, col) chain."""

    name: str
    #: "sampled" (random pair), "reference-ends" (planned between a reference's ends),
    #: "given" (--paths) or "reference" (a reference path itself, for its RRPI and cost)
    group: str
    pixels: np.ndarray
    length_m: float
    cost: float | None = None
    mode: str | None = None
    rrpi: int | None = None
    hausdorff: HausdorffResult | None = None
    #: RRPI of the rank-optimal route between the same ends (None: not computed or no route)
    rrpi_optimal: int | None = None
    #: whether the rank-optimal route was looked for (ranks given)
    rank_optimal_ran: bool = False
    #: names of the reference paths of the same start and goal; None when there are no
    #: references (and for a reference path itself)
    references: tuple[str, ...] | None = None

    @property
    def ratio(self) -> float | None:
        """RRPI / rank-optimal RRPI (inf when only the optimum is 0); None without both."""
        if self.rrpi is None or self.rrpi_optimal is None:
            return None
        return rrpi_ratio(self.rrpi, self.rrpi_optimal)

    def to_json(self, grid: Grid) -> dict[str, Any]:
        start, goal = self.pixels[0], self.pixels[-1]
        out: dict[str, Any] = {
            "name": self.name,
            "group": self.group,
            "start": point_json(grid, start),
            "goal": point_json(grid, goal),
            "length_m": self.length_m,
            "pixels": int(len(self.pixels)),
            "cost": self.cost,
            "mode": self.mode,
            "rrpi": self.rrpi,
        }
        if self.rrpi is not None:
            out["rrpi_per_pixel"] = self.rrpi / len(self.pixels)
        if self.rank_optimal_ran:
            ratio = self.ratio
            out["rrpi_optimal"] = self.rrpi_optimal
            out["rrpi_ratio"] = ratio if ratio is not None and math.isfinite(ratio) else None
            out["rrpi_ratio_infinite"] = ratio is not None and math.isinf(ratio)
        if self.references is not None:
            out["hausdorff"] = None if self.hausdorff is None else asdict(self.hausdorff)
            out["hausdorff_references"] = list(self.references)
        elif self.hausdorff is not None:
            out["hausdorff"] = asdict(self.hausdorff)
        return out
