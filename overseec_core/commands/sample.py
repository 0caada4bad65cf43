"""`overseec sample`: write the procedural sample scene (image, labels, classes, reference route)."""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `sample` subcommand: output folder, size and seed."""
    p = sub.add_parser("sample", help="generate the procedural sample scene", description=__doc__)
    p.add_argument("--out", type=Path, required=True, metavar="DIR", help="folder (created)")
    p.add_argument("--size", type=int, default=1024, metavar="PX", help="side in pixels (default 1024)")
    p.add_argument("--seed", type=int, default=0, metavar="N", help="random seed: same seed, same pixels (default 0)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `sample` (sample.generate: image, labels, classes, reference paths and meta in --out);
    prints the written files."""
    from overseec_core.errors import InputError
    from overseec_core.sample import generate

    if not 64 <= args.size <= 8192:
        raise InputError(f"--size must be in 64..8192, got {args.size}")
    scene = generate(args.out, size=args.size, seed=args.seed)
    for path in (scene.image, scene.labels, scene.classes, scene.reference, scene.meta):
        print(path)
    return 0
