"""`overseec info IMAGE`: georeferencing, layout and how the image will be read."""

from __future__ import annotations

import argparse

from overseec_core.commands import print_json
from overseec_core.commands.options import add_read_options
from overseec_core.io.read import read_info
from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `info` subcommand: the image, --json and the read options."""
    p = sub.add_parser("info", help="describe an image: CRS, size, bands, pixel size, read plan", description=__doc__)
    p.add_argument("image", metavar="IMAGE", help="GeoTIFF or any GDAL raster")
    p.add_argument("--json", action="store_true", help="print a JSON document")
    add_read_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `info` (io read_info): print the image's CRS, size, bands, pixel size, extent and read
    plan as aligned lines (or the JSON). Writes nothing."""
    info = read_info(args.image, bands=args.bands, assume_crs=args.assume_crs).to_json()
    if args.json:
        print_json(args, info)
        return 0
    px, py = info["pixel_size_m"]
    rows = [
        ("file", info["path"]),
        ("driver", info["driver"]),
        ("crs", info["crs"] + (" (assumed)" if info["crs_assumed"] else "")),
        ("size", f"{info['width']} x {info['height']} px, {info['count']} band(s) {', '.join(info['dtypes'])}"),
        ("pixel size", f"{px:.4g} m x {py:.4g} m"),
        ("extent", f"{info['width'] * px:.1f} m x {info['height'] * py:.1f} m"),
        ("bounds", ", ".join(repr(float(v)) for v in info["bounds"])),  # full precision: copyable
        ("nodata", "NaN" if info["nodata_is_nan"] else str(info["nodata"])),
        ("alpha band", str(info["alpha_band"] or "none")),
        ("colour interp.", ", ".join(info["colorinterp"])),
        ("overviews", ", ".join(map(str, info["overviews"])) or "none"),
        ("read as", info["read_plan"]["description"]),
    ]
    width = max(len(k) for k, _ in rows)
    for key, value in rows:
        print(f"{key:<{width}}  {value}")
    return 0
