"""Mission briefs (issue 31): held-out briefs, what each must mean, and the route checks on real maps.

A *brief* is a mission prompt as a user would type it, the layer names its costmap is built over,
the reading it must have (measured on layers, never on the interpreter's internal names) and,
where the classes exist on a real ground-truth scene, what its routes must do there.

The brief sets (``tests/mission_briefs_set*.py``) are written WITHOUT reading the interpreter
(``overseec_core/interpret/``), its tests or its corpora, and are scored ONCE before anything is
changed for them (``bench/mission_briefs_report.py --set N``): that first-contact figure is the
one that counts. A set is never edited to make the interpreter pass; a case whose expectation
contradicts the cost-scale contract below is retired in the set's ``DOUBTFUL`` with the reason.

The cost scale: every cell costs [0, 1]; neutral 0.5 (unlabelled ground, unmentioned non-hazards,
anything merely allowed); preferred below 0.5; avoided above; lethal = impassable (only for words
that forbid: off limits, no-go, never enter, stay out of, keep out of, don't go into). Unmentioned
hazards (tree, building, water, railway) sit at "prior" levels in the avoided band. A *hard* rule
(distance rules worded as absolute) makes a keep-out zone: no route enters it where any route can
avoid it, and where none can, the route runs the fewest metres in it.

Expectations (tuples; layer names must be in the brief's ``layers``; "ground" is an unlabelled
cell, probed on a 1 m grid with the layer ``X`` as a 9 m square at a given gap):

Order and level (scored as "order"):
- ``("preferred", L)``: cost(L) < 0.5 and not lethal; ``("neutral", L)``; ``("avoided", L)``:
  cost(L) > 0.5 and not lethal
- ``("below", A, B)``: cost(A) < cost(B) strictly, neither lethal

Forbidden (scored as "forbidden"):
- ``("lethal", L)``: L is impassable; ``("not_lethal", L)``: it is not

Cues (scored as "cues"):
- ``("keep_out", X, m)``: a hard zone of m metres: ground 1 m and (m - 1) m from X is kept out
  (impassable where avoidable), ground at m + max(3, m / 2) metres is not. ``m=None`` when the
  brief gives no number: ground 1 m from X is kept out, ground 60 m away is not
- ``("soft_zone", X, m)``: ground within m metres of X (probed at 1 m and m - 1 m) costs more than
  ground far away (60 m), and is neither kept out nor lethal; ``m=None`` as above (probe at 1 m)
- ``("graded_away", X, m)``: the closer, the dearer: cost(ground 2 m) > cost(ground 8 m) >=
  cost(ground 60 m), nothing kept out; with a number m the ground at m + 5 m costs what ground
  60 m away costs (the fall-off reaches neutral at m)
- ``("graded_toward", X, m)``: the closer, the cheaper: cost(2 m) < cost(8 m) <= cost(60 m), and
  cost(2 m) < 0.5
- ``("beside", X)``: on versus beside: X itself is avoided or lethal, ground 2 m from X is
  preferred (< 0.5), and ground 2 m from X is cheaper than ground 60 m away
- ``("no_cross", L)``: a hard never-cross rule on L (the interpretation's no_cross cue)

Clauses (scored as "clauses"):
- ``("unread", word)``: the reading reports a clause containing ``word`` as not understood
- ``("all_read",)``: no clause of the brief is reported as not understood

Route checks (:class:`Route`, scored per route as "routes"): the brief's costmap is built over the
scene's ground-truth classes (the brief's layer names matched to the scene's class names as the
CLI matches them), 8 seeded start/goal pairs on passable cells are planned, and each route is
compared with the route between the same points on a flat costmap (every cell 0.5: the shortest
path). ``relation`` is one of:

- ``"more_on"`` / ``"less_on"``: the route's share of metres on ``cls`` is >= / <= the flat
  route's (and over the 8 routes strictly more / less in total)
- ``"zero_on"``: no metre on ``cls`` (a forbidden class); where no route avoids it (a
  never-cross rule on a class that separates the points, checked with the independent
  planner), its metres on ``cls`` are the least possible (within 5 %)
- ``"keeps"``: the route's closest approach to ``cls`` is >= ``metres`` wherever a route can keep
  that distance (checked with an independent planner); where none can, its metres within
  ``metres`` of ``cls`` are within 5 % of the least possible
- ``"closer"`` / ``"farther"``: the route's mean distance to ``cls`` (per metre of route) is <= / >=
  the flat route's
- ``"beside"``: less share on ``cls`` than the flat route's and more metres within ``metres`` of
  ``cls`` (but not on it) than the flat route's, in total over the 8 routes

A route check on a class the scene holds no pixel of (a clip's classes.json may name a class
the clip does not show: nb1 has no railway) measures nothing and is not scored; nor is a
"more_on"/"beside" check on a class no seeded pair's route can reach even where the class costs
nothing and all else is neutral (checked with an independent planner: nb2's road is a strip at
the clip's edge). The scorer says how many routes it left out.

The scorer also reports every route check against a second baseline, beside this one (never
instead of it): the route of the same brief without its words on ``cls`` (its other rules and the
priors held), where no route is right when the independent planner finds none without what the
brief forbids, and no metre on ``cls`` is as little as can be for ``less_on``
(``bench/mission_briefs_report.py --baseline``).

Scenes (``scene``) and their ground-truth class names:

- ``"nb1"``, ``"nb2"``: New Brunswick clips, 0.5 m, ~300 x 400 px: building, road, water,
  vegetation, railway (the railway only on nb2; nb2's road is a short stretch few routes meet)
- ``"vegas"``: Las Vegas, ~0.3 m, 1300 x 1300 px: paved road, unpaved road (the unpaved class is
  nearly empty there)
- ``"kampala"``: Kampala, 7.5 cm, 3072 x 2048 px: building (dense informal settlement)
- ``"massachusetts"``: 1 m, 1182 x 901 px: building (suburb)
- ``"neon"``: Florida forest plot, 10 cm, 400 x 400 px: tree (crowns)
- ``"sample"``: the bundled sample, 0.5 m, 1024 x 1024 px: grass, road, trail, tree, water, building,
  baseball field
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

#: What a brief exercises (issue 31's constructs, plus the plain readings every brief relies on).
CONSTRUCTS: dict[str, str] = {
    "distance_hard": "distance rules worded as absolute: a hard zone of the stated metres",
    "distance_soft": "distance rules worded softly: a soft zone, the number kept",
    "graded_away": "don't go near / keep well away / the further the better: priced by distance",
    "graded_toward": "stay close to / keep within sight of: cheaper the nearer",
    "on_beside": "along X but not on X: X avoided or forbidden, a band beside it preferred",
    "qualified": "qualified classes (paved / unpaved, deciduous / conifer) and excepted sub-areas",
    "terse": "terse and symbolic briefs: 'A > B', 'X: no', 'X fine', typos in multi-word names",
    "permission": "permissions that lift priors, and stay-out wording that forbids",
    "clauses": "every clause accounted for: unread clauses reported, never silently dropped",
}

VOICES = ("analyst", "robot", "field")

#: Expectation kind -> the score it counts towards.
SCORES: dict[str, str] = {
    "preferred": "order",
    "neutral": "order",
    "avoided": "order",
    "below": "order",
    "lethal": "forbidden",
    "not_lethal": "forbidden",
    "keep_out": "cues",
    "soft_zone": "cues",
    "graded_away": "cues",
    "graded_toward": "cues",
    "beside": "cues",
    "no_cross": "cues",
    "unread": "clauses",
    "all_read": "clauses",
}

RELATIONS = ("more_on", "less_on", "zero_on", "keeps", "closer", "farther", "beside")
SCENE_CLASSES: dict[str, tuple[str, ...]] = {
    "nb1": ("building", "road", "water", "vegetation", "railway"),
    "nb2": ("building", "road", "water", "vegetation", "railway"),
    "vegas": ("paved road", "unpaved road"),
    "kampala": ("building",),
    "massachusetts": ("building",),
    "neon": ("tree",),
    "sample": ("grass", "road", "trail", "tree", "water", "building", "baseball field"),
}


@dataclass(frozen=True)
class Route:
    """A route check of a brief on one real scene (see the module docstring)."""

    scene: str
    relation: str
    cls: str
    metres: float | None = None


@dataclass(frozen=True)
class Brief:
    """A held-out mission brief, its layers, the reading it must have and its route checks."""

    prompt: str
    voice: str
    construct: str
    layers: tuple[str, ...]
    expect: tuple[tuple, ...]
    routes: tuple[Route, ...] = ()
    #: Why the expectation is what it is, where that is not obvious.
    why: str = ""

    @property
    def id(self) -> str:
        words = re.sub(r"[^a-z0-9 ]+", "", self.prompt.lower()).split()
        return f"{self.construct}-" + "_".join(words[:7])


def format_problems(brief: Brief) -> list[str]:  # noqa: C901
    """What is malformed about a brief (empty when it is well formed)."""
    problems = []
    if brief.voice not in VOICES:
        problems.append(f"voice {brief.voice!r} not in {VOICES}")
    if brief.construct not in CONSTRUCTS:
        problems.append(f"construct {brief.construct!r} unknown")
    if not brief.expect:
        problems.append("no expectation")
    for exp in brief.expect:
        kind = exp[0]
        if kind not in SCORES:
            problems.append(f"{exp}: unknown kind")
            continue
        if kind in ("unread", "all_read"):
            continue
        names = exp[1:3] if kind == "below" else exp[1:2]
        for name in names:
            if name not in brief.layers:
                problems.append(f"{exp}: {name!r} is not one of the layers")
        if kind in ("keep_out", "soft_zone", "graded_away", "graded_toward") and len(exp) != 3:
            problems.append(f"{exp}: needs (kind, layer, metres or None)")
    for route in brief.routes:
        if route.scene not in SCENE_CLASSES:
            problems.append(f"{route}: unknown scene")
        elif route.cls not in SCENE_CLASSES[route.scene]:
            problems.append(f"{route}: {route.cls!r} is not a class of {route.scene}")
        if route.relation not in RELATIONS:
            problems.append(f"{route}: unknown relation")
        if route.relation in ("keeps", "beside") and route.metres is None:
            problems.append(f"{route}: {route.relation} needs metres")
    return problems


# ==============================================================================================
# Checks of a brief's reading (probes on a 1 m grid; the cost language evaluates the program)
# ==============================================================================================

NEUTRAL = 0.5
EPS = 1e-6
#: The far probe: ground this many metres from X (beyond every default distance).
FAR_M = 60
_STRIPE = 9  # X is a vertical stripe this many metres wide at the west edge of the probe grid
_MARGIN = 10


def ground_probe(program_text: str, layers: tuple[str, ...], x: str, gap: int) -> tuple[float, bool, bool]:
    """(cost, lethal, keep_out) of unlabelled ground ``gap`` metres east of a stripe of layer ``x``.

    The grid is 1 m pixels, 41 m tall, wide enough for the gap and 20 m beyond it; only ``x`` is
    present, every other layer is empty. Evaluated with the project's cost language.
    """
    from overseec_core.costlang import check_program, evaluate_program, normalise_entity_name

    program = check_program(program_text, list(layers))
    width = _MARGIN + _STRIPE + gap + 20
    shape = (41, width)
    stripe = np.zeros(shape, dtype=bool)
    stripe[:, _MARGIN : _MARGIN + _STRIPE] = True
    name = normalise_entity_name(x)
    masks = {e: (stripe if normalise_entity_name(e) == name else np.zeros(shape, dtype=bool)) for e in program.entities}
    result = evaluate_program(program, masks, {}, sampling=(1.0, 1.0), shape=shape)
    col = _MARGIN + _STRIPE - 1 + gap
    return float(result.cost[20, col]), bool(result.lethal[20, col]), bool(result.keep_out[20, col])


def _fmt(c: tuple[float, bool, bool]) -> str:
    cost, lethal, keep = c
    return f"{cost:.3f}" + (" lethal" if lethal else "") + (" keep_out" if keep else "")


def _price(c: tuple[float, bool, bool]) -> float:
    """A probe's cost with impassable cells counted as dearest."""
    return 2.0 if (c[1] or c[2]) else c[0]


