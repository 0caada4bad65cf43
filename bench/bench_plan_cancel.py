"""How fast `overseec plan` stops on Ctrl-C, with the compiled kernel and with the fallback planner.

    .venv/bin/python bench/bench_plan_cancel.py [--side 6000] [--at 1 2 4 8]

Writes a side x side random costmap (1 m pixels, UTM) to a temporary folder, starts `overseec plan`
corner to corner (with OVERSEEC_PLANNER=kernel and =fallback), sends SIGINT after each delay in
``--at`` and prints how long the process took to exit after the signal (issue 33 rule 5: within
a second, whatever phase the run is in: reading, building the fallback's search, searching). A
run that finished before the signal says so. Wall-clock figures on a shared machine: read the
spread, not the last digit.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def write_costmap(path: Path, side: int) -> None:
    """A seeded random costmap in [0.1, 0.9], written in 512-row strips (never the whole array twice)."""
    import rasterio
    from rasterio.transform import from_origin
    from rasterio.windows import Window

    rng = np.random.default_rng(0)
    profile = dict(driver="GTiff", width=side, height=side, count=1, dtype="float32", crs="EPSG:32633")
    profile.update(transform=from_origin(500_000, 5_000_000, 1, 1), tiled=True, blockxsize=512, blockysize=512)
    with rasterio.open(path, "w", **profile) as ds:
        for r0 in range(0, side, 512):
            rows = min(512, side - r0)
            strip = (0.1 + 0.8 * rng.random((rows, side))).astype(np.float32)
            ds.write(strip, 1, window=Window(0, r0, side, rows))


def stop_after(costmap: Path, side: int, planner: str, at: float, out: Path) -> str:
    """One run stopped by SIGINT ``at`` seconds in: how it ended and how long after the signal."""
    exe = Path(sys.prefix) / "bin" / "overseec"
    argv = [str(exe), "plan", str(costmap), "--start", "500000.5", "4999999.5"]
    argv += ["--goal", str(500_000 + side - 0.5), str(5_000_000 - side + 0.5), "--out", str(out), "-q"]
    proc = subprocess.Popen(
        argv, env={**os.environ, "OVERSEEC_PLANNER": planner}, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    time.sleep(at)
    if proc.poll() is not None:
        return f"finished before the signal (exit {proc.returncode})"
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=600)
    return f"exit {proc.returncode} {time.monotonic() - sent:5.2f} s after SIGINT"


def main(argv: list[str] | None = None) -> int:
    """Write the costmap, stop each planner at each delay, print the figures."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--side", type=int, default=6000, help="costmap side in pixels (default 6000)")
    ap.add_argument("--at", type=float, nargs="+", default=[1.0, 2.0, 4.0, 8.0], help="seconds before SIGINT")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="overseec-cancel-") as tmp:
        costmap = Path(tmp) / "costmap.tif"
        write_costmap(costmap, args.side)
        print(f"{args.side}² costmap; SIGINT after each delay, time to exit after it:")
        for planner in ("kernel", "fallback"):
            for at in args.at:
                ended = stop_after(costmap, args.side, planner, at, Path(tmp) / "p.geojson")
                print(f"  {planner:8s} at {at:4.1f} s: {ended}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
