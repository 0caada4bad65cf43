"""Score a held-out brief set (issue 31): reading scores per kind and construct, and route checks.

    .venv/bin/python bench/mission_briefs_report.py --set 1 [--no-routes] [--baseline B] [--json OUT] [-v]

Prints, for the set: the share of expectations that hold per score (order, forbidden, cues,
clauses) and per construct, and the share of end-to-end routes that pass (8 seeded pairs per
brief and scene; skipped for scenes missing from ../shared/scenes). Score a new set ONCE before
changing anything for it: that first-contact figure is the one that counts.

Routes are scored twice (``--baseline both``): against the flat route, as the contract
(tests/mission_briefs.py) words it, and against the route of the same brief without its words on
the checked class (its other rules and the priors held), which asks what those words changed --
a route that skirts a pond the priors avoid is nearer the water than a flat route straight across
it, whatever the brief says about the water. Both figures are reported; neither replaces the
other.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from tests import mission_briefs as mb
from tests import mission_briefs_routes as mbr

#: The relation key under which route checks on a class absent from their scene are counted.
NOT_SCORED = "~not scored"
#: What a route is compared with (tests.mission_briefs_routes.RouteHarness.check).
BASELINES = {
    "flat": "vs the flat route: the contract",
    "ablated": "vs the brief without its words on the class; no route right where none exists",
}


def _score_routes(harness, briefs, baseline: str, verbose: bool, record: list) -> tuple[list, dict]:
    """Route verdicts of every brief against one baseline: (passed, total) and per relation."""
    routes = [0, 0]
    route_rel: dict = defaultdict(lambda: [0, 0])
    absent: set[str] = set()
    for b in briefs:
        for r in b.routes:
            if not mbr.scene_available(r.scene):
                continue
            present = mbr.class_present(r.scene, r.cls)
            unreachable = present and r.relation in ("more_on", "beside") and not mbr.class_within_reach(r.scene, r.cls)
            if not present or unreachable:  # nothing to measure (tests/mission_briefs.py)
                absent.add(f"{r.scene} {r.cls}" + (" (out of every pair's reach)" if unreachable else ""))
                route_rel[NOT_SCORED][1] += mbr.N_PAIRS
                continue
            try:
                verdicts = harness.check(b, r, baseline)
            except Exception as exc:  # a brief the pipeline refuses fails all its routes
                verdicts = [f"{type(exc).__name__}: {exc}"] * mbr.N_PAIRS
            for v in verdicts:
                routes[1] += 1
                route_rel[r.relation][1] += 1
                if v is None:
                    routes[0] += 1
                    route_rel[r.relation][0] += 1
            bad = [v for v in verdicts if v is not None]
            if bad and verbose:
                print(f"ROUTE FAIL ({baseline}) {b.id} {r}: {len(bad)}/{len(verdicts)}: {bad[0]}")
            route = [r.scene, r.relation, r.cls, r.metres]
            record.append({"id": b.id, "route": route, "baseline": baseline, "verdicts": verdicts})
    if absent and verbose:
        print(f"not scored ({baseline}): routes on a class the scene lacks: {', '.join(sorted(absent))}")
    return routes, route_rel


def main(argv: list[str] | None = None) -> int:  # noqa: C901
    """Score one set and print the figures (see the module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--set", type=int, required=True, help="brief set number (tests/mission_briefs_setN.py)")
    ap.add_argument("--no-routes", action="store_true", help="reading checks only")
    ap.add_argument("--json", type=Path, help="write every verdict to this JSON file")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every failure")
    ap.add_argument(
        "--baseline",
        choices=("flat", "ablated", "both"),
        default="both",
        help="what each route is compared with: the flat route (the contract), the brief without its words on "
        "the class, or both (default)",
    )
    args = ap.parse_args(argv)
    module = importlib.import_module(f"tests.mission_briefs_set{args.set}")
    briefs = [b for b in module.BRIEFS if b.id not in getattr(module, "DOUBTFUL", {})]
    t0 = time.perf_counter()
    score = defaultdict(lambda: [0, 0])
    construct = defaultdict(lambda: [0, 0])
    brief_pass = 0
    record = []
    for b in briefs:
        verdicts = mb.check_brief(b)
        ok_all = True
        for exp, why in verdicts:
            s = mb.SCORES[exp[0]]
            score[s][1] += 1
            construct[b.construct][1] += 1
            if why is None:
                score[s][0] += 1
                construct[b.construct][0] += 1
            else:
                ok_all = False
                if args.verbose:
                    print(f"FAIL {b.id}: {exp}: {why}")
        brief_pass += ok_all
        record.append({"id": b.id, "prompt": b.prompt, "reading": [[list(e), w] for e, w in verdicts]})
    scored = {}
    if not args.no_routes:
        harness = mbr.RouteHarness()
        for baseline in ("flat", "ablated") if args.baseline == "both" else (args.baseline,):
            scored[baseline] = _score_routes(harness, briefs, baseline, args.verbose, record)
    print(f"set {args.set}: {len(briefs)} briefs, {brief_pass} read wholly right ({brief_pass / len(briefs):.0%})")
    for s in ("order", "forbidden", "cues", "clauses"):
        ok, n = score[s]
        print(f"  {s:10s} {ok:4d}/{n:<4d} {ok / n if n else float('nan'):.2f}")
    print("  by construct:")
    for c in mb.CONSTRUCTS:
        ok, n = construct[c]
        print(f"    {c:14s} {ok:4d}/{n:<4d} {ok / n if n else float('nan'):.2f}")
    for baseline, (routes, route_rel) in scored.items():
        if routes[1]:
            print(f"  routes     {routes[0]:4d}/{routes[1]:<4d} {routes[0] / routes[1]:.2f}  ({BASELINES[baseline]})")
            for rel, (ok, n) in sorted(route_rel.items()):
                if rel == NOT_SCORED:
                    print(f"    ({n} routes not scored: their class is not on the scene or out of every pair's reach)")
                else:
                    print(f"    {rel:14s} {ok:4d}/{n:<4d} {ok / n:.2f}")
    print(f"  ({time.perf_counter() - t0:.0f} s)")
    if args.json:
        args.json.write_text(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
