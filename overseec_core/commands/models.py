"""`overseec models`: which segmentation models are usable offline, fetch them, find them.

    overseec models list                      known checkpoints, each segmenter's default, whether cached
    overseec models download CIDAS/clipseg-rd64-refined   (needs network; short timeouts)
    overseec models path facebook/sam-vit-base            local folder to copy to offline machines

`overseec segment` never downloads: on an offline machine copy a downloaded folder (`models path`)
and pass it with --model (the segmenter's; --clipseg-model for CLIPSeg) / --sam-model. `models list`
marks each segmenter's default model (`overseec segment --segmenter NAME` uses it without --model).
"""

from __future__ import annotations

import argparse
import importlib.util

from overseec_core import defaults
from overseec_core.commands import print_json
from overseec_core.errors import ModelError
from overseec_core.progress import Progress

KINDS = defaults.MODEL_KINDS


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `models` subcommand and its verbs: list, download, path."""
    p = sub.add_parser(
        "models",
        help="list, download or locate the segmentation models",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    verbs = p.add_subparsers(dest="verb", metavar="VERB")
    verbs.required = True
    ls = verbs.add_parser("list", help="known models and whether each is available offline")
    ls.add_argument("--json", action="store_true", help="print a JSON document")
    dl = verbs.add_parser("download", help="download a model into the Hugging Face cache")
    dl.add_argument("name", metavar="NAME", help="hub id, e.g. CIDAS/clipseg-rd64-refined")
    dl.add_argument("--kind", choices=KINDS, help="check it is this kind of model (default: guessed)")
    dl.add_argument("--timeout", type=float, default=20.0, metavar="SECONDS", help="network timeout (default 20 s)")
    pa = verbs.add_parser("path", help="print the local folder of a model (cached hub id or directory)")
    pa.add_argument("name", metavar="NAME", help="hub id or directory")
    pa.add_argument("--kind", choices=KINDS, help="kind of model (default: guessed)")
    p.set_defaults(func=run)


def guess_kind(name: str) -> str | None:
    """Kind of a known checkpoint, or from its name; None when it cannot be told."""
    from overseec_core.locate.models import KNOWN_MODELS

    for kind, known, _ in KNOWN_MODELS:
        if known.lower() == name.lower():
            return kind
    lower = name.lower()
    if "clipseg" in lower:
        return "clipseg"
    if "sam" in lower.rsplit("/", 1)[-1]:
        return "sam"
    return None


def resolve_any(name: str, kind: str | None):
    """Resolve as the given kind, else as each kind in turn (the first that works)."""
    from overseec_core.locate.models import resolve_model

    guessed = guess_kind(name)
    kinds = [kind] if kind else ([guessed] if guessed else list(KINDS))
    error: ModelError | None = None
    for k in kinds:
        try:
            return resolve_model(name, k)
        except ModelError as exc:
            error = error or exc
    assert error is not None
    raise error


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `models`: list the known models and whether each is cached, download one into the
    Hugging Face cache, or print a model's local folder."""
    from overseec_core.locate.models import download_model, list_models

    if args.verb == "list":
        rows = list_models()
        if args.json:
            print_json(args, [r.to_json() for r in rows])
            return 0
        width = max(len(r.name) for r in rows)
        for r in rows:
            state = f"available  {r.path}" if r.available else "missing    `overseec models download " + r.name + "`"
            default = f"  (default of --segmenter {r.segmenter})" if r.segmenter else ""
            print(f"{r.kind:<10} {r.name:<{width}}  {state}{default}")
        if not all(r.available for r in rows) and importlib.util.find_spec("huggingface_hub") is None:
            from overseec_core.install import detect

            print(f"(downloading needs the models extra, not installed here: {detect().extra_advice('models')})")
        return 0
    if args.verb == "download":
        kind = args.kind or guess_kind(args.name)
        progress.message(f"downloading {args.name} into the Hugging Face cache ...")
        path = download_model(args.name, kind, timeout_s=args.timeout)
        print(path)
        return 0
    ref = resolve_any(args.name, args.kind)
    print(ref.path)
    return 0
