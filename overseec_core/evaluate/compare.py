"""Prompt sensitivity: several prompts (or cost programs) on the same layers and the same points.

For each candidate the costmap stage and the planner run exactly as `overseec costmap` and
`overseec plan` run them (:func:`pipeline.run_costmap`, :func:`pipeline.run_plan`), each into its
own subfolder ``prompt_1/``, ``prompt_2/`` ... of the output folder. Then the candidates are set
side by side:

- ``difference.tif``: float32, one band per candidate k > 1 holding cost_k - cost_1 (NaN where
  either costmap has no data), written block by block, so memory stays bounded by the block size;
- ``compare.png``: one panel per candidate (its costmap, its route in bold, the other routes
  faint, a scale bar, the prompt as the title), in map coordinates;
- ``compare.csv`` / ``compare.json`` / ``report.md``: each route's length, cost, its share of
  pixels in each class (with ``--labels``/``--classes``), and the Hausdorff distance between every
  pair of routes;
- ``manifest.json``: prompts, inputs (hashed), parameters and outputs.

This is the paper's prompt-sensitivity figure, for any map.
"""

from __future__ import annotations

import csv
import io
import math
import os
import time
from collections.abc import Iterable, Mapping, Sequence
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.windows import Window

from overseec_core.errors import InputError, OverseecError, RasterError
from overseec_core.io.read import open_raster, read_grid
from overseec_core.io.write import RasterWriter
from overseec_core.limits import MAX_PROGRAM_BYTES, read_text_limited
from overseec_core.progress import NullProgress, Progress, check_cancelled

#: Candidate kinds: a mission prompt (interpreted offline) or a cost program file.
KINDS = ("prompt", "program")
#: What compare writes into its output folder (besides the per-candidate subfolders).
DIFFERENCE_NAME, FIGURE_NAME = "difference.tif", "compare.png"
CSV_NAME, JSON_NAME, REPORT_NAME = "compare.csv", "compare.json", "report.md"
OUTPUT_NAMES = ("manifest.json", DIFFERENCE_NAME, FIGURE_NAME, CSV_NAME, JSON_NAME, REPORT_NAME)
#: What each candidate's subfolder receives (costmap stage + plan stage).
SUBFOLDER_NAMES = ("manifest.json", "costmap.tif", "lethal.tif", "costmap.program.txt", "path.geojson")
#: Rows of the class raster read at once when sampling it along a route.
SAMPLE_STRIP_ROWS = 512
#: Pixels whose cost differs by more than this count as changed in the difference summary.
CHANGED_TOLERANCE = 1e-6
#: Share key for route pixels on no data or on a class id that classes.json does not name.
OTHER_CLASS = "(other)"


# --------------------------------------------------------------------------------------------
# Options
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Candidate:
    """One thing to compare: a prompt, or a cost program file, and its place in the order."""

    index: int  # 1-based
    kind: str  # "prompt" | "program"
    value: str  # the prompt text, or the program file's path

    @property
    def name(self) -> str:
        """Its subfolder and its name in tables and band descriptions."""
        return f"prompt_{self.index}"

    @property
    def title(self) -> str:
        """What a reader recognises it by: the prompt, or 'program FILE'."""
        return self.value if self.kind == "prompt" else f"program {Path(self.value).name}"


def make_candidates(items: Iterable[tuple[str, str | os.PathLike]]) -> tuple[Candidate, ...]:
    """Number ("prompt"|"program", value) pairs in the order given (prompts and programs mix)."""
    out = []
    for k, (kind, value) in enumerate(items, start=1):
        if kind not in KINDS:
            raise InputError(f"unknown candidate kind {kind!r}; use prompt or program")
        out.append(Candidate(k, kind, str(value)))
    return tuple(out)


def _prompt_key(text: str) -> str:
    """Prompts that differ only in case, spacing or final punctuation are the same request."""
    return " ".join(text.lower().split()).rstrip(" .!;,")


