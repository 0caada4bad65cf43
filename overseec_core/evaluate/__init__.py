"""Evaluation: the OVerSeeC paper's metrics on planned or given paths, plus segmentation IoU.

What each figure means here (the paper leaves some choices open; these are ours, stated once):

RRPI (rank-relative path index)
    Given a class raster on the costmap grid and a rank per class (1 = most preferred), the RRPI of
    a path is ``sum over its pixels of (rank(class(pixel)) - 1)``: a path that stays on rank-1
    terrain scores 0, every pixel on worse terrain adds its rank distance from the best. Pixels
    whose class has no rank (background, classes left out of ``--ranks``, label nodata) count as
    ``unranked_rank``, by default the largest rank given (``"max"``): not knowing what a pixel is
    is treated as the least preferred known terrain. A path's pixels are its 8-connected pixel
    chain (the planner's output, or a drawn line rasterised with Bresenham's algorithm).

Hausdorff distance to reference paths
    Reference paths are human-drawn LineStrings in any vector format and CRS; they are reprojected
    to the costmap's CRS with pyproj. Distances are in metres using the pixel size on the ground
    (x and y apart, so non-square pixels and geographic CRSs are right): from a path pixel to the
    reference lines they are exact (see :class:`ReferenceSet`); the reverse direction samples the
    references every quarter of the smaller pixel side (error below an eighth of a pixel).
    A path is only compared with the reference paths *of its own start and goal*: those whose
    first and last points lie within max(3 pixels, 1 % of the map diagonal) in ground metres of
    the path's start and goal (either direction). Paths without such a reference get no
    Hausdorff distance (null), and the report says how many were matched per group.
    The default is the *directed* Hausdorff distance from a system path to the union of the
    reference paths of its pair, ``max over path pixels p of min over reference points r
    |p - r|``: how far the path strays from anywhere a human would go (the union holds several
    humans' paths, so the reverse direction would charge the system for not following all of them
    at once). ``symmetric`` takes the max of both directions. Each distance is normalised by the
    map diagonal in metres, and the reported "mean Hausdorff" is the mean of the normalised
    distances over the matched paths. The mean point-to-reference distance is reported beside it.

Rank-optimal reference
    For each path with an RRPI, the best route under the ranks between the same ends: planned in
    exact mode with the project's planner (same base cost per metre as the evaluated costmap's
    planner) on a costmap that encodes the ranks exactly, ``(rank - 1) / (K - 1)`` with ``K`` the
    largest rank (unranked rank included; all zeros when K = 1) and label nodata impassable.
    ``rrpi_ratio = rrpi / rrpi_optimal``: 1 when both are 0, infinite when only the optimum is 0
    (written null in JSON with ``rrpi_ratio_infinite: true``, ``inf`` in pairs.csv). Summaries per
    group: median ratio, share of paths within 5 % (ratio <= 1.05), worst and best ratio, mean
    excess RRPI. A costmap equal to the rank costmap scores exactly 1. The planner minimises
    metre-weighted cost while RRPI counts pixels (a diagonal step is one pixel but 1.41 pixel
    lengths), so the reference is not the minimum-RRPI pixel chain and ratios a little below 1
    occur (down to 0.93 on a real scene); the exact minimum (a node-weighted search, e.g.
    skimage.graph.MCP) measured 6x slower than the planner.

KDE centre of mass
    A Gaussian KDE (scipy.stats.gaussian_kde, Scott's bandwidth) of the (path length in metres,
    RRPI) points of the sampled pairs is evaluated on a grid spanning the data padded by three
    kernel standard deviations and clipped at 0 (neither figure can be negative); the centre of
    mass is the density-weighted mean of that grid, the mode its densest cell. Axes with no spread
    (e.g. every path has RRPI 0) are held at their constant value. The linear fit is
    scipy.stats.linregress of RRPI on length (slope in RRPI per metre).

IoU
    Per ground-truth class, ``|pred AND gt| / |pred OR gt|`` over pixels valid in both rasters.
    The prediction is either a masks raster (one band per entity, band description = entity name;
    integer bands are positive where > 0, float bands where >= 0.5) or a single-band class raster
    with no band description, read with the same classes.json.

Everything is streamed or bounded: IoU reads row blocks, the labels for RRPI are read once
(1 byte per pixel for uint8 labels), and plots read decimated rasters.

Modules (each imports only those listed before it)::

    classes    ClassTable, RankTable: classes.json and --ranks
    geometry   pixels <-> metres <-> world, lines read from vector files, same-grid checks,
               ReferenceSet and the Hausdorff distance
    sampling   seeded start-goal pairs over passable cells
    metrics    RRPI, rank-optimal reference, KDE centre of mass, linear fit, EvaluatedPath
    iou        per-class IoU of masks (or a class raster) against ground truth
    report     report.md, pairs.csv, paths.geojson and the PNG plots
    stage      EvaluateOptions, check_options, evaluate_paths (the stage), EvaluateResult
"""

