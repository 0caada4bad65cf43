"""Verified GeoTIFF output.

:class:`RasterWriter` writes tiled, compressed GeoTIFFs on an exact copy of an input grid, into a
temporary file beside the target that is renamed only when complete and verified, with overviews
and band descriptions. It refuses to overwrite any input.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
import rasterio
from rasterio.enums import Interleaving, Resampling
from rasterio.windows import Window

from overseec_core.errors import OutputError
from overseec_core.io.atomic import discard, output_error, publish, space_reason, temp_beside
from overseec_core.io.grid import Grid
from overseec_core.io.read import GDAL_ERRORS, _gdal_reason

# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


def _env_flag(name: str) -> bool:
    return os.environ.get(name, "").strip().lower() in ("1", "true", "yes")


@dataclass(frozen=True)
class WriteOptions:
    """GeoTIFF layout of outputs: tiled, compressed, with internal overviews.

    GDAL cannot stream a Cloud-Optimized GeoTIFF: the COG layout (overviews before the data) needs
    a full rewrite through the COG driver after the data is written, measured at 5-7x the cost of
    building internal overviews on large outputs. It is therefore opt-in: ``cog=True``, or the
    environment variable OVERSEEC_COG=1 (the CLI's ``--cog``). Compression defaults to ZSTD
    (fast, read by every GDAL >= 2.3 and so by QGIS); OVERSEEC_COMPRESS=deflate for older readers.
    """

    blocksize: int = 512
    compress: str = field(default_factory=lambda: os.environ.get("OVERSEEC_COMPRESS", "zstd"))
    zlevel: int = 6
    zstd_level: int = 1
    overviews: bool = True
    overview_resampling: Resampling = Resampling.average
    cog: bool = field(default_factory=lambda: _env_flag("OVERSEEC_COG"))
    #: Compression of the streamed temporary file when a COG rewrite follows (read once, deleted).
    intermediate_compress: str = "zstd"
    #: GDAL compression threads (GTiff/COG NUM_THREADS).
    threads: str = "ALL_CPUS"
    #: Before the rename every output is checked (:func:`verify_geotiff`): its block index and
    #: its last blocks, a few milliseconds. True also decodes every block (slower, see there).
    verify_every_block: bool = False


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def check_output_path(path: str | os.PathLike, inputs: Iterable[str | os.PathLike] = ()) -> Path:
    """Refuse outputs that would overwrite an input, take a run folder's bookkeeping name
    (manifest.json, .manifest.lock) or cannot be written; return the path."""
    from overseec_core.io.manifest import check_output_name

    out = Path(path)
    check_output_name(out)
    for src in inputs:
        if src is None:
            continue
        src = Path(src)
        if out.resolve() == src.resolve() or _same_file(out, src):
            raise OutputError(f"output {out} is the input {src}; choose another output path")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"cannot write {out}: folder {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write {out}: folder {parent} is not writable")
    if out.is_dir():
        raise OutputError(f"cannot write {out}: it is a directory")
    return out


#: Most GDAL failure messages kept per call (a full disk can repeat one per block).
_MAX_GDAL_MESSAGES = 20
#: GDAL's CE_Failure: the class of the messages :func:`gdal_errors` collects (CE_Fatal is 4).
_CE_FAILURE = 3


@functools.lru_cache(maxsize=1)
def _osgeo_gdal() -> Any:
    """osgeo.gdal when it drives the very GDAL rasterio uses (Debian's python3-gdal), else None.

    GDAL reports some write failures only to its error handler, never to the caller: blocks its
    cache flushes at close, a directory it cannot rewrite. rasterio 1.3 has no public way to
    push a handler; osgeo's ``PushErrorHandler`` does, and a self-test (an error raised through
    rasterio must reach it) makes sure it is the same library, not a second GDAL.
    """
    try:
        from osgeo import gdal
    except Exception:  # not installed or broken: the written file's verification still guards
        return None
    seen: list[str] = []
    with rasterio.Env():
        gdal.PushErrorHandler(lambda cls, no, msg: seen.append(str(msg)))
        try:
            rasterio.open("/vsimem/overseec-selftest-missing.tif").close()
        except Exception:  # expected: the file does not exist
            pass
        finally:
            gdal.PopErrorHandler()
    return gdal if seen else None


@contextmanager
def gdal_errors() -> Iterator[list[str]]:
    """Run GDAL calls with their failure messages collected instead of printed.

    Inside, GDAL's default handler (``ERROR 1: ...`` lines on stderr, one per failed block) is
    replaced: rasterio's Env routes messages to logging, and where :func:`_osgeo_gdal` is
    available a handler on top of it collects every CE_Failure message, including those of
    calls that do not fail (a close whose flush hit a full disk). GDAL's handler stack is
    per thread: enter it in the thread that makes the calls.
    """
    messages: list[str] = []
    gdal = _osgeo_gdal()
    with rasterio.Env():
        if gdal is None:
            yield messages
            return

        def collect(cls: int, _no: int, msg: str) -> None:
            if cls >= _CE_FAILURE and len(messages) < _MAX_GDAL_MESSAGES:
                messages.append(" ".join(str(msg).split()))

        gdal.PushErrorHandler(collect)
        try:
            yield messages
        finally:
            gdal.PopErrorHandler()


def _write_failed(messages: Sequence[str]) -> bool:
    """True when GDAL's messages say data did not reach the file (I/O, not e.g. PROJ notes)."""
    if space_reason(None, messages) is not None:
        return True
    words = ("write", "seek", "i/o", "io error", "flush")
    return any(w in m.lower() for m in messages for w in words)


def _block_counts(ds) -> tuple[int, int]:
    """Blocks across and down one band of ``ds``."""
    bh, bw = ds.block_shapes[0]
    return -(-ds.width // bw), -(-ds.height // bh)


def _check_block_index(ds, size: int, level: str) -> str | None:
    """None when every block of every band has bytes inside a file of ``size`` bytes.

    libtiff records a block's offset before writing it and its byte count after: a block whose
    write failed (a full disk) has a count of 0, which GDAL would read back silently as nodata.
    """
    nbx, nby = _block_counts(ds)
    bands = [1] if ds.interleaving == Interleaving.pixel else ds.indexes
    for b in bands:
        for y in range(nby):
            for x in range(nbx):
                off = ds.get_tag_item(f"BLOCK_OFFSET_{x}_{y}", "TIFF", bidx=b)
                n = ds.get_tag_item(f"BLOCK_SIZE_{x}_{y}", "TIFF", bidx=b)
                if not off or not n or int(off) <= 0 or int(n) <= 0 or int(off) + int(n) > size:
                    return f"block {x},{y} of band {b}{level} was not written"
    return None


def _read_blocks(ds, every: bool) -> None:
    """Decode the last block row (the last data written), or every block row with ``every``."""
    bh = ds.block_shapes[0][0]
    last = ((ds.height - 1) // bh) * bh
    for row in range(0, ds.height, bh) if every else [last]:
        ds.read(window=Window(0, row, ds.width, min(bh, ds.height - row)))


def verify_geotiff(
    path: str | os.PathLike, grid: Grid, count: int, dtype: str, every_block: bool = False
) -> str | None:
    """Reopen a just-written GeoTIFF; None when it is whole, else what is wrong (one phrase).

    Checks the grid, band count and type; that every block of every band and overview has
    bytes in the file (the block index: milliseconds); decodes the last block row of the full
    resolution and the whole smallest overview (catching a truncated tail). ``every_block``
    decodes everything (about +40 % of the write time for a 4000 x 4000 float32 output, against
    about +6 % for the default).
    """
    try:
        return _verify_geotiff(Path(path), grid, count, dtype, every_block)
    except (*GDAL_ERRORS, OSError) as exc:
        return f"it does not read back ({_gdal_reason(exc)})"


def _verify_geotiff(path: Path, grid: Grid, count: int, dtype: str, every_block: bool) -> str | None:
    size = os.path.getsize(path)
    with rasterio.open(path) as ds:
        if (ds.width, ds.height, ds.count) != (grid.width, grid.height, count):
            return f"it reads back as {ds.count} x {ds.height} x {ds.width}"
        if set(ds.dtypes) != {dtype}:
            return f"it reads back as {ds.dtypes[0]}, not {dtype}"
        if ds.crs != grid.crs or not ds.transform.almost_equals(grid.transform):
            return "its georeferencing did not survive"
        levels = len(ds.overviews(1))
        problem = _check_block_index(ds, size, "")
        if problem:
            return problem
        _read_blocks(ds, every_block)
    for k in range(levels):
        with rasterio.open(path, overview_level=k) as ov:
            problem = _check_block_index(ov, size, f" of overview {k + 1}")
            if problem:
                return problem
            if k == levels - 1 or every_block:
                _read_blocks(ov, True)
    return None


class RasterWriter:
    """Writes a GeoTIFF on a given grid, atomically.

    Data goes to a hidden temporary file beside the target; on success the file gets overviews
    (and a COG layout), is closed, checked (:func:`verify_geotiff`), flushed to the disk and
    renamed over the target. Every GDAL call runs inside :func:`gdal_errors`, so a failure GDAL
    only reports to its handler (a full disk found while flushing its cache) is noticed and
    nothing is printed. On any exception or failed check the temporary file is deleted and the
    target is untouched; a full disk is ``cannot write PATH: no space left on device``.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        grid: Grid,
        count: int,
        dtype: str,
        nodata: float | None = None,
        descriptions: Sequence[str] | None = None,
        tags: dict[str, str] | None = None,
        inputs: Iterable[str | os.PathLike] = (),
        options: WriteOptions | None = None,
        photometric: str = "minisblack",
    ) -> None:
        self.path = check_output_path(path, inputs)
        options = options or WriteOptions()
        #: "minisblack" (default): every band is data, so a 3- or 4-band uint8 output (masks of
        #: three or four entities) is never taken for RGB(A); "rgb" for imagery.
        self.photometric = photometric
        self.grid, self.count, self.dtype = grid, count, np.dtype(dtype).name
        self.nodata, self.options = nodata, options
        self.descriptions = list(descriptions or [])
        self.tags = dict(tags or {})
        if self.descriptions and len(self.descriptions) != count:
            raise OutputError(f"{len(self.descriptions)} band names for {count} bands")
        self._tmp = temp_beside(self.path, ".partial.tif")
        self._ds = None
        with gdal_errors() as messages:
            try:
                self._ds = rasterio.open(self._tmp, "w", **self._profile())
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)

    def _profile(self) -> dict:
        g, o = self.grid, self.options
        block = o.blocksize
        tiled = g.width >= block and g.height >= block
        compress = o.intermediate_compress if (o.cog and tiled) else o.compress
        profile = dict(
            driver="GTiff",
            width=g.width,
            height=g.height,
            count=self.count,
            dtype=self.dtype,
            crs=g.crs,
            transform=g.transform,
            nodata=self.nodata,
            compress=compress,
            BIGTIFF="IF_SAFER",
            num_threads=o.threads,
            photometric=self.photometric,
        )
        if compress.lower() in ("deflate", "zstd", "lzw"):
            profile["predictor"] = 3 if np.dtype(self.dtype).kind == "f" else 2
        if compress.lower() == "deflate":
            profile["zlevel"] = o.zlevel
        if compress.lower() == "zstd":
            profile["zstd_level"] = o.zstd_level
        if tiled:
            profile.update(tiled=True, blockxsize=block, blockysize=block)
        return profile

    @property
    def block_rows(self) -> int:
        """Rows per output block: flushing whole block rows keeps GDAL's cache small."""
        return self.options.blocksize if self._profile().get("tiled") else 1

    def _fail(self, exc: BaseException | None, messages: Sequence[str] = ()) -> NoReturn:
        """Delete the temporary file and raise the one-line OutputError for this failure.

        The reason is worked out first, while the temporary file still shows how far it got
        (a size limit) and the disk how full it is.
        """
        err = output_error(self.path, exc, messages, self._tmp)
        self._discard()
        raise err from None

    def write(self, data: np.ndarray, row_off: int, col_off: int = 0) -> None:
        """Write (count, h, w) or (h, w) data at an offset."""
        if data.ndim == 2:
            data = data[None]
        window = Window(col_off, row_off, data.shape[2], data.shape[1])
        assert self._ds is not None  # opened by __init__ (or it raised)
        with gdal_errors() as messages:
            try:
                self._ds.write(data.astype(self.dtype, copy=False), window=window)
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)
            if _write_failed(messages):
                self._fail(None, messages)

    def _finish(self) -> None:  # noqa: C901
        """Descriptions, tags, close; overviews; COG rewrite; verify; flush and rename.

        The data is closed (GDAL's block cache flushed, where a full disk usually shows) and
        checked *before* overviews are built on the reopened file: GDAL 3.6 building overviews
        on a dataset whose flush has just failed dereferences a dead TIFF handle and crashes
        the process (seen with the disk full a few KB into the file).
        """
        ds = self._ds
        assert ds is not None  # opened by __init__ (or it raised)
        o = self.options
        factors = overview_factors(self.grid.width, self.grid.height, o.blocksize)
        with gdal_errors() as messages:
            try:
                for i, name in enumerate(self.descriptions, start=1):
                    ds.set_band_description(i, name)
                if self.tags:
                    ds.update_tags(**self.tags)
                ds.close()
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)
            if _write_failed(messages):
                self._fail(None, messages)
            try:
                if o.overviews and factors and not o.cog:
                    self._add_overviews(factors)
                if o.cog and self._profile().get("tiled"):
                    self._to_cog(bool(factors) and o.overviews)
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)
            if _write_failed(messages):
                self._fail(None, messages)
            problem = verify_geotiff(self._tmp, self.grid, self.count, self.dtype, every_block=o.verify_every_block)
            if problem:
                self._fail(None, [f"incomplete file: {problem}", *messages])
        try:
            publish(self._tmp, self.path)
        except OSError as exc:
            self._fail(exc)

    def _add_overviews(self, factors: list[int]) -> None:
        """Build internal overviews in the closed temporary file (reopened for update)."""
        o = self.options
        with rasterio.open(self._tmp, "r+", num_threads=o.threads) as ds:
            ds.build_overviews(factors, o.overview_resampling)
            ds.update_tags(ns="rio_overview", resampling=o.overview_resampling.name)

    def _to_cog(self, overviews: bool) -> None:
        """Rewrite the finished temporary file in COG layout (streams through GDAL)."""
        from rasterio.shutil import copy as rio_copy

        o = self.options
        cog_tmp = temp_beside(self.path, ".cog.tif")
        try:
            opts = dict(
                driver="COG",
                blocksize=o.blocksize,
                compress=o.compress.upper(),
                overviews="AUTO" if overviews else "NONE",
                bigtiff="IF_SAFER",
                overview_resampling=o.overview_resampling.name.upper(),
                num_threads=o.threads,
            )
            if o.compress.lower() in ("deflate", "zstd", "lzw"):
                opts["predictor"] = "YES"
            if o.compress.lower() == "deflate":
                opts["level"] = o.zlevel
            if o.compress.lower() == "zstd":
                opts["level"] = o.zstd_level
            rio_copy(self._tmp, cog_tmp, **opts)
            os.replace(cog_tmp, self._tmp)
        except BaseException:
            discard(cog_tmp, (".aux.xml",))
            raise

    def _discard(self) -> None:
        """Close (GDAL's flush errors silenced) and delete the temporary file and its sidecars."""
        if self._ds is not None and not self._ds.closed:
            with gdal_errors():
                try:
                    self._ds.close()
                except (*GDAL_ERRORS, OSError):
                    pass  # already failing; the file is deleted below
        discard(self._tmp, (".aux.xml",))

    def __enter__(self) -> RasterWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is not None:
            self._discard()
            return
        try:
            self._finish()
        except BaseException:
            self._discard()
            raise


def overview_factors(width: int, height: int, blocksize: int = 512) -> list[int]:
    """2, 4, 8 ... until the smallest overview fits in one block."""
    factors, f = [], 2
    while max(width, height) / f >= blocksize / 2 and max(width, height) > blocksize:
        factors.append(f)
        f *= 2
    return factors


def write_array(
    path: str | os.PathLike,
    data: np.ndarray,
    grid: Grid,
    nodata: float | None = None,
    descriptions: Sequence[str] | None = None,
    tags: dict[str, str] | None = None,
    inputs: Iterable[str | os.PathLike] = (),
    options: WriteOptions | None = None,
    photometric: str = "minisblack",
) -> Path:
    """Write a whole in-memory array (count, H, W) or (H, W); for small results and tests."""
    arr = data[None] if data.ndim == 2 else data
    with RasterWriter(
        path,
        grid,
        arr.shape[0],
        arr.dtype.name,
        nodata=nodata,
        descriptions=descriptions,
        tags=tags,
        inputs=inputs,
        options=options,
        photometric=photometric,
    ) as w:
        w.write(arr, 0)
    return Path(path)