def check_candidates(candidates: Sequence[Candidate]) -> None:
    """At least two, none empty, no two the same (same prompt, or same program text): a
    duplicate would only compare a costmap with itself."""
    if len(candidates) < 2:
        raise InputError(
            f"compare needs at least two prompts or programs (got {len(candidates)}); "
            "give --prompt and/or --program twice or more"
        )
    seen: dict[tuple[str, str], Candidate] = {}
    for c in candidates:
        if c.kind == "prompt":
            if not c.value.strip():
                raise InputError(f"--prompt {c.index} is empty; say what to prefer and avoid")
            key = ("prompt", _prompt_key(c.value))
        else:
            path = Path(c.value)
            if not path.is_file():
                raise InputError(f"--program {path}: no such file")
            key = ("program", read_text_limited(path, MAX_PROGRAM_BYTES, "--program").strip())
        if key in seen:
            first = seen[key]
            what = f"prompt {c.value!r}" if c.kind == "prompt" else f"program {c.value}"
            raise InputError(f"{c.name} repeats {first.name} ({what}); give different prompts or programs to compare")
        seen[key] = c


@dataclass(frozen=True)
class CompareOptions:
    """What `overseec compare` asks for.

    Layers are given as `overseec costmap` takes them (``masks`` folder, ``labels`` + ``classes``,
    ``vectors`` "name=path", ``grid`` for vector-only layers); every candidate reads the same ones.
    ``points`` are (x, y) map coordinates, start, vias..., goal, in ``crs`` (None = the layers' CRS).
    """

    out_dir: Path
    candidates: tuple[Candidate, ...]
    points: tuple[tuple[float, float], ...]
    crs: str | None = None
    mode: str = "exact"
    masks: Path | None = None
    labels: Path | None = None
    classes: Path | None = None
    vectors: tuple[str, ...] = ()
    grid: Path | None = None
    line_width_m: float = 0.0
    block_size: int = 1024
    aliases: tuple[tuple[str, str], ...] = ()
    #: Prior table file for the prompts (``interpret.priors``); ``no_priors`` switches it off.
    priors: Path | None = None
    no_priors: bool = False

    def costmap_options(self, candidate: Candidate) -> Any:
        """The costmap stage's options for one candidate, into its subfolder."""
        from overseec_core.synthesize.options import CostmapOptions

        return CostmapOptions(
            out=self.out_dir / candidate.name / "costmap.tif",
            masks=self.masks,
            labels=self.labels,
            classes=self.classes,
            vectors=self.vectors,
            grid=self.grid,
            prompt=candidate.value if candidate.kind == "prompt" else None,
            program=Path(candidate.value) if candidate.kind == "program" else None,
            line_width_m=self.line_width_m,
            block_size=self.block_size,
            aliases=self.aliases,
            priors=self.priors,
            no_priors=self.no_priors,
        )

    def inputs(self) -> list[tuple[str, Path]]:
        """Every file or folder compare reads, with the option that named it."""
        from overseec_core.synthesize.layers import parse_vector_spec

        found = [("masks", self.masks), ("labels", self.labels), ("classes", self.classes), ("grid", self.grid)]
        found += [("vector", parse_vector_spec(spec)[1]) for spec in self.vectors]
        found += [("program", Path(c.value)) for c in self.candidates if c.kind == "program"]
        found += [("priors", self.priors)]
        return [(role, Path(p)) for role, p in found if p is not None]


def check_options(o: CompareOptions) -> None:
    """Refuse, in one line and before anything is written, what cannot be compared."""
    from overseec_core.io.grid import parse_crs
    from overseec_core.plan.planner import MODES

    check_candidates(o.candidates)
    if not o.points:
        raise InputError("no points: give --start X Y and --goal X Y (the same route is planned on every costmap)")
    if len(o.points) < 2:
        raise InputError("compare needs a start and a goal (--start X Y --goal X Y)")
    if o.mode not in MODES:
        raise InputError(f"unknown planning mode {o.mode!r}; use {' or '.join(MODES)}")
    if o.crs is not None:
        parse_crs(o.crs)
    if o.masks is None and o.labels is None and o.classes is None and not o.vectors:
        raise InputError("no entity layers: give --masks DIR, --labels L --classes C, or --vector")
    if (o.labels is None) != (o.classes is None):
        raise InputError("--labels and --classes go together (a class raster and its classes.json)")
    check_out_dir(o)


