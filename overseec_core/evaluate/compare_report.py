"""Compare's results as rows and tables: each route's length, cost and class shares, the CSV and
the Markdown report.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from overseec_core import runfiles
from overseec_core.evaluate.compare import CHANGED_TOLERANCE, DIFFERENCE_NAME, FIGURE_NAME, OTHER_CLASS, DifferenceBand

# --------------------------------------------------------------------------------------------
# Result and its tables
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RouteRow:
    """One candidate's route as the tables show it."""

    name: str
    kind: str
    prompt: str
    length_m: float
    cost: float
    n_pixels: int
    mode: str
    bound: float
    #: Class name -> fraction of route pixels (None without --labels/--classes).
    class_share: Mapping[str, float] | None
    costmap: str  # relative to the output folder
    route: str
    program_file: str
    program_source: str
    mean_cost: float | None
    notes: tuple[str, ...] = ()

    @property
    def cost_per_m(self) -> float | None:
        return self.cost / self.length_m if self.length_m > 0 else None

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "kind": self.kind,
            "prompt": self.prompt,
            "length_m": self.length_m,
            "cost": self.cost,
            "cost_per_m": self.cost_per_m,
            "n_pixels": self.n_pixels,
            "mode": self.mode,
            "bound": self.bound,
            "class_share": dict(self.class_share) if self.class_share is not None else None,
            "costmap": self.costmap,
            "route": self.route,
            "program_file": self.program_file,
            "program_source": self.program_source,
            "mean_cost": self.mean_cost,
            "notes": list(self.notes),
        }


@dataclass(frozen=True)
class CompareResult:
    """What compare wrote and measured."""

    out_dir: Path
    rows: tuple[RouteRow, ...]
    #: Symmetric Hausdorff distances (m) between the routes, in candidate order.
    hausdorff_m: tuple[tuple[float, ...], ...]
    difference: tuple[DifferenceBand, ...]
    files: Mapping[str, Path]
    points: tuple[tuple[float, float], ...]
    crs: str | None
    mode: str
    classes: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()
    timings: Mapping[str, float] = field(default_factory=dict)

    @property
    def manifest(self) -> Path:
        return self.out_dir / runfiles.MANIFEST

    def pairs(self) -> list[dict[str, Any]]:
        """Every unordered pair of routes with its Hausdorff distance."""
        n = len(self.rows)
        return [
            {"a": self.rows[i].name, "b": self.rows[j].name, "hausdorff_m": self.hausdorff_m[i][j]}
            for i in range(n)
            for j in range(i + 1, n)
        ]

    def to_json(self) -> dict[str, Any]:
        return {
            "prompts": [r.to_json() for r in self.rows],
            "pairs": self.pairs(),
            "hausdorff_m": [list(r) for r in self.hausdorff_m],
            "difference": [b.to_json() for b in self.difference],
            "points": [list(p) for p in self.points],
            "crs": self.crs,
            "mode": self.mode,
            "classes": list(self.classes),
            "notes": list(self.notes),
            "files": {k: str(v) for k, v in self.files.items()},
            "timings": dict(self.timings),
        }


def csv_columns(rows: Sequence[RouteRow], classes: Sequence[str]) -> list[str]:
    """CSV header: the route's measures, ``share_<class>`` per class, ``hausdorff_m_<name>``
    per candidate (a row of the distance matrix)."""
    extra = [OTHER_CLASS] if any(r.class_share and OTHER_CLASS in r.class_share for r in rows) else []
    return (
        ["name", "kind", "prompt", "length_m", "cost", "cost_per_m", "n_pixels", "mode"]
        + [f"share_{c}" for c in (*classes, *extra)]
        + [f"hausdorff_m_{r.name}" for r in rows]
    )


