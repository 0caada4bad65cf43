"""The evaluate stage's files besides metrics.json: report.md (:func:`render_report`), pairs.csv,
paths.geojson and the PNG plots (drawn by :mod:`overseec_core.evaluate.plots` and
:mod:`overseec_core.evaluate.maps`)."""

from __future__ import annotations

import csv
import io
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core.evaluate import maps, plots
from overseec_core.evaluate.geometry import VectorLine
from overseec_core.evaluate.iou import IoUResult
from overseec_core.evaluate.metrics import EvaluatedPath
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.grid import Grid
from overseec_core.plan.export import LONLAT_DECIMALS, write_geojson
from overseec_core.runfiles import EVALUATION_FILES

DEFINITIONS = {
    "rrpi": "sum over path pixels of (rank - 1); unranked classes and nodata count as unranked_rank",
    "hausdorff_paper": "the paper's Hausdorff figure (the headline): mean over the path's pixels of the "
    "distance (m) to the nearest point of the union of the reference paths of the same start and goal, "
    "divided by the map diagonal (m)",
    "hausdorff": "max over path pixels of the distance (m) to the union of the reference paths of the same "
    "start and goal (both ends within max(3 px, 1 % of the map diagonal), either direction; "
    "paths without one get null) (directed; symmetric adds the reverse direction), divided by "
    "the map diagonal (m)",
    "rrpi_optimal": "RRPI of the exact-mode route between the same ends on a costmap of (rank - 1) / (K - 1), "
    "K = the largest rank incl. the unranked rank (label nodata impassable), with the same "
    "base cost per metre; rrpi_ratio = rrpi / rrpi_optimal (1 when both are 0; infinite when "
    "only the optimum is 0: written null with rrpi_ratio_infinite true)",
    "kde_com": "density-weighted mean of a Gaussian KDE of (length_m, rrpi) over a grid spanning the data "
    "+/- 3 kernel sd, clipped at 0; mode = densest grid cell",
    "fit": "scipy.stats.linregress of rrpi on length_m (slope in RRPI per metre)",
    "iou": "per ground-truth class |pred & gt| / |pred | gt| over pixels valid in both rasters",
}


def _plot_tag(p: EvaluatedPath) -> str:
    """What the overlay writes beside a path's start and goal: the pair number, else its name."""
    m = re.fullmatch(r"pair (\d+)", p.name)
    if m:
        return m.group(1)
    return p.name if len(p.name) <= 14 else p.name[:13] + "…"


def write_plots(
    files: Mapping[str, Path],
    grid: Grid | None,
    paths: Sequence[EvaluatedPath],
    references: Sequence[VectorLine],
    kde,
    fit,
    iou: IoUResult | None,
    cost_preview: Any = None,
    *,
    costmap: Path | None = None,
    image: Path | None = None,
    plot_size: int = 1600,
) -> dict[str, Path]:
    """The PNG plots the figures allow (RRPI vs length, paths overlay, IoU), into ``files``."""
    written: dict[str, Path] = {}
    sampled = [(p.length_m, p.rrpi) for p in paths if p.group == "sampled" and p.rrpi is not None]
    if sampled:
        written["rrpi_plot"] = plots.plot_rrpi_vs_length(
            files["rrpi_plot"],
            [x for x, _ in sampled],
            [y for _, y in sampled],
            kde,
            fit,
            title=f"RRPI vs path length ({len(sampled)} sampled pairs)",
        )
    if grid is not None and (paths or references) and (costmap is not None or image is not None or paths):
        draw = [maps.PlotPath(line.rows_cols, kind="reference") for line in references]
        system = [p for p in paths if p.group != "reference"]
        draw += [maps.PlotPath(p.pixels, tag=_plot_tag(p)) for p in system]
        written["overlay_plot"] = maps.plot_paths_overlay(
            files["overlay_plot"],
            grid,
            draw,
            costmap=costmap if cost_preview is None else None,
            image=image,
            max_size=plot_size,
            cost=cost_preview,
            title=f"{len(system)} path(s) on {Path(costmap).name if costmap else 'the grid'}",
        )
    if iou is not None and iou.classes:
        written["iou_plot"] = plots.plot_iou(
            files["iou_plot"], [c.name for c in iou.classes], [c.iou for c in iou.classes], iou.mean_iou
        )
    return written