from __future__ import annotations

from overseec_core.evaluate.classes import ClassTable, RankTable, load_classes, parse_ranks
from overseec_core.evaluate.geometry import (
    MATCH_TOLERANCE_FRACTION,
    MATCH_TOLERANCE_PIXELS,
    HausdorffResult,
    ReferenceSet,
    VectorLine,
    check_same_grid,
    densify,
    endpoint_tolerance_m,
    hausdorff,
    map_diagonal_m,
    matching_references,
    point_json,
    point_segment_distance,
    rasterise_line,
    read_lines,
    to_metres,
    world_to_rowcol,
)
from overseec_core.evaluate.iou import IOU_BLOCK_PIXELS, ClassIoU, IoUResult, compute_iou, parse_matches
from overseec_core.evaluate.metrics import (
    KDE_GRID_SIZE,
    NEAR_OPTIMAL_RATIO,
    EvaluatedPath,
    KdeSummary,
    LinearFit,
    RankOptimalPlanner,
    RankOptimum,
    kde_centre_of_mass,
    linear_fit,
    rank_costmap,
    rank_optimal_rrpi,
    rank_scale,
    rrpi,
    rrpi_ratio,
    summarise_ratios,
)
from overseec_core.evaluate.report import DEFINITIONS, render_report
from overseec_core.evaluate.sampling import DEFAULT_MIN_SEPARATION_FRACTION, Pixel, sample_pairs, sample_pairs_uniform
from overseec_core.evaluate.stage import EvaluateOptions, EvaluateResult, check_options, evaluate_paths

__all__ = [
    "ClassIoU",
    "ClassTable",
    "DEFAULT_MIN_SEPARATION_FRACTION",
    "DEFINITIONS",
    "EvaluateOptions",
    "EvaluateResult",
    "EvaluatedPath",
    "HausdorffResult",
    "IOU_BLOCK_PIXELS",
    "IoUResult",
    "KDE_GRID_SIZE",
    "KdeSummary",
    "LinearFit",
    "MATCH_TOLERANCE_FRACTION",
    "MATCH_TOLERANCE_PIXELS",
    "NEAR_OPTIMAL_RATIO",
    "Pixel",
    "RankOptimalPlanner",
    "RankOptimum",
    "RankTable",
    "ReferenceSet",
    "VectorLine",
    "check_options",
    "check_same_grid",
    "compute_iou",
    "densify",
    "endpoint_tolerance_m",
    "evaluate_paths",
    "hausdorff",
    "kde_centre_of_mass",
    "linear_fit",
    "load_classes",
    "map_diagonal_m",
    "matching_references",
    "parse_matches",
    "parse_ranks",
    "point_json",
    "point_segment_distance",
    "rank_costmap",
    "rank_optimal_rrpi",
    "rank_scale",
    "rasterise_line",
    "read_lines",
    "render_report",
    "rrpi",
    "rrpi_ratio",
    "sample_pairs",
    "sample_pairs_uniform",
    "summarise_ratios",
    "to_metres",
    "world_to_rowcol",
]
