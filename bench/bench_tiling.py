"""Benchmark: stream a large RGB GeoTIFF through the tiling engine with an identity model.

Prints wall time, Mpx/s and peak RSS for overseec (read tiles -> model -> Hann blend -> streamed
tiled/compressed write -> internal overviews) next to, in the same run on the same file,
rasterio alone reading and writing it block by block (the source's own profile), with and
without a rewrite into COG layout (what `--cog` adds). Each variant runs in a fresh process so its peak RSS is its own.

    .venv/bin/python bench/bench_tiling.py                 # 20000 x 20000, 512 px tiles, 64 overlap
    .venv/bin/python bench/bench_tiling.py --size 4000     # quick check
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("GDAL_CACHEMAX", "256")
REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))


def make_input(path: Path, size: int, seed: int = 0) -> None:
    """A textured RGB scene written in 512-row strips (never the whole image in memory)."""
    import rasterio
    from rasterio.transform import from_origin

    if path.exists():
        return
    rng = np.random.default_rng(seed)
    tmp = path.with_suffix(".partial.tif")
    profile = dict(
        driver="GTiff",
        width=size,
        height=size,
        count=3,
        dtype="uint8",
        crs="EPSG:32633",
        transform=from_origin(500000, 5000000, 0.5, 0.5),
        tiled=True,
        blockxsize=512,
        blockysize=512,
        compress="deflate",
        predictor=2,
    )
    cols = np.arange(size, dtype=np.float32)
    with rasterio.open(tmp, "w", **profile) as ds:
        for r0 in range(0, size, 512):
            rows = np.arange(r0, min(size, r0 + 512), dtype=np.float32)[:, None]
            base = 100 + 60 * np.sin(cols / 300.0) * np.cos(rows / 410.0)
            noise = rng.integers(-12, 13, (3, len(rows), size), dtype=np.int16)
            strip = np.clip(base[None] + noise + np.array([0, 20, -20])[:, None, None], 0, 255)
            ds.write(strip.astype(np.uint8), window=((r0, r0 + len(rows)), (0, size)))
    os.replace(tmp, path)


def child_reference(src: Path, dst: Path, cog: bool, zstd: bool = False) -> dict:
    """Child process: copy ``src`` to ``dst`` block by block with rasterio (optionally zstd, or
    then to a COG): the baseline overseec's streaming is measured against. Returns its seconds."""
    import rasterio
    from rasterio.shutil import copy as rio_copy

    t0 = time.perf_counter()
    with rasterio.open(src) as a:
        profile = a.profile
        if zstd:  # the codec overseec writes with, so the ratio compares like with like
            profile.update(compress="zstd", zstd_level=1, predictor=2, num_threads="ALL_CPUS")
        with rasterio.open(dst, "w", **profile) as b:
            for _, window in a.block_windows(1):
                b.write(a.read(window=window), window=window)
    t_copy = time.perf_counter() - t0
    if cog:
        cog_path = dst.with_suffix(".cog.tif")
        rio_copy(
            dst,
            cog_path,
            driver="COG",
            compress="DEFLATE",
            predictor="YES",
            blocksize=512,
            overviews="AUTO",
            overview_resampling="AVERAGE",
            bigtiff="IF_SAFER",
        )
        os.replace(cog_path, dst)
    return {"seconds": time.perf_counter() - t0, "seconds_copy": t_copy}