def _same(a: Path, b: Path) -> bool:
    a, b = Path(a), Path(b)
    if a.resolve() == b.resolve():
        return True
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def check_out_dir(o: CompareOptions) -> None:
    """The output folder, its subfolders and every file compare writes must not be an input.

    A candidate's own program file (``prompt_k/costmap.program.txt``, edited and given back as
    the k-th ``--program``) is the one exception, as with `overseec costmap`. Then
    :func:`check_run_folders`: no symlinked ``prompt_k``, no damaged manifest.
    """
    out = Path(o.out_dir)
    folders = [out] + [out / c.name for c in o.candidates]
    files = [out / n for n in OUTPUT_NAMES] + [out / c.name / n for c in o.candidates for n in SUBFOLDER_NAMES]
    own = [
        out / c.name / "costmap.program.txt"
        for c in o.candidates
        if c.kind == "program" and _same(Path(c.value), out / c.name / "costmap.program.txt")
    ]
    for role, path in o.inputs():
        if any(_same(path, f) for f in folders):
            raise InputError(f"--out {out} is the input --{role} {path}; choose another output folder")
        hit = next((f for f in files if _same(path, f)), None)
        if hit is not None and not any(_same(hit, p) for p in own):
            raise InputError(
                f"--{role} {path} is where compare writes {hit.relative_to(out)}; move it or choose another --out"
            )
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out} exists and is not a folder")
    check_run_folders(out, folders[1:])


def check_run_folders(out: Path, subfolders: Sequence[Path]) -> None:
    """Refuse, before anything is written, a candidate folder that is a symbolic link and a
    damaged manifest in any folder compare records into.

    Outputs never follow a link out of the output folder: a file output replaces a symlink in
    its place (atomic.publish renames over the link, the target stays), but ``OUT/prompt_k`` is
    a folder compare writes into, and replacing a link there would delete the user's link, so it
    is refused. A ``manifest.json`` that is not a UTF-8 JSON object is refused, never replaced
    (:func:`overseec_core.io.manifest.read_manifest`).
    """
    from overseec_core.io.manifest import check_run_folder

    for folder in subfolders:
        if folder.is_symlink():
            raise InputError(
                f"--out {out}: {folder} is a symbolic link, and compare never writes through one; "
                "remove it or choose another --out"
            )
    for folder in (out, *subfolders):
        check_run_folder(folder)


# --------------------------------------------------------------------------------------------
# Measures (pure, or reading a window at a time)
# --------------------------------------------------------------------------------------------