def render_csv(result: CompareResult) -> str:
    """The route table as CSV text (one row per candidate)."""
    cols = csv_columns(result.rows, result.classes)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for i, r in enumerate(result.rows):
        base = [
            r.name,
            r.kind,
            r.prompt,
            f"{r.length_m:.3f}",
            f"{r.cost:.6g}",
            "" if r.cost_per_m is None else f"{r.cost_per_m:.6g}",
            r.n_pixels,
            r.mode,
        ]
        shares = [
            f"{(r.class_share or {}).get(c[len('share_') :], 0.0):.6f}" if r.class_share is not None else ""
            for c in cols
            if c.startswith("share_")
        ]
        dists = [f"{d:.3f}" for d in result.hausdorff_m[i]]
        w.writerow(base + shares + dists)
    return buf.getvalue()


def _md(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _num(value: float | None, fmt: str = ".4g") -> str:
    return "n/a" if value is None or not math.isfinite(value) else format(value, fmt)


def render_report(result: CompareResult) -> str:
    """The Markdown report: routes, class shares, Hausdorff matrix, cost differences, figure."""
    rows = result.rows
    names = [r.name for r in rows]
    pts = "; ".join(f"({x:.10g}, {y:.10g})" for x, y in result.points)
    lines = [
        f"# Prompt sensitivity: {len(rows)} prompts on one map",
        "",
        f"Same entity layers and the same points ({pts}{', ' + result.crs if result.crs else ''}); "
        f"planning mode {result.mode}. Each prompt's costmap, program and route are in its "
        "folder.",
        "",
        "## Routes",
        "",
        "| # | prompt | length (m) | cost | cost per m | folder |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r.name} | {_md(r.prompt)} | {r.length_m:.1f} | {_num(r.cost)} | {_num(r.cost_per_m)} | `{r.name}/` |"
        )
    if result.classes:
        cols = list(result.classes) + ([OTHER_CLASS] if any(OTHER_CLASS in (r.class_share or {}) for r in rows) else [])
        lines += [
            "",
            "## Share of each route in each class",
            "",
            "| # | " + " | ".join(_md(c) for c in cols) + " |",
            "|---|" + "---|" * len(cols),
        ]
        for r in rows:
            share = r.class_share or {}
            cells = [f"{100 * share.get(c, 0.0):.1f} %" for c in cols]
            lines.append(f"| {r.name} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "## Hausdorff distance between routes (m)",
        "",
        "| | " + " | ".join(names) + " |",
        "|---|" + "---|" * len(names),
    ]
    for i, name in enumerate(names):
        lines.append(f"| {name} | " + " | ".join(f"{d:.1f}" for d in result.hausdorff_m[i]) + " |")
    lines += [
        "",
        f"## Cost differences (`{DIFFERENCE_NAME}`)",
        "",
        "| band | difference | mean | min | max | pixels changed |",
        "|---|---|---|---|---|---|",
    ]
    for b in result.difference:
        frac = b.changed_pixels / b.valid_pixels if b.valid_pixels else None
        lines.append(
            f"| {b.band} | {b.description} | {_num(b.mean, '+.4f')} | {_num(b.min, '+.4f')} | "
            f"{_num(b.max, '+.4f')} | {'n/a' if frac is None else f'{100 * frac:.1f} %'} |"
        )
    lines += ["", f"![one panel per prompt]({FIGURE_NAME})", ""]
    if result.notes:
        lines += ["## Notes", ""] + [f"- {_md(n)}" for n in result.notes] + [""]
    lines += [
        "## Definitions",
        "",
        "- **length**: ground length of the route (m); **cost**: the planner's total, "
        "(mean cost of the two cells + base cost per m) x step length, on the prompt's own costmap.",
        "- **share**: fraction of the route's pixels in each class of the class raster "
        f"({OTHER_CLASS}: no data or a class id without a name).",
        "- **Hausdorff distance**: the largest distance from a pixel of either route to the "
        "other route (a polyline), in ground metres; 0 when the routes are the same.",
        "- **difference**: cost of the prompt minus cost of prompt_1, per pixel; "
        f"'pixels changed' counts |difference| > {CHANGED_TOLERANCE:g}.",
        "",
    ]
    return "\n".join(lines)