def _zone_gaps(m: float | None) -> tuple[list[int], int]:
    """Ground gaps inside a zone of ``m`` metres, and one outside it."""
    if m is None:
        return [1], FAR_M
    m_int = max(int(round(m)), 1)
    inside = sorted({1, max(m_int - 1, 1)})
    return inside, int(round(m + max(3.0, m / 2.0)))


def _check_keep_out(r, x: str, m: float | None) -> str | None:
    inside, outside = _zone_gaps(m)
    for g in inside:
        c = r.ground(x, g)
        if not (c[2] or c[1]):
            return f"ground {g} m from {x} should be kept out; probe gives {_fmt(c)}"
    c = r.ground(x, outside)
    if c[2] or c[1]:
        return f"ground {outside} m from {x} should be outside the zone; probe gives {_fmt(c)}"
    return None


def _check_soft_zone(r, x: str, m: float | None) -> str | None:
    inside, _ = _zone_gaps(m)
    far = r.ground(x, FAR_M)
    for g in inside:
        c = r.ground(x, g)
        if c[1] or c[2]:
            return f"a soft zone must not be kept out or lethal: ground {g} m from {x} gives {_fmt(c)}"
        if not c[0] > far[0] + EPS:
            return f"ground {g} m from {x} should cost more than ground {FAR_M} m away: {_fmt(c)} vs {_fmt(far)}"
    return None