def sample_pixels(path: str | os.PathLike, pixels: np.ndarray, band: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Values of a raster band at (row, col) pixels and whether each is valid (not nodata).

    Reads strips of :data:`SAMPLE_STRIP_ROWS` rows, each only across the columns the pixels in
    it span, so a route across a huge raster costs a few strips, never the whole band.
    """
    rc = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    with open_raster(path) as ds:
        values = np.zeros(len(rc), dtype=np.dtype(ds.dtypes[band - 1]))
        valid = np.zeros(len(rc), dtype=bool)
        if len(rc) == 0:
            return values, valid
        if (rc < 0).any() or (rc[:, 0] >= ds.height).any() or (rc[:, 1] >= ds.width).any():
            raise RasterError(f"{path}: route pixels outside the raster ({ds.width}x{ds.height})")
        nodata = ds.nodatavals[band - 1]
        for r0 in range(int(rc[:, 0].min()), int(rc[:, 0].max()) + 1, SAMPLE_STRIP_ROWS):
            sel = (rc[:, 0] >= r0) & (rc[:, 0] < r0 + SAMPLE_STRIP_ROWS)
            if not sel.any():
                continue
            rows, cols = rc[sel, 0], rc[sel, 1]
            c0, r1 = int(cols.min()), int(rows.max()) + 1
            window = Window(c0, r0, int(cols.max()) + 1 - c0, r1 - r0)
            data = ds.read(band, window=window)
            v = data[rows - r0, cols - c0]
            ok = np.isfinite(v) if v.dtype.kind == "f" else np.ones(len(v), dtype=bool)
            if nodata is not None and not np.isnan(nodata):
                ok &= v != nodata
            values[sel], valid[sel] = v, ok
    return values, valid


def class_shares(ids: np.ndarray, valid: np.ndarray, classes: Mapping[int, str]) -> dict[str, float]:
    """Fraction of route pixels in each class of ``classes`` (id -> name, in id order), and
    :data:`OTHER_CLASS` for pixels on no data or an unnamed id when there are any. Sums to 1."""
    ids = np.asarray(ids)
    valid = np.asarray(valid, dtype=bool)
    n = len(ids)
    if n == 0:
        return {name: 0.0 for _, name in sorted(classes.items())}
    shares = {name: float(np.count_nonzero(valid & (ids == cid))) / n for cid, name in sorted(classes.items())}
    named = np.isin(ids, list(classes)) & valid
    other = float(n - np.count_nonzero(named)) / n
    if other > 0:
        shares[OTHER_CLASS] = other
    return shares


def route_hausdorff_m(a: np.ndarray, b: np.ndarray, pixel_size: tuple[float, float]) -> float:
    """Symmetric Hausdorff distance (ground metres) between two routes of (row, col) pixels.

    Each direction is the evaluation's distance of one route's pixels to the other route taken
    as a polyline (:func:`evaluate.hausdorff` against a one-line :class:`evaluate.ReferenceSet`),
    so equal routes are 0 apart, and a route against itself shifted by one pixel is one pixel.
    """
    from overseec_core.evaluate import ReferenceSet, VectorLine, hausdorff

    a = np.asarray(a, dtype=np.float64).reshape(-1, 2)
    b = np.asarray(b, dtype=np.float64).reshape(-1, 2)

    def directed(p: np.ndarray, q: np.ndarray) -> float:
        ref = ReferenceSet.build([VectorLine(name="route", rows_cols=q)], pixel_size)
        return hausdorff(p, ref, pixel_size, diagonal_m=1.0).directed_m

    return max(directed(a, b), directed(b, a))


def hausdorff_matrix(routes: Sequence[np.ndarray], pixel_size: tuple[float, float]) -> tuple[tuple[float, ...], ...]:
    """Symmetric matrix of :func:`route_hausdorff_m` between every pair (0 on the diagonal)."""
    n = len(routes)
    m = np.zeros((n, n))
    for i in range(n):
        for j in range(i + 1, n):
            m[i, j] = m[j, i] = route_hausdorff_m(routes[i], routes[j], pixel_size)
    return tuple(tuple(float(v) for v in row) for row in m)


@dataclass(frozen=True)
class DifferenceBand:
    """Summary of one band of the difference raster: cost of ``name`` minus cost of ``base``."""

    band: int
    name: str
    base: str
    valid_pixels: int
    changed_pixels: int  # |difference| > CHANGED_TOLERANCE
    mean: float | None
    min: float | None
    max: float | None

    @property
    def description(self) -> str:
        return f"{self.name} - {self.base}"

    def to_json(self) -> dict[str, Any]:
        return {
            "band": self.band,
            "description": self.description,
            "name": self.name,
            "base": self.base,
            "valid_pixels": self.valid_pixels,
            "changed_pixels": self.changed_pixels,
            "changed_fraction": self.changed_pixels / self.valid_pixels if self.valid_pixels else None,
            "mean": self.mean,
            "min": self.min,
            "max": self.max,
        }


def write_difference(
    costmaps: Sequence[str | os.PathLike],
    names: Sequence[str],
    out: str | os.PathLike,
    block_size: int = 1024,
    progress: Progress | None = None,
) -> tuple[DifferenceBand, ...]:
    """cost_k - cost_1 for k = 2..n as an n-1 band float32 GeoTIFF (NaN where either is no data).

    All costmaps must share one grid. Read and written in ``block_size`` windows, so memory is
    n windows whatever the map's size; lethal cells keep their cost (lethal.tif says which they
    are). Returns a summary per band.
    """
    from overseec_core.synthesize.engine import blocks

    if len(costmaps) < 2 or len(costmaps) != len(names):
        raise InputError("the difference needs two costmaps or more, one name each")
    grid = read_grid(costmaps[0])
    for path in costmaps[1:]:
        other = read_grid(path)
        if not other.same_as(grid):
            raise RasterError(
                f"{path} is not on the grid of {costmaps[0]}; costmaps to compare must come from the same layers"
            )
    progress = progress or NullProgress()
    n = len(costmaps) - 1
    valid = np.zeros(n, np.int64)
    changed = np.zeros(n, np.int64)
    total = np.zeros(n, np.float64)
    lo = np.full(n, np.inf)
    hi = np.full(n, -np.inf)
    windows = [core for core, _ in blocks(grid, max(16, block_size), (0, 0))]
    descriptions = [f"{names[k]} - {names[0]}" for k in range(1, len(names))]
    progress.begin("difference", len(windows), unit="block")
    try:
        with ExitStack() as stack:
            sources = [stack.enter_context(open_raster(p)) for p in costmaps]
            writer = stack.enter_context(
                RasterWriter(
                    out,
                    grid,
                    n,
                    "float32",
                    nodata=float("nan"),
                    descriptions=descriptions,
                    tags={"OVERSEEC_DIFFERENCE": "cost of band's prompt minus cost of " + names[0]},
                    inputs=costmaps,
                )
            )
            for window in windows:
                check_cancelled(progress)
                base = sources[0].read(1, window=window).astype(np.float32)
                diff = np.empty((n, int(window.height), int(window.width)), np.float32)
                for k, ds in enumerate(sources[1:]):
                    diff[k] = ds.read(1, window=window).astype(np.float32) - base
                    d = diff[k][np.isfinite(diff[k])]
                    valid[k] += d.size
                    if d.size:
                        changed[k] += int(np.count_nonzero(np.abs(d) > CHANGED_TOLERANCE))
                        total[k] += float(d.sum(dtype=np.float64))
                        lo[k], hi[k] = min(lo[k], float(d.min())), max(hi[k], float(d.max()))
                diff[~np.isfinite(diff)] = np.nan
                writer.write(diff, int(window.row_off), int(window.col_off))
                progress.advance(1)
    finally:
        progress.end()
    return tuple(
        DifferenceBand(
            band=k + 1,
            name=names[k + 1],
            base=names[0],
            valid_pixels=int(valid[k]),
            changed_pixels=int(changed[k]),
            mean=float(total[k] / valid[k]) if valid[k] else None,
            min=float(lo[k]) if valid[k] else None,
            max=float(hi[k]) if valid[k] else None,
        )
        for k in range(n)
    )


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
        return self.out_dir / "manifest.json"

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


# --------------------------------------------------------------------------------------------
# The command
# --------------------------------------------------------------------------------------------


def _titled(candidate: Candidate, exc: OverseecError) -> OverseecError:
    """The same error, its message prefixed with the candidate it concerns."""
    short = candidate.title if len(candidate.title) <= 60 else candidate.title[:57] + "..."
    if exc.args and isinstance(exc.args[0], str):
        exc.args = (f"{candidate.name} ({short!r}): {exc.args[0]}",) + tuple(exc.args[1:])
    return exc


def _rel(path: Path, root: Path) -> str:
    try:
        return Path(path).resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(path)


def _same_program_notes(candidates: Sequence[Candidate], programs: Sequence[str]) -> list[str]:
    """Notes for candidates whose programs came out the same (their costmaps are equal)."""
    notes: list[str] = []
    first: dict[str, Candidate] = {}
    for c, text in zip(candidates, programs):
        body = "\n".join(ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#"))
        if body in first:
            notes.append(
                f"{c.name} and {first[body].name} give the same cost program: their costmaps and routes are the same"
            )
        else:
            first[body] = c
    return notes


def _input_files(o: CompareOptions) -> list[tuple[str, Path]]:
    """The files to hash into the manifest: every input file, and for a --masks folder the mask
    and probability rasters the costmap stage reads from it (compose.MASK_FILES)."""
    from overseec_core.synthesize.layers import MASK_FILES

    files = []
    for role, path in o.inputs():
        if path.is_dir() and role == "masks":
            pair = next((pair for pair in MASK_FILES if (path / pair[0]).is_file()), ())
            files += [(role, path / name) for name in pair if (path / name).is_file()]
        elif path.is_file():
            files.append((role, path))
    return files


def run_compare(
    options: CompareOptions, progress: Progress | None = None, command_args: dict | None = None
) -> CompareResult:
    """Every candidate's costmap and route, then the difference raster, figure and tables.

    All outputs are one transaction: a failure or a cancel (in any candidate) leaves the output
    folder as it was, and removes the folders it created.
    """
    from overseec_core.io.transaction import output_transaction

    check_options(options)
    out = Path(options.out_dir)
    created = [d for d in (out, *(out / c.name for c in options.candidates)) if not d.exists()]
    try:
        with output_transaction():
            return _run(options, progress or NullProgress(), command_args)
    except BaseException:
        for folder in reversed(created):  # only if empty: nothing of anyone else's goes
            try:
                folder.rmdir()
            except OSError:
                pass
        raise


def _run(o: CompareOptions, progress: Progress, command_args: dict | None) -> CompareResult:
    from overseec_core.io.manifest import RunDir

    t0 = time.perf_counter()
    out = Path(o.out_dir)
    run = RunDir(out, command="compare", args=command_args)
    for role, path in _input_files(o):
        run.record_input(f"compare_{role}_{path.name}", path)
    run.update_parameters(
        compare={
            "prompts": [{"name": c.name, "kind": c.kind, "value": c.value} for c in o.candidates],
            "points": [list(p) for p in o.points],
            "crs": o.crs,
            "mode": o.mode,
            "vectors": list(o.vectors),
            "aliases": [list(a) for a in o.aliases],
            "line_width_m": o.line_width_m,
            "block_size": o.block_size,
        }
    )
    with run.stage("compare"):
        costmaps, plans = _run_candidates(o, progress)
        t_runs = time.perf_counter()
        difference = write_difference(
            [cm.costmap for cm in costmaps],
            [c.name for c in o.candidates],
            out / DIFFERENCE_NAME,
            o.block_size,
            progress,
        )
        routes = [np.asarray(p.result.pixels, dtype=np.int64) for p in plans]
        classes, shares = _route_shares(o, routes)
        rows = tuple(_route_row(c, cm, p, s, out) for c, cm, p, s in zip(o.candidates, costmaps, plans, shares))
        notes = _same_program_notes(o.candidates, [cm.program for cm in costmaps])
        for note in notes:
            progress.message(f"note: {note}")
        grid = read_grid(costmaps[0].costmap)
        _write_figure(out / FIGURE_NAME, grid, o.candidates, [cm.costmap for cm in costmaps], routes)
        result = CompareResult(
            out_dir=out,
            rows=rows,
            hausdorff_m=hausdorff_matrix(routes, grid.pixel_size_m()),
            difference=difference,
            files=_output_files(out),
            points=tuple(o.points),
            crs=o.crs,
            mode=o.mode,
            classes=tuple(classes.values()),
            notes=tuple(notes),
            timings={"candidates_s": round(t_runs - t0, 4), "compare_s": round(time.perf_counter() - t_runs, 4)},
        )
        _write_tables(result)
    run.set(
        "compare",
        {
            "prompts": [r.to_json() for r in rows],
            "pairs": result.pairs(),
            "difference": [b.to_json() for b in difference],
            "notes": list(notes),
            "outputs": {k: v.name for k, v in result.files.items()},
            "folders": [c.name for c in o.candidates],
            "timings": dict(result.timings),
        },
    )
    run.save()
    return result


def _run_candidates(o: CompareOptions, progress: Progress) -> tuple[list, list]:
    """Each candidate through the costmap stage and the planner, into its subfolder; an error
    names the candidate it came from."""
    from overseec_core.pipeline import run_costmap, run_plan
    from overseec_core.plan.stage import PlanOptions

    costmaps, plans = [], []
    for c in o.candidates:
        check_cancelled(progress)
        progress.message(f"{c.name}: {c.title}")
        folder = Path(o.out_dir) / c.name
        folder.mkdir(parents=True, exist_ok=True)
        try:
            cost = run_costmap(
                o.costmap_options(c), progress, command_args={"compare": c.name, "kind": c.kind, "value": c.value}
            )
            plan = run_plan(
                PlanOptions(
                    costmap=cost.costmap, points=tuple(o.points), out=folder / "path.geojson", crs=o.crs, mode=o.mode
                ),
                progress,
                command_args={"compare": c.name},
            )
        except OverseecError as exc:
            _titled(c, exc)  # the same error, its message now naming the candidate
            raise
        costmaps.append(cost)
        plans.append(plan)
    return costmaps, plans


def _route_shares(
    o: CompareOptions, routes: Sequence[np.ndarray]
) -> tuple[dict[int, str], list[Mapping[str, float] | None]]:
    """Classes (id -> name, in id order) and each route's class shares; none without labels."""
    from overseec_core.evaluate import load_classes

    if o.labels is None or o.classes is None:
        return {}, [None] * len(routes)
    classes = dict(sorted(load_classes(o.classes).names.items()))
    return classes, [class_shares(*sample_pixels(o.labels, r), classes) for r in routes]