def _ratio_text(ratio: float | None) -> str:
    if ratio is None:
        return ""
    return "inf" if math.isinf(ratio) else f"{ratio:.4f}"


def write_pairs_csv(path: Path, paths: Sequence[EvaluatedPath]) -> Path:
    """pairs.csv: one row per evaluated path with its figures."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(
        [
            "name",
            "group",
            "start_row",
            "start_col",
            "goal_row",
            "goal_col",
            "length_m",
            "pixels",
            "cost",
            "mode",
            "rrpi",
            "hausdorff_m",
            "hausdorff_normalised",
            "mean_distance_m",
            "rrpi_optimal",
            "rrpi_ratio",
            "hausdorff_references",
            "hausdorff_paper",
        ]
    )
    for p in paths:
        hd = p.hausdorff
        w.writerow(
            [
                p.name,
                p.group,
                *map(int, p.pixels[0]),
                *map(int, p.pixels[-1]),
                f"{p.length_m:.3f}",
                len(p.pixels),
                "" if p.cost is None else f"{p.cost:.6g}",
                p.mode or "",
                "" if p.rrpi is None else p.rrpi,
                "" if hd is None else f"{hd.hausdorff_m:.3f}",
                "" if hd is None else f"{hd.normalised:.6f}",
                "" if hd is None else f"{hd.mean_m:.3f}",
                "" if p.rrpi_optimal is None else p.rrpi_optimal,
                _ratio_text(p.ratio),
                "" if p.references is None else ";".join(p.references),
                "" if hd is None else f"{hd.paper:.6f}",
            ]
        )
    return write_text_atomic(path, buf.getvalue())


def write_paths_geojson(path: Path, paths: Sequence[EvaluatedPath], grid: Grid) -> Path:
    """Evaluated paths as RFC 7946 GeoJSON (WGS 84 lon/lat) LineStrings with their figures,
    written compactly like the plan stage's paths (plan.export)."""
    # pyproj loads on first use, as elsewhere in the core
    from pyproj import CRS as ProjCRS  # noqa: N811 (not rasterio's CRS)
    from pyproj import Transformer

    to_wgs84 = Transformer.from_crs(ProjCRS.from_wkt(grid.crs.to_wkt()), ProjCRS.from_epsg(4326), always_xy=True)
    features = []
    for p in paths:
        xs, ys = grid.transform * (p.pixels[:, 1] + 0.5, p.pixels[:, 0] + 0.5)
        lon, lat = to_wgs84.transform(np.asarray(xs), np.asarray(ys))
        coords = np.round(np.column_stack([lon, lat]), LONLAT_DECIMALS).tolist()
        if len(coords) == 1:
            coords = coords * 2
        props = {k: v for k, v in p.to_json(grid).items() if k not in ("start", "goal")}
        features.append(
            {"type": "Feature", "properties": props, "geometry": {"type": "LineString", "coordinates": coords}}
        )
    return write_geojson(path, {"type": "FeatureCollection", "features": features})


