"""Prompt sensitivity: several prompts (or cost programs) on the same layers and the same points.

For each candidate the costmap stage and the planner run exactly as `overseec costmap` and
`overseec plan` run them, each into its own subfolder ``prompt_1/``, ``prompt_2/`` ... of the
output folder (:func:`overseec_core.pipeline.run_compare` chains them). Then the candidates are
set side by side (this module, and :mod:`.compare_report` for the tables):

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

import os
from collections.abc import Iterable, Mapping, Sequence
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.windows import Window

from overseec_core import runfiles
from overseec_core.errors import InputError, RasterError
from overseec_core.evaluate.geometry import ReferenceSet, VectorLine, hausdorff
from overseec_core.io.grid import parse_crs
from overseec_core.io.manifest import check_run_folder
from overseec_core.io.read import open_raster, read_grid
from overseec_core.io.write import RasterWriter
from overseec_core.limits import MAX_PROGRAM_BYTES, read_text_limited
from overseec_core.plan.planner import MODES
from overseec_core.progress import NullProgress, Progress, check_cancelled
from overseec_core.synthesize.engine import blocks
from overseec_core.synthesize.layers import parse_vector_spec
from overseec_core.synthesize.options import CostmapOptions

#: Candidate kinds: a mission prompt (interpreted offline) or a cost program file.
KINDS = ("prompt", "program")
#: What compare writes into its output folder (besides the per-candidate subfolders): the
#: names are ``runfiles.COMPARE_FILES``'s.
DIFFERENCE_NAME, FIGURE_NAME = runfiles.COMPARE_FILES["difference"], runfiles.COMPARE_FILES["figure"]
CSV_NAME, JSON_NAME, REPORT_NAME = (runfiles.COMPARE_FILES[k] for k in ("csv", "json", "report"))
OUTPUT_NAMES = (runfiles.MANIFEST, DIFFERENCE_NAME, FIGURE_NAME, CSV_NAME, JSON_NAME, REPORT_NAME)
#: What each candidate's subfolder receives (costmap stage + plan stage).
SUBFOLDER_NAMES = (runfiles.MANIFEST, runfiles.COSTMAP, runfiles.LETHAL, runfiles.COSTMAP_PROGRAM, runfiles.PATH)
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
        return runfiles.COMPARE_CANDIDATE_DIR.format(index=self.index)

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

        return CostmapOptions(
            out=self.out_dir / candidate.name / runfiles.COSTMAP,
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

        found = [("masks", self.masks), ("labels", self.labels), ("classes", self.classes), ("grid", self.grid)]
        found += [("vector", parse_vector_spec(spec)[1]) for spec in self.vectors]
        found += [("program", Path(c.value)) for c in self.candidates if c.kind == "program"]
        found += [("priors", self.priors)]
        return [(role, Path(p)) for role, p in found if p is not None]


def check_options(o: CompareOptions) -> None:
    """Refuse, in one line and before anything is written, what cannot be compared."""

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
        out / c.name / runfiles.COSTMAP_PROGRAM
        for c in o.candidates
        if c.kind == "program" and _same(Path(c.value), out / c.name / runfiles.COSTMAP_PROGRAM)
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