def _route_row(c: Candidate, cm: Any, p: Any, share: Mapping[str, float] | None, out: Path) -> RouteRow:
    """The table row of one candidate from its costmap (CostmapResult) and plan (PlanRunResult)."""
    r = p.result
    return RouteRow(
        name=c.name,
        kind=c.kind,
        prompt=c.title,
        length_m=float(r.length_m),
        cost=float(r.cost),
        n_pixels=int(len(r.pixels)),
        mode=str(r.mode),
        bound=float(r.bound),
        class_share=share,
        costmap=_rel(cm.costmap, out),
        route=_rel(p.outputs["geojson"], out),
        program_file=_rel(cm.program_file, out),
        program_source=cm.program_source,
        mean_cost=cm.mean_cost,
        notes=tuple(r.notes),
    )


def _write_figure(
    path: Path, grid: Any, candidates: Sequence[Candidate], costmaps: Sequence[Path], routes: Sequence[np.ndarray]
) -> Path:
    """compare.png: :func:`plots.side_by_side_figure`, written atomically."""
    from overseec_core.evaluate.plots import PlotPath, read_cost_preview, side_by_side_figure
    from overseec_core.io.atomic import atomic_path

    fig, _ = side_by_side_figure(
        grid,
        [read_cost_preview(p, max_size=900) for p in costmaps],
        [PlotPath(rows_cols=r, label=c.name) for c, r in zip(candidates, routes)],
        [f"{c.index}. {c.title}" for c in candidates],
    )
    with atomic_path(path, suffix=".partial.png") as tmp:
        fig.savefig(tmp, format="png")
    return path


def _output_files(out: Path) -> dict[str, Path]:
    return {
        "difference": out / DIFFERENCE_NAME,
        "figure": out / FIGURE_NAME,
        "csv": out / CSV_NAME,
        "json": out / JSON_NAME,
        "report": out / REPORT_NAME,
    }


def _write_tables(result: CompareResult) -> None:
    """compare.csv, compare.json and report.md, each atomically."""
    from overseec_core.io.atomic import write_text_atomic
    from overseec_core.io.manifest import write_json_atomic

    write_text_atomic(result.files["csv"], render_csv(result))
    write_json_atomic(result.files["json"], result.to_json())
    write_text_atomic(result.files["report"], render_report(result))