def _check_graded(r, kind: str, x: str, m: float | None) -> str | None:
    c2, c8, cfar = r.ground(x, 2), r.ground(x, 8), r.ground(x, FAR_M)
    where = f"ground 2 m: {_fmt(c2)}, 8 m: {_fmt(c8)}, {FAR_M} m: {_fmt(cfar)} from {x}"
    if any(c[1] or c[2] for c in (c2, c8, cfar)):
        return f"graded nearness must not be kept out or lethal ({where})"
    if kind == "graded_away":
        if not (c2[0] > c8[0] + EPS and c8[0] >= cfar[0] - EPS):
            return f"the closer to {x}, the dearer ({where})"
        if m is not None:
            beyond = r.ground(x, int(round(m)) + 5)
            if abs(beyond[0] - cfar[0]) > EPS:
                return f"beyond {m} m from {x} the fall-off should have reached far ground ({_fmt(beyond)}; {where})"
        return None
    if not (c2[0] < c8[0] - EPS and c8[0] <= cfar[0] + EPS and c2[0] < NEUTRAL - EPS):
        return f"the closer to {x}, the cheaper, and preferred close by ({where})"
    return None


def _check_beside(r, x: str) -> str | None:
    own = r.cost(x)
    c2, cfar = r.ground(x, 2), r.ground(x, FAR_M)
    where = f"{x}: {_fmt(own)}; ground 2 m from it: {_fmt(c2)}; {FAR_M} m: {_fmt(cfar)}"
    if not (own[1] or own[0] > NEUTRAL + EPS):
        return f"{x} itself should be avoided or forbidden ({where})"
    if c2[1] or c2[2] or not c2[0] < NEUTRAL - EPS:
        return f"ground beside {x} should be preferred ({where})"
    if not c2[0] < _price(cfar) - EPS:
        return f"ground beside {x} should cost less than ground far from it ({where})"
    return None