def _fmt(value: Any, digits: int = 4) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def render_report(metrics: Mapping[str, Any]) -> str:  # noqa: C901
    """A short Markdown report of metrics.json, linking the PNG plots beside it."""
    lines = ["# overseec evaluation", ""]
    files = metrics.get("files", {})
    inputs = metrics.get("inputs", {})
    if inputs:
        lines += ["Inputs: " + ", ".join(f"{k} `{Path(v).name}`" for k, v in inputs.items()), ""]
    if "ranks" in metrics:
        r = metrics["ranks"]
        lines += [
            "Ranks: " + ", ".join(f"{k}={v}" for k, v in r["ranks"].items()) + f"; unranked = {r['unranked_rank']}",
            "",
        ]
    s = metrics.get("sampling")
    if s:
        lines += [
            "## Sampled start-goal pairs",
            "",
            f"{s['planned']} of {s['drawn']} pairs planned ({s['mode']} mode, seed {s['seed']}, "
            + (
                "drawn uniformly over the image, as the paper draws them"
                if s.get("draw") == "image"
                else f"at least {s['min_separation_m']:.1f} m apart"
            )
            + f"); {len(s['unreachable'])} unreachable.",
        ]
        if s.get("rules_not_met"):
            lines += [
                f"**{s['rules_not_met']} of them could not keep a keep-out rule** (a distance rule, "
                "a never-cross rule or an obstacle): no route between their points avoids the "
                "rule's keep-out zone, so they enter it as little as they can."
            ]
        lines += [""]
    kde, fit = metrics.get("kde"), metrics.get("fit")
    if kde:
        lines += [
            f"- KDE centre of mass: length **{kde['com']['length_m']:.1f} m**, "
            f"RRPI **{kde['com']['rrpi']:.2f}** (mode {kde['mode']['length_m']:.1f} m, "
            f"{kde['mode']['rrpi']:.2f}){'; ' + kde['note'] if kde.get('note') else ''}"
        ]
    if fit:
        sign = "-" if fit["intercept"] < 0 else "+"
        lines += [
            f"- Linear fit: RRPI = {fit['slope']:.4g} x length_m {sign} {abs(fit['intercept']):.4g} "
            f"(r = {fit['r']:.3f}, n = {fit['n']})"
        ]
    elif kde:
        lines += ["- Linear fit: n/a (fewer than 2 distinct lengths)"]
    if kde or fit:
        lines += [""]
    if "rrpi_plot" in files:
        lines += [f"![RRPI vs path length]({files['rrpi_plot']})", ""]
    ro = metrics.get("rank_optimal")
    if ro and ro.get("groups"):
        lines += [
            "## Rank-optimal reference",
            "",
            f"Each path's RRPI against the best route under the ranks between the same ends (planned "
            f"{ro['mode']} on a costmap of {ro['cost']} per pixel, base cost {ro['base_cost_per_m']:g} "
            f"per metre); ratio = RRPI / optimal RRPI. A ratio of 1 is as good as a costmap that "
            "encodes the ranks exactly; a little below 1 is possible (RRPI counts pixels, the planner "
            "weighs metres).",
            "",
            f"| group | n | median ratio | within {100 * (ro['near_optimal_ratio'] - 1):.0f} % | "
            "worst ratio | mean excess RRPI |",
            "|---|---|---|---|---|---|",
        ]
        for group, g in ro["groups"].items():
            if not g["n"]:
                lines += [f"| {group} | 0 | n/a | n/a | n/a | n/a |"]
                continue
            median = "inf" if g["median_ratio"] is None else f"{g['median_ratio']:.3f}"
            worst = "inf" if g["worst_ratio"] is None else f"{g['worst_ratio']:.3f}"
            lines += [
                f"| {group} | {g['n']} | {median} | {100 * g['share_within_5pct']:.0f} % | {worst} | "
                f"{g['mean_excess_rrpi']:.1f} |"
            ]
        lines += [""]
    h = metrics.get("hausdorff")
    if h:
        lines += ["## Hausdorff distance to reference paths", ""]
        matched = h.get("matched") or {}
        if matched:
            counts = ", ".join(f"{v['matched']} of {v['paths']} {g}" for g, v in matched.items())
            lines += [
                f"Only paths whose start and goal lie within {h['endpoint_tolerance_m']:.1f} m of a "
                f"reference path's ends are measured, each against the reference path(s) of its pair; "
                f"matched: {counts}.",
                "",
            ]
        if h.get("mean_normalised") is not None:
            lines += [
                f"Hausdorff distance as the paper defines it (mean over each path's points of the distance "
                f"to the reference union, per map diagonal), over the {h['n']} matched {h['paths']} path(s) "
                f"({len(h['references'])} reference path(s) in all): **{h['mean_paper_normalised']:.4f}** "
                f"({h['mean_point_distance_m']:.1f} m). Per-path maximum ({h['kind']}): "
                f"{h['mean_normalised']:.4f} of the map diagonal ({h['mean_m']:.1f} m).",
                "",
            ]
        else:
            lines += ["No evaluated path shares its start and goal with a reference path: no Hausdorff distance.", ""]
    summary = metrics.get("summary", {})
    if summary:
        lines += [
            "## Paths",
            "",
            "| group | n | mean length (m) | mean RRPI | Hausdorff (paper) | max Hausdorff / diagonal |",
            "|---|---|---|---|---|---|",
        ]
        for group, g in summary.items():
            lines += [
                f"| {group} | {g['n']} | {g['mean_length_m']:.1f} | {_fmt(g.get('mean_rrpi'))} | "
                f"{_fmt(g.get('mean_hausdorff_paper'))} | {_fmt(g.get('mean_hausdorff_normalised'))} |"
            ]
        lines += [""]
        shown = metrics.get("paths", [])[:50]
        lines += [
            "| path | start (row, col) | goal (row, col) | length (m) | cost | RRPI | optimal RRPI | "
            "ratio | Hausdorff (m) |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        for p in shown:
            hd = p.get("hausdorff")
            ratio = "inf" if p.get("rrpi_ratio_infinite") else _fmt(p.get("rrpi_ratio"))
            lines += [
                f"| {p['name']} | {p['start']['row']}, {p['start']['col']} | {p['goal']['row']}, "
                f"{p['goal']['col']} | {p['length_m']:.1f} | {_fmt(p['cost'])} | {_fmt(p['rrpi'])} | "
                f"{_fmt(p.get('rrpi_optimal'))} | {ratio} | "
                f"{'n/a' if not hd else format(hd['hausdorff_m'], '.2f')} |"
            ]
        if len(metrics.get("paths", [])) > len(shown):
            lines += [
                f"| ... {len(metrics['paths']) - len(shown)} more in {EVALUATION_FILES['pairs_csv']} | | | | | | | | |"
            ]
        lines += [""]
    if s and s["unreachable"]:
        lines += ["Unreachable pairs (skipped):", ""]
        lines += [f"- {u['name']}: {u['error']}" for u in s["unreachable"]] + [""]
    if "overlay_plot" in files:
        lines += [f"![paths over the costmap]({files['overlay_plot']})", ""]
    iou = metrics.get("iou")
    if iou:
        scored = sum(c["iou"] is not None for c in iou["classes"])
        lines += [
            "## IoU",
            "",
            f"Mean IoU **{_fmt(iou['mean_iou'])}** over the {scored} class(es) present in "
            f"either raster ({iou['mode']} mode; {iou['valid_pixels']} valid pixels).",
            "",
            "| class | predicted by | IoU | TP | FP | FN |",
            "|---|---|---|---|---|---|",
        ]
        for c in iou["classes"]:
            lines += [
                f"| {c['name']} | {', '.join(c['bands']) or 'same class id'} | {_fmt(c['iou'])} | "
                f"{c['tp']} | {c['fp']} | {c['fn']} |"
            ]
        if iou["missing_classes"]:
            lines += ["", "No mask band for: " + ", ".join(iou["missing_classes"])]
        if iou["unmatched_bands"]:
            lines += ["", "Bands matching no class (use --match CLASS=BAND): " + ", ".join(iou["unmatched_bands"])]
        lines += [""]
        if "iou_plot" in files:
            lines += [f"![IoU per class]({files['iou_plot']})", ""]
    for note in metrics.get("notes", []):
        lines += [f"> {note}", ""]
    return "\n".join(lines).rstrip() + "\n"
