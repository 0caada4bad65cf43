"""Benchmark: compose a SIZE x SIZE costmap from 6 entity masks (prints figures).

    .venv/bin/python bench/bench_compose.py --size 2000      # quick check
    .venv/bin/python bench/bench_compose.py                  # the issue's 10000 x 10000

Writes a segment-like folder (masks.tif uint8 + probs.tif float32, 6 named bands: road, trail,
grass, baseball field, building, water) block by block, then composes the program synthesised
from preferences with a hierarchy (baseball field inside grass), near(road, 5 m) and a lethal
entity, in a fresh process whose wall time and peak RSS are measured. Target: peak RSS under 2 GB
at 10000 x 10000 (bounded by the block size, not the image).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rasterio.crs import CRS  # noqa: E402
from rasterio.transform import from_origin  # noqa: E402

from overseec_core.io.grid import Grid  # noqa: E402
from overseec_core.io.write import RasterWriter, WriteOptions  # noqa: E402

NAMES = ("road", "trail", "grass", "baseball field", "building", "water")
PIXEL_M = 0.5


def layers_for_rows(r0: int, r1: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Synthetic masks (6, h, w) uint8 and probabilities (6, h, w) float32 for rows r0..r1.

    A road grid every 400 px (12 px wide), trails on diagonals, grass fields with baseball
    fields inside them, building blocks and ponds; smooth probabilities (they compress like real
    ones, unlike noise).
    """
    y, x = np.mgrid[r0:r1, 0:width]
    road = ((y % 400) < 12) | ((x % 400) < 12)
    trail = (np.abs(((x + y) % 600) - 300) < 3) & ~road
    cell_y, cell_x = (y // 400), (x // 400)
    kind = (cell_y * 7 + cell_x * 3) % 5
    inner_y, inner_x = y % 400, x % 400
    block = (inner_y > 30) & (inner_y < 370) & (inner_x > 30) & (inner_x < 370)
    grass = block & (kind <= 1) & ~road & ~trail
    field = grass & ((inner_y - 200) ** 2 + (inner_x - 200) ** 2 < 90**2)
    building = block & (kind == 2) & ((inner_y % 60) < 40) & ((inner_x % 60) < 40)
    water = block & (kind == 3) & ((inner_y - 200) ** 2 + (inner_x - 200) ** 2 < 150**2)
    masks = np.stack([road, trail, grass, field, building, water]).astype(np.uint8)
    smooth = 0.75 + 0.2 * np.sin(x / 97.0) * np.cos(y / 131.0)
    probs = (masks * smooth[None]).astype(np.float32)
    return masks, probs


def make_masks(folder: Path, size: int, rows_per_step: int = 512) -> float:
    """Write the inputs (masks.tif, probs.tif: one band per entity) into ``folder`` in row strips,
    so a 10000 px side never sits in memory; returns the seconds taken."""
    grid = Grid(CRS.from_epsg(32633), from_origin(500000.0, 4000000.0 + size * PIXEL_M, PIXEL_M, PIXEL_M), size, size)
    t0 = time.perf_counter()
    plain = WriteOptions(cog=False, overviews=False)  # inputs only need to be read back
    with (
        RasterWriter(folder / "masks.tif", grid, len(NAMES), "uint8", descriptions=NAMES, options=plain) as mw,
        RasterWriter(folder / "probs.tif", grid, len(NAMES), "float32", descriptions=NAMES, options=plain) as pw,
    ):
        for r0 in range(0, size, rows_per_step):
            r1 = min(r0 + rows_per_step, size)
            masks, probs = layers_for_rows(r0, r1, size)
            mw.write(masks, r0)
            pw.write(probs, r0)
    return time.perf_counter() - t0


def program_text() -> str:
    """The cost program the benchmark composes: fixed preferences (roads best, water lethal), a
    baseball field inside grass and near(road, 5 m), so each kind of operator is timed."""
    from overseec_core.costlang import program_from_interpretation
    from overseec_core.schema import Cue, Preference

    prefs = [
        Preference("road", 1, 0.0),
        Preference("trail", 1, 0.0),
        Preference("grass", 2, 0.4),
        Preference("baseball field", 3, 0.9),
        Preference("building", 4, 1.0),
        Preference("water", 5, 1.0, lethal=True),
    ]
    return program_from_interpretation(NAMES, prefs, [("baseball field", "grass")], [Cue("near", "road", 5.0)])


def compose_child(folder: Path, out: Path, block: int) -> None:
    """Run in a fresh process: compose and report wall time and peak RSS as JSON."""
    from overseec_core.costlang import check_program
    from overseec_core.synthesize.engine import compose_costmap
    from overseec_core.synthesize.layers import MaskDirSource

    t0 = time.perf_counter()
    source = MaskDirSource(folder)
    program = check_program(program_text(), source.names)
    stats = compose_costmap(program, source, out, block_size=block)
    source.close()
    wall = time.perf_counter() - t0
    print(
        json.dumps(
            {
                "wall_s": wall,
                "compose_s": stats.seconds,
                "peak_rss_mb": peak_rss_kb() / 1024,
                "halo": stats.halo,
                "blocks": stats.blocks,
                "mean_cost": stats.mean_cost,
                "lethal_pixels": stats.lethal_pixels,
                "valid_pixels": stats.valid_pixels,
            }
        )
    )


def peak_rss_kb() -> int:
    """This process's peak resident set (kB). VmHWM, not ru_maxrss: on Linux ru_maxrss survives
    exec, so a child would report its parent's peak (the mask generator's) when that is larger."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def main() -> None:
    """Generate (or reuse) the inputs, compose the costmap in a child process (its peak RSS is the
    composition's own) and print wall time, Mpx/s, peak RSS and the costmap's size."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=int, default=10000, help="image side in pixels (default 10000)")
    ap.add_argument("--block", type=int, default=1024, help="composition block side (default 1024)")
    ap.add_argument(
        "--inputs",
        type=Path,
        help="keep the generated masks in this folder and reuse them on the next run "
        "(default: a temporary folder, removed after)",
    )
    ap.add_argument("--child", nargs=2, metavar=("MASKS_DIR", "OUT"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        compose_child(Path(args.child[0]), Path(args.child[1]), args.block)
        return

    with tempfile.TemporaryDirectory() as tmp:
        folder = args.inputs / str(args.size) if args.inputs else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        print(
            f"bench_compose: {args.size} x {args.size} px at {PIXEL_M} m, {len(NAMES)} entities "
            f"({', '.join(NAMES)}), block {args.block}, {os.cpu_count()} CPUs"
        )
        if (folder / "probs.tif").exists():
            print(f"  reusing the inputs in {folder}")
        else:
            gen_s = make_masks(folder, args.size)
            print(f"  inputs written in {gen_s:.1f} s")
        sizes = {p.name: p.stat().st_size for p in (folder / "masks.tif", folder / "probs.tif")}
        print("  inputs: " + ", ".join(f"{k} {v / 2**20:.0f} MiB" for k, v in sorted(sizes.items())))
        out = Path(tmp) / "costmap.tif"
        done = subprocess.run(
            [sys.executable, __file__, "--block", str(args.block), "--child", str(folder), str(out)],
            capture_output=True,
            text=True,
        )
        if done.returncode != 0:
            print(done.stderr, file=sys.stderr)
            raise SystemExit(done.returncode)
        r = json.loads(done.stdout.strip().splitlines()[-1])
        mpx = args.size * args.size / 1e6
        print("  program: hierarchy (baseball field inside grass), near(road, 5 m), water lethal")
        print(f"  halo {r['halo'][0]} x {r['halo'][1]} px, {r['blocks']} blocks")
        print(f"  compose wall time   {r['wall_s']:.1f} s  ({mpx / r['compose_s']:.1f} Mpx/s)")
        print(f"  peak RSS (compose)  {r['peak_rss_mb']:.0f} MiB   (target < 2048 MiB)")
        print(
            f"  costmap {out.stat().st_size / 2**20:.0f} MiB, mean cost {r['mean_cost']:.3f}, "
            f"lethal {100 * r['lethal_pixels'] / r['valid_pixels']:.1f}%"
        )


if __name__ == "__main__":
    main()