def _unparsed(r) -> list[str]:
    """What the reading reports as having no effect: the clauses not understood, and the
    prompt's words about entities no layer stands for (the warning ``costmap`` prints for each,
    and what ``--strict`` refuses, :func:`overseec_core.synthesize.fit.require_all_matched`)."""
    r.need()
    no_effect = getattr(r.resolved, "no_effect", ()) if r.resolved is not None else ()
    return [str(u) for u in getattr(r.interp, "unparsed", ())] + [str(u) for u in no_effect]


def _check_unread(r, word: str) -> str | None:
    got = _unparsed(r)
    if any(word.lower() in u.lower() for u in got):
        return None
    return f"no clause containing {word!r} is reported as not understood (unread: {got})"


def _check_all_read(r) -> str | None:
    got = _unparsed(r)
    return None if not got else f"clauses reported as not understood: {got}"


def check_brief(brief: Brief) -> list[tuple[tuple, str | None]]:  # noqa: C901
    """Each expectation of the brief with its failure reason (None = it holds)."""
    from .mission_prompts import CaseFailure, Reading, _cross, _level, _order

    class BriefReading(Reading):
        def ground(self, x: str, gap: int) -> tuple[float, bool, bool]:
            self.need()
            key = ("ground", x, gap)
            if key not in self._costs:
                self._costs[key] = ground_probe(self.resolved.text, self.layers, x, gap)
            return self._costs[key]

    r = BriefReading.of(brief.prompt, brief.layers)
    out = []
    for exp in brief.expect:
        kind = exp[0]
        try:
            if kind in ("preferred", "neutral", "avoided", "lethal", "not_lethal"):
                why = _level(r, kind, exp[1])
            elif kind == "below":
                why = _order(r, kind, exp[1], exp[2])
            elif kind == "no_cross":
                why = _cross(r, kind, exp[1])
            elif kind == "keep_out":
                why = _check_keep_out(r, exp[1], exp[2])
            elif kind == "soft_zone":
                why = _check_soft_zone(r, exp[1], exp[2])
            elif kind in ("graded_away", "graded_toward"):
                why = _check_graded(r, kind, exp[1], exp[2])
            elif kind == "beside":
                why = _check_beside(r, exp[1])
            elif kind == "unread":
                why = _check_unread(r, exp[1])
            elif kind == "all_read":
                why = _check_all_read(r)
            else:
                why = f"unknown expectation kind {kind!r}"
        except CaseFailure as exc:
            why = f"not read: {exc}"
        except Exception as exc:  # a check reports, never crashes the report
            why = f"{type(exc).__name__} while checking: {exc}"
        out.append((exp, why))
    return out
