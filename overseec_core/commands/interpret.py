"""`overseec interpret PROMPT`: entities, preferences, hierarchy, cues and the cost program.

Offline (deterministic rules, no network) unless an LLM is given with --llm-url/--llm-model or
OVERSEEC_LLM_URL/OVERSEEC_LLM_MODEL. --json prints the stable document other tools read
(`overseec segment --entities-json`, the QGIS plugin): entities (name, geometry, prompts),
preferences (entity, rank 1 = best, weight = cost level, lower = preferred, lethal, prior, band:
preferred / neutral / prior / avoided / lethal), hierarchy ([child,
parent]), cues, program, unparsed (what was not understood), source and notes.
"""

from __future__ import annotations

import argparse
import sys

from overseec_core import runfiles
from overseec_core.commands import output_folders, print_json, recorded_args
from overseec_core.commands.options import add_llm_options, add_priors_options
from overseec_core.errors import InputError
from overseec_core.interpret.priors import resolve_priors
from overseec_core.interpret.stage import run_interpret
from overseec_core.limits import MAX_PROMPT_BYTES, read_text_limited
from overseec_core.progress import Progress
from overseec_core.schema import Interpretation


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `interpret` subcommand: the prompt (argument, --prompt or --prompt-file), the
    outputs, priors and LLM options."""
    p = sub.add_parser(
        "interpret",
        help="turn a mission prompt into entities, preferences and a cost program",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "prompt",
        nargs="?",
        metavar="PROMPT",
        help='the mission prompt, e.g. "prefer roads, avoid water" (or --prompt TEXT, or --prompt-file FILE)',
    )
    p.add_argument(
        "--prompt",
        dest="prompt_option",
        metavar="TEXT",
        help="the mission prompt, as `run`, `costmap` and `compare` take it (instead of the PROMPT argument)",
    )
    p.add_argument("--prompt-file", metavar="FILE", help="read the prompt from a file ('-' = stdin)")
    p.add_argument("--offline", action="store_true", help="use the offline interpreter (no LLM)")
    p.add_argument(
        "--terrain",
        action="store_true",
        help="the costmap will have a DEM (--dem): the LLM may read slope and roughness",
    )
    p.add_argument("--json", action="store_true", help="print the JSON document")
    p.add_argument("--out", metavar="FILE", help="also write the JSON document to FILE")
    p.add_argument(
        "--run-dir",
        metavar="DIR",
        help=f"record the interpretation in a run directory ({runfiles.INTERPRETATION} + manifest)",
    )
    add_priors_options(p)
    add_llm_options(p)
    p.set_defaults(func=run)


def read_prompt(args: argparse.Namespace) -> str:
    """The prompt from the argument, --prompt or --prompt-file (exactly one)."""
    given = [
        name
        for name, value in (
            ("the PROMPT argument", args.prompt),
            ("--prompt", getattr(args, "prompt_option", None)),
            ("--prompt-file", args.prompt_file),
        )
        if value is not None
    ]
    if len(given) != 1:
        why = "no prompt" if not given else f"both {given[0]} and {given[1]}"
        raise InputError(f"{why}: give the prompt once, as an argument, with --prompt TEXT or with --prompt-file FILE")
    if getattr(args, "prompt_option", None) is not None:
        return args.prompt_option
    if args.prompt is not None:
        return args.prompt
    if args.prompt_file == "-":
        text = sys.stdin.read(MAX_PROMPT_BYTES + 1)
        if len(text) > MAX_PROMPT_BYTES:
            raise InputError(f"--prompt-file -: the prompt is longer than {MAX_PROMPT_BYTES // 1024} KiB")
        return text
    return read_text_limited(args.prompt_file, MAX_PROMPT_BYTES, "--prompt-file")


def _cue_text(c) -> str:
    metres = f" {c.metres:g} m" if c.metres is not None else ""
    return {
        "centre": f"centre of {c.entity}",
        "side": f"side of {c.entity}",
        "near": f"within{metres} of {c.entity}",
        "far": f"at least{metres} from {c.entity}",
        "unless_near": f"{c.entity}: not within{metres} of {c.other}",
        "if_near": f"{c.entity}: only within{metres} of {c.other}",
        "no_cross": f"never cross {c.entity} (crossed once, at the cheapest place, only if it separates the points)",
    }.get(c.kind, c.kind)


def summary(it: Interpretation) -> str:
    """A readable table of an interpretation."""
    geom = {e.name: e.geometry for e in it.entities}
    width = max([len("entity")] + [len(p.entity) for p in it.preferences])
    lines = [f"source     {it.source}", ""]
    lines.append(f"{'entity':<{width}}  geometry  rank  level  meaning")
    for p in sorted(it.preferences, key=lambda p: (p.rank, p.entity)):
        lines.append(
            f"{p.entity:<{width}}  {geom.get(p.entity, '?'):<8}  {p.rank:>4}  "
            f"{'-' if p.lethal else f'{p.weight:.2f}':>5}  {p.band}"
        )
    lines.append("")
    lines.append("hierarchy  " + ("; ".join(f"{c} inside {p}" for c, p in it.hierarchy) or "none"))
    lines.append("cues       " + ("; ".join(_cue_text(c) for c in it.cues) or "none"))
    lines.append("unparsed   " + ("; ".join(repr(u) for u in it.unparsed) or "none"))
    for i, note in enumerate(it.notes):
        lines.append(("notes      " if i == 0 else "           ") + note)
    lines += ["", "cost program:", it.program.rstrip()]
    return "\n".join(lines)


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `interpret` (interpret.stage.run_interpret; writes --out and --run-dir when given);
    prints the summary of entities, preferences and program (or the JSON)."""
    prompt = read_prompt(args)
    with output_folders(args.out):
        result = run_interpret(
            prompt,
            offline=args.offline or None,
            llm_url=args.llm_url,
            llm_model=args.llm_model,
            llm_key_env=args.llm_key_env,
            llm_timeout=args.llm_timeout,
            llm_retries=args.llm_retries,
            llm_fallback_offline=args.llm_fallback_offline,
            out=args.out,
            run_dir=args.run_dir,
            progress=progress,
            command_args=recorded_args(args),
            priors=resolve_priors(args.priors, enabled=not args.no_priors),
            terrain=args.terrain,
        )
    if args.json:
        print_json(args, result.to_json())
    else:
        print(summary(result))
    return 0