def child_overseec(src: Path, dst: Path, tile: int, overlap: int, batch: int) -> dict:
    """Child process: stream ``src`` through the tiling engine with an identity model into ``dst``
    (Hann blend, tiled write); returns its seconds and the engine's statistics."""
    from overseec_core.io.read import RasterSource
    from overseec_core.io.write import RasterWriter
    from overseec_core.locate.tiling import TileGrid, stream_predict, writer_sink

    def identity(rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        return np.moveaxis(rgb, -1, 1).astype(np.float32)

    t0 = time.perf_counter()
    with RasterSource(src) as source:
        g = source.grid
        grid = TileGrid(g.width, g.height, tile, overlap)
        writer = RasterWriter(dst, g, 3, "uint8", descriptions=["red", "green", "blue"])
        with writer:
            stats = stream_predict(
                source,
                identity,
                writer_sink(writer),
                grid,
                3,
                blend="hann",
                batch_size=batch,
                flush_rows=writer.block_rows,
            )
            t_stream = time.perf_counter() - t0
    return {
        "seconds": time.perf_counter() - t0,
        "seconds_stream": t_stream,
        "tiles": stats.tiles,
        "seconds_reading": stats.seconds_reading,
        "seconds_model": stats.seconds_predicting,
        "peak_buffer_rows": stats.peak_buffer_rows,
    }


def peak_rss_mb() -> float:
    """This process's own peak RSS (VmHWM). ru_maxrss would include the parent's peak: Linux keeps
    the high-water mark across fork+exec."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def run_child(args: list[str]) -> dict:
    """Run this script as a child with ``args`` (so its peak RSS is its own) and return the JSON
    line it prints last."""
    out = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    """Prepare the input, run the three rasterio baselines and overseec's stream each in a child
    process, and print wall time, Mpx/s, peak RSS and the ratios."""
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--size", type=int, default=20000)
    p.add_argument("--tile", type=int, default=512)
    p.add_argument("--overlap", type=int, default=64)
    p.add_argument("--batch", type=int, default=4)
    p.add_argument("--workdir", type=Path, default=REPO / "bench" / "out")
    p.add_argument("--child", choices=["reference", "reference-zstd", "reference-cog", "overseec"])
    p.add_argument("--src", type=Path)
    p.add_argument("--dst", type=Path)
    a = p.parse_args()

    if a.child:
        if a.child == "overseec":
            result = child_overseec(a.src, a.dst, a.tile, a.overlap, a.batch)
        else:
            result = child_reference(a.src, a.dst, cog=a.child == "reference-cog", zstd=a.child == "reference-zstd")
        result["peak_rss_mb"] = peak_rss_mb()
        print(json.dumps(result))
        return

    a.workdir.mkdir(parents=True, exist_ok=True)
    src = a.workdir / f"bench_rgb_{a.size}.tif"
    t0 = time.perf_counter()
    make_input(src, a.size)
    print(
        f"input: {src} ({a.size} x {a.size} RGB uint8, {src.stat().st_size / 1e6:.0f} MB on disk; "
        f"prepared in {time.perf_counter() - t0:.1f} s)"
    )
    mpx = a.size * a.size / 1e6
    rows = []
    for name, child in (
        ("rasterio block read+write", "reference"),
        ("rasterio block read+write, zstd", "reference-zstd"),
        ("rasterio block read+write + COG", "reference-cog"),
        ("overseec stream (identity, hann)", "overseec"),
    ):
        dst = a.workdir / f"out_{child}.tif"
        dst.unlink(missing_ok=True)
        r = run_child(
            [
                "--child",
                child,
                "--src",
                str(src),
                "--dst",
                str(dst),
                "--tile",
                str(a.tile),
                "--overlap",
                str(a.overlap),
                "--batch",
                str(a.batch),
            ]
        )
        rows.append((name, r))
        dst.unlink(missing_ok=True)
    print(f"\n{'variant':<34} {'wall s':>8} {'Mpx/s':>8} {'peak RSS MB':>12}")
    for name, r in rows:
        print(f"{name:<34} {r['seconds']:>8.1f} {mpx / r['seconds']:>8.1f} {r['peak_rss_mb']:>12.0f}")
    plain, plain_zstd, plain_cog, ours = (r for _, r in rows)
    print(
        f"\noverseec tiles: {ours['tiles']} ({a.tile} px, overlap {a.overlap}); streaming "
        f"{ours['seconds_stream']:.1f} s (reading {ours['seconds_reading']:.1f} s in a prefetch thread, "
        f"model {ours['seconds_model']:.1f} s), overviews {ours['seconds'] - ours['seconds_stream']:.1f} s; "
        f"blend buffer peak {ours['peak_buffer_rows']} rows"
    )
    print(f"ratio overseec / rasterio read+write:       {ours['seconds'] / plain['seconds']:.2f}x (target <= 3x)")
    print(
        f"ratio overseec / rasterio read+write, zstd: {ours['seconds'] / plain_zstd['seconds']:.2f}x "
        "(same codec as overseec)"
    )
    print(f"ratio overseec / rasterio read+write + COG: {ours['seconds'] / plain_cog['seconds']:.2f}x")
    print(f"peak RSS overseec: {ours['peak_rss_mb']:.0f} MB (target < 1024 MB)")


if __name__ == "__main__":
    main()
