"""Mission-language corpus (issue 20): prompts, what each must mean, and the checks that say so.

Every case is a prompt, its phrasing family, the layer names its costmap is built over, and a
list of expectations. Expectations about costs are measured on LAYERS, not on the interpreter's
internal entity names (which may be normalised: "streets" may become "road"): the prompt is
interpreted offline (``interpret_offline``), fitted to the case's layers (``compose.fit_program``)
and the resulting cost program is evaluated with the project's own cost-language evaluator on
small synthetic probes (:func:`layer_cost`): a square covered by one layer on a 1 m grid, read
at its centre, optionally with a second layer 3 px ("near") or 40 px ("far") away.

The cost scale (issue 20): every pixel costs [0, 1]; neutral ground 0.5 (unlabelled ground,
unmentioned non-hazards, anything merely allowed); preferred below 0.5; avoided above; lethal =
impassable. Unmentioned hazards (tree, building, water, railway) take "prior" levels in the
avoided band (tree below building; not lethal).

Expectations (layer names ``L``, ``A``, ``B``, ``X``, ``Y``; EPS = 1e-6):

- ``("preferred", L)``: cost(L) < 0.5, not lethal
- ``("neutral", L)``: |cost(L) - 0.5| <= EPS, not lethal, not kept out
- ``("avoided", L)``: cost(L) > 0.5, not lethal (also used for "last resort": tolerable)
- ``("lethal", L)`` / ``("not_lethal", L)``
- ``("below", A, B)``: cost(A) < cost(B) strictly, and neither is lethal
- ``("not_below", A, B)``: cost(A) >= cost(B), neither lethal
- ``("near_above_far", X, Y)``: X within 3 m of Y costs strictly more than X 40 m from Y
- ``("near_below_far", X, Y)``: X within 3 m of Y costs strictly less than X 40 m from Y, and
  X near Y is not lethal
- ``("far_band", X, Y, band)``: X 40 m from Y is preferred / neutral / avoided (as above)
- ``("ge_prompt", L, other_prompt)``: cost(L) under this prompt >= cost(L) under ``other_prompt``
  on the same layers (e.g. "avoid the buildings" never puts buildings below their prior)
- ``("no_cross", L)``: the interpretation has ``Cue(kind="no_cross", hard=True)`` on an entity
  that lands on layer L; ``("no_no_cross", L)``: it has no ``no_cross`` cue landing on L
- ``("band", L, band)``: the preference(s) landing on layer L (the stated ones when any, else
  the unstated ones) have ``Preference.band == band``; for band "prior" also ``prior is True``
  and no stated preference lands on L
- ``("note_quotes", word)``: a note (interpretation or fitted program) quotes the word as
  written ('vegitation'), or maps the entity it names to a layer ("street -> road");
  ``("not_unparsed", word)``: no unparsed fragment contains it
- ``("costmap_ok",)``: ``pipeline.run_costmap`` writes a costmap over a synthetic label raster
  of the case's layers; ``("permission_note",)``: it does, and a note says the prompt is
  permission only (a note with both "permission" and "only")
- ``("error",)``: ``run_costmap`` raises InputError / InterpretError; ``("cli_exit", 2)``:
  ``overseec costmap --prompt ...`` exits with that status
- ``("cli_band", entity, word)``: ``overseec interpret --offline PROMPT`` prints the entity's row
  with the level word (preferred / neutral / prior / avoided / lethal)

:func:`check_case` returns the list of failed expectations with reasons (empty = pass); the
test module and ``bench/mission_language_report.py`` both use it.

Scene-level cases (:data:`SCENE_CASES`) and the priors figure settings are at the end; the
harness that runs them is in tests/test_mission_language.py.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from overseec_core.interpret.lexicon import singularise

NEUTRAL = 0.5
EPS = 1e-6
BANDS = ("preferred", "neutral", "prior", "avoided", "lethal")

#: The paper's headline prompt (the one prompt not new here: the issue asks for it by name).
HEADLINE = "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible."

SAMPLE_LAYERS = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
NB_LAYERS = ("building", "road", "water", "vegetation", "railway")

FAMILIES: dict[str, str] = {
    "negation_motion": "negation over motion verbs: don't leave/stray from X = stay on X; stay/keep off X = avoid",
    "last_resort": "last resort inside lists: tolerable (above neutral, not lethal)",
    "comparative": "comparatives and chains: strict order, no side lethal",
    "condition": "conditions: 'X is fine unless near Y', 'avoid X except near Y'",
    "scope": "scope of off limits / no-go / never: only its own clause",
    "no_cross": "'do not cross' / 'never cross' = hard no_cross cue, not lethal; 'try not to cross' = soft",
    "spelling": "misspellings and colloquial terrain words, quoted in a note",
    "prior": "priors of unmentioned hazards, and how avoid / permission / off limits move them",
    "outcome": "outcomes: permission-only costmaps, nothing understood = error, CLI level words",
}


@dataclass(frozen=True)
class Case:
    prompt: str
    family: str
    layers: tuple[str, ...]
    expect: tuple[tuple, ...]
    #: Why the expectation is what it is, where that is not obvious (or a doubt for the report).
    why: str = ""

    @property
    def id(self) -> str:
        words = re.sub(r"[^a-z0-9 ]+", "", self.prompt.lower()).split()
        return f"{self.family}-" + "_".join(words[:7])


C = Case
L_PATHS = ("road", "trail", "vegetation", "building", "water")

CASES: list[Case] = [
    # ------------------------------------------------------------------ 1. negation over motion verbs
    C("Don't leave the road.", "negation_motion", L_PATHS, (("preferred", "road"),)),
    C("Please do not stray from the trail.", "negation_motion", L_PATHS, (("preferred", "trail"),)),
    C("Whatever happens, don't get off the road!", "negation_motion", L_PATHS, (("preferred", "road"),)),
    C(
        "never wander off the trail",
        "negation_motion",
        L_PATHS,
        (("preferred", "trail"),),
        why="'never' negates the motion away from the trail: the trail is preferred, not lethal",
    ),
    C(
        "do not deviate from the road, and avoid the water",
        "negation_motion",
        L_PATHS,
        (("preferred", "road"), ("avoided", "water"), ("below", "road", "water")),
    ),
    C("Kindly keep off the road.", "negation_motion", L_PATHS, (("avoided", "road"),)),
    C("Stay off the trail, please", "negation_motion", L_PATHS, (("avoided", "trail"),)),
    C(
        "Try not to leave the trail; the buildings should be avoided.",
        "negation_motion",
        L_PATHS,
        (("preferred", "trail"), ("avoided", "building")),
    ),
    C("We mustn't stray from the road.", "negation_motion", L_PATHS, (("preferred", "road"),)),
    C(
        "don't wander away from the trail or the road",
        "negation_motion",
        L_PATHS,
        (("preferred", "trail"), ("preferred", "road")),
    ),
    C(
        "Keep off the vegetation and don't get off the road",
        "negation_motion",
        L_PATHS,
        (("avoided", "vegetation"), ("preferred", "road"), ("below", "road", "vegetation")),
    ),
    C("Don't deviate from the trail at any point.", "negation_motion", L_PATHS, (("preferred", "trail"),)),
    # ------------------------------------------------------------------ 2. last resort inside lists
    C(
        "Go through the vegetation where you can; the road is only a last resort.",
        "last_resort",
        ("road", "vegetation", "building", "water"),
        (("preferred", "vegetation"), ("avoided", "road")),
    ),
    C(
        "Only fall back on the trail as a last resort.",
        "last_resort",
        ("road", "trail", "vegetation", "building"),
        (("avoided", "trail"),),
    ),
    C(
        "Stick to the grass, with roads as a last resort.",
        "last_resort",
        ("road", "grass", "building", "water"),
        (("preferred", "grass"), ("avoided", "road")),
    ),
    C(
        "Prefer the road; take the farmland only as a last resort.",
        "last_resort",
        ("road", "farmland", "building", "water"),
        (("preferred", "road"), ("avoided", "farmland")),
    ),
    C(
        "Favour the trails - the grass is strictly a last resort.",
        "last_resort",
        ("trail", "grass", "building", "water"),
        (("preferred", "trail"), ("avoided", "grass")),
    ),
    C(
        "Roads and trails are fine, but use the vegetation only as a last resort.",
        "last_resort",
        ("road", "trail", "vegetation", "building"),
        (("neutral", "road"), ("neutral", "trail"), ("avoided", "vegetation")),
    ),
    C(
        "Prefer the forest, then farmland, and only use the road as a last resort.",
        "last_resort",
        ("forest", "farmland", "road", "water"),
        (("preferred", "forest"), ("below", "forest", "farmland"), ("below", "farmland", "road"), ("avoided", "road")),
    ),
    C(
        "I want the trail; the road is a last resort.",
        "last_resort",
        ("trail", "road", "building", "water"),
        (("preferred", "trail"), ("avoided", "road")),
    ),
    C(
        "As a last resort you may take the road, but prefer the vegetation.",
        "last_resort",
        ("road", "vegetation", "building"),
        (("avoided", "road"), ("preferred", "vegetation")),
        why="'you may' is qualified by 'as a last resort': tolerable, not neutral",
    ),
    C(
        "Prefer the vegetation and the trail, with the road as a last resort",
        "last_resort",
        ("road", "trail", "vegetation", "water"),
        (("preferred", "vegetation"), ("preferred", "trail"), ("avoided", "road")),
    ),
    C(
        "Prefer grass, trails and, as a last resort, roads.",
        "last_resort",
        ("grass", "trail", "road", "building"),
        (("preferred", "grass"), ("preferred", "trail"), ("avoided", "road")),
        why="the last list item carries its own qualifier; the first two keep 'prefer'",
    ),
    # ------------------------------------------------------------------ 3. comparatives and chains
    C(
        "For this mission, the trail is better than the road.",
        "comparative",
        ("trail", "road", "vegetation", "building"),
        (("below", "trail", "road"),),
    ),
    C(
        "Rather farmland than forest.",
        "comparative",
        ("farmland", "forest", "road", "water"),
        (("below", "farmland", "forest"),),
    ),
    C(
        "I'd rather take the road than the vegetation.",
        "comparative",
        ("road", "vegetation", "building", "water"),
        (("below", "road", "vegetation"),),
    ),
    C(
        "grass over trail over road",
        "comparative",
        ("grass", "trail", "road", "building"),
        (("below", "grass", "trail"), ("below", "trail", "road")),
    ),
    C(
        "Farmland is better than forest, and forest is better than the buildings.",
        "comparative",
        ("farmland", "forest", "building", "road"),
        (("below", "farmland", "forest"), ("below", "forest", "building")),
    ),
    C(
        "I'd prefer the trail to the road.",
        "comparative",
        ("trail", "road", "grass", "water"),
        (("below", "trail", "road"),),
        why="'prefer X to Y' is a comparison (X below Y), not 'prefer X' and 'prefer Y'",
    ),
    C(
        "Water is worse than vegetation.",
        "comparative",
        ("water", "vegetation", "road", "building"),
        (("below", "vegetation", "water"),),
    ),
    C(
        "Rather the road than the railway, and rather the railway than the water.",
        "comparative",
        ("road", "railway", "water", "vegetation"),
        (("below", "road", "railway"), ("below", "railway", "water")),
    ),
    C(
        "I would rather walk through the forest than across the farmland.",
        "comparative",
        ("forest", "farmland", "road", "water"),
        (("below", "forest", "farmland"),),
    ),
    C(
        "vegetation over buildings, please",
        "comparative",
        ("vegetation", "building", "road", "water"),
        (("below", "vegetation", "building"),),
    ),
    C(
        "Go by road rather than by trail.",
        "comparative",
        ("road", "trail", "grass", "building"),
        (("below", "road", "trail"),),
    ),
    C(
        "The grass is better than the trees, and the trees are better than the buildings.",
        "comparative",
        ("grass", "tree", "building", "road"),
        (("below", "grass", "tree"), ("below", "tree", "building")),
    ),
    # ------------------------------------------------------------------ 4. conditions
    C(
        "The road is fine unless near the buildings.",
        "condition",
        ("road", "building", "vegetation", "water"),
        (("far_band", "road", "building", "neutral"), ("near_above_far", "road", "building")),
    ),
    C(
        "Avoid water, except near roads.",
        "condition",
        ("water", "road", "vegetation", "building"),
        (("far_band", "water", "road", "avoided"), ("near_below_far", "water", "road")),
    ),
    C(
        "Vegetation is OK unless it's near the railway.",
        "condition",
        ("vegetation", "railway", "road", "building"),
        (("far_band", "vegetation", "railway", "neutral"), ("near_above_far", "vegetation", "railway")),
    ),
    C(
        "Grass is fine unless within 15 m of a building.",
        "condition",
        ("grass", "building", "road", "water"),
        (("far_band", "grass", "building", "neutral"), ("near_above_far", "grass", "building")),
    ),
    C(
        "avoid the farmland except near the road",
        "condition",
        ("farmland", "road", "forest", "water"),
        (("far_band", "farmland", "road", "avoided"), ("near_below_far", "farmland", "road")),
    ),
    C(
        "Crossing the forest is fine, unless you are near the water.",
        "condition",
        ("forest", "water", "road", "building"),
        (("far_band", "forest", "water", "neutral"), ("near_above_far", "forest", "water")),
    ),
    C(
        "Avoid the buildings except when close to the road.",
        "condition",
        ("building", "road", "vegetation", "water"),
        (("far_band", "building", "road", "avoided"), ("near_below_far", "building", "road")),
    ),
    C(
        "The trail is fine unless it runs close to the water.",
        "condition",
        ("trail", "water", "road", "building"),
        (("far_band", "trail", "water", "neutral"), ("near_above_far", "trail", "water")),
    ),
    C(
        "Avoid the vegetation except within 5 m of the trail.",
        "condition",
        ("vegetation", "trail", "road", "building"),
        (("far_band", "vegetation", "trail", "avoided"), ("near_below_far", "vegetation", "trail")),
    ),
    C(
        "Farmland is acceptable unless close to the railway.",
        "condition",
        ("farmland", "railway", "road", "water"),
        (("far_band", "farmland", "railway", "neutral"), ("near_above_far", "farmland", "railway")),
        why="'acceptable' is a permission (neutral), like 'fine' and 'ok'",
    ),
    # ------------------------------------------------------------------ 5. scope of off limits / no-go / never
    C(
        "Cross farmland rather than forest, and the lake is off-limits.",
        "scope",
        ("farmland", "forest", "lake", "road"),
        (("lethal", "lake"), ("not_lethal", "farmland"), ("not_lethal", "forest"), ("below", "farmland", "forest")),
    ),
    C(
        "Prefer the road and avoid the forest; the railway is a no-go.",
        "scope",
        ("road", "forest", "railway", "water"),
        (("lethal", "railway"), ("preferred", "road"), ("avoided", "forest")),
    ),
    C(
        "Never enter the water, and stay on the trail.",
        "scope",
        ("water", "trail", "road", "building"),
        (("lethal", "water"), ("preferred", "trail")),
    ),
    C(
        "The buildings are a no-go zone but farmland is fine.",
        "scope",
        ("building", "farmland", "road", "water"),
        (("lethal", "building"), ("neutral", "farmland")),
    ),
    C(
        "Avoid the forest and the farmland; the lake is off limits.",
        "scope",
        ("forest", "farmland", "lake", "road"),
        (("lethal", "lake"), ("avoided", "forest"), ("avoided", "farmland")),
    ),
    C(
        "The railway is off limits. Roads are better than trails.",
        "scope",
        ("railway", "road", "trail", "grass"),
        (("lethal", "railway"), ("below", "road", "trail")),
    ),
    C(
        "never go into the buildings; the grass and the trail are fine",
        "scope",
        ("building", "grass", "trail", "road"),
        (("lethal", "building"), ("neutral", "grass"), ("neutral", "trail")),
    ),
    C(
        "The lake is off limits, but I would rather walk on farmland than in the forest.",
        "scope",
        ("lake", "farmland", "forest", "road"),
        (("lethal", "lake"), ("below", "farmland", "forest")),
    ),
    C(
        "The water is a no-go area; otherwise prefer the vegetation.",
        "scope",
        ("water", "vegetation", "road", "building"),
        (("lethal", "water"), ("preferred", "vegetation")),
    ),
    C(
        "stay on the road, the grass is ok, and never walk on the railway",
        "scope",
        ("road", "grass", "railway", "building"),
        (("lethal", "railway"), ("preferred", "road"), ("neutral", "grass")),
    ),
    C(
        "I'd rather use the trail than the road, and the forest is off limits",
        "scope",
        ("trail", "road", "forest", "water"),
        (("lethal", "forest"), ("below", "trail", "road")),
    ),
    # ------------------------------------------------------------------ 6. do not cross vs never cross
    C(
        "Do not cross the railway.",
        "no_cross",
        ("railway", "road", "vegetation", "building"),
        (("no_cross", "railway"), ("avoided", "railway")),
    ),
    C(
        "You must never cross the stream.",
        "no_cross",
        ("stream", "road", "vegetation", "building"),
        (("no_cross", "stream"), ("avoided", "stream")),
    ),
    C(
        "Please don't cross the road.",
        "no_cross",
        ("road", "trail", "grass", "building"),
        (("no_cross", "road"), ("avoided", "road")),
    ),
    C(
        "Never cross the railway tracks.",
        "no_cross",
        ("railway", "road", "vegetation", "water"),
        (("no_cross", "railway"), ("avoided", "railway")),
    ),
    C(
        "Try not to cross the road.",
        "no_cross",
        ("road", "grass", "trail", "building"),
        (("no_no_cross", "road"), ("avoided", "road")),
    ),
    C(
        "Avoid crossing the river.",
        "no_cross",
        ("river", "road", "vegetation"),
        (("no_no_cross", "river"), ("avoided", "river")),
    ),
    C(
        "Do not cross the water, prefer the trail.",
        "no_cross",
        ("water", "trail", "road", "building"),
        (("no_cross", "water"), ("avoided", "water"), ("preferred", "trail")),
    ),
    C(
        "Ideally avoid crossing the railway, and never cross the river.",
        "no_cross",
        ("railway", "river", "road", "vegetation"),
        (("no_no_cross", "railway"), ("avoided", "railway"), ("no_cross", "river"), ("avoided", "river")),
    ),
    C(
        "don't ever cross the canal",
        "no_cross",
        ("canal", "road", "vegetation", "building"),
        (("no_cross", "canal"), ("avoided", "canal")),
    ),
    C(
        "We should try not to cross the railway.",
        "no_cross",
        ("railway", "road", "vegetation"),
        (("no_no_cross", "railway"), ("avoided", "railway")),
    ),
    C(
        "do not cross the road and do not cross the river",
        "no_cross",
        ("road", "river", "grass"),
        (("no_cross", "road"), ("avoided", "road"), ("no_cross", "river"), ("avoided", "river")),
    ),
    # ------------------------------------------------------------------ 7. misspellings and colloquial words
    C(
        "Prefer the vegitation.",
        "spelling",
        ("vegetation", "road", "building", "water"),
        (("preferred", "vegetation"), ("note_quotes", "vegitation"), ("not_unparsed", "vegitation")),
    ),
    C(
        "The buidlings are off limits.",
        "spelling",
        ("building", "road", "vegetation", "water"),
        (("lethal", "building"), ("note_quotes", "buidlings"), ("not_unparsed", "buidlings")),
    ),
    C(
        "Stay on the raod.",
        "spelling",
        ("road", "vegetation", "building", "water"),
        (("preferred", "road"), ("note_quotes", "raod"), ("not_unparsed", "raod")),
    ),
    C(
        "Stick to the streets.",
        "spelling",
        ("road", "vegetation", "building", "water"),
        (("preferred", "road"), ("note_quotes", "streets")),
        why="a colloquial synonym, not a typo: should the note quote it too? (the brief says so)",
    ),
    C(
        "keep to the lanes where possible",
        "spelling",
        ("road", "grass", "building", "water"),
        (("preferred", "road"), ("note_quotes", "lanes")),
    ),
    C(
        "walk on the dirt, not the grass",
        "spelling",
        ("bare soil", "grass", "road", "building"),
        (("preferred", "bare soil"), ("below", "bare soil", "grass"), ("note_quotes", "dirt")),
        why="'dirt' is bare soil (matching.SYNONYMS); 'not the grass' = the grass is worse",
    ),
    C(
        "Use the footpaths.",
        "spelling",
        ("trail", "road", "building", "water"),
        (("preferred", "trail"), ("note_quotes", "footpaths")),
    ),
    C(
        "Keep to the woods.",
        "spelling",
        ("tree", "road", "grass", "building"),
        (("preferred", "tree"), ("note_quotes", "woods")),
    ),
    C(
        "Wading through the creek is fine.",
        "spelling",
        ("water", "road", "grass", "building"),
        (("neutral", "water"), ("note_quotes", "creek")),
    ),
    C(
        "prefer the vegetaion and keep off the raod",
        "spelling",
        ("vegetation", "road", "building"),
        (
            ("preferred", "vegetation"),
            ("avoided", "road"),
            ("note_quotes", "vegetaion"),
            ("note_quotes", "raod"),
            ("not_unparsed", "vegetaion"),
            ("not_unparsed", "raod"),
        ),
    ),
    C(
        "Walking between the biuldings is fine.",
        "spelling",
        ("building", "road", "grass", "water"),
        (("neutral", "building"), ("note_quotes", "biuldings"), ("not_unparsed", "biuldings")),
    ),
    # ------------------------------------------------------------------ 8. priors of unmentioned hazards
    C(
        HEADLINE,
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "road", "preferred"),
            ("band", "grass", "neutral"),
            ("band", "baseball field", "avoided"),
            ("band", "tree", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("preferred", "road"),
            ("preferred", "trail"),
            ("neutral", "grass"),
            ("avoided", "baseball field"),
            ("avoided", "tree"),
            ("avoided", "building"),
            ("avoided", "water"),
            ("not_below", "building", "tree"),
            ("not_below", "water", "tree"),
        ),
    ),
    C(
        "Keep to the roads and the trails, the grass is okay, and keep off the baseball field if you can.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "tree", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("avoided", "tree"),
            ("avoided", "building"),
            ("avoided", "water"),
            ("not_below", "building", "tree"),
            ("avoided", "baseball field"),
            ("neutral", "grass"),
        ),
    ),
    C(
        "Please try to avoid any buildings.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "building", "avoided"),
            ("avoided", "building"),
            ("ge_prompt", "building", HEADLINE),
            ("band", "tree", "prior"),
            ("band", "water", "prior"),
        ),
    ),
    C(
        "Feel free to walk among the trees.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "tree", "neutral"),
            ("neutral", "tree"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("avoided", "building"),
        ),
    ),
    C(
        "The river is strictly off limits for us.",
        "prior",
        SAMPLE_LAYERS,
        (("lethal", "water"), ("band", "water", "lethal"), ("band", "tree", "prior"), ("band", "building", "prior")),
    ),
    C(
        "Roads are preferred here.",
        "prior",
        NB_LAYERS,
        (
            ("preferred", "road"),
            ("avoided", "railway"),
            ("avoided", "building"),
            ("avoided", "water"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
        ),
        why="railway has no default entity: its prior must come from the layer itself",
    ),
    C(
        "Walk on the grass; the trees are fine too.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("preferred", "grass"),
            ("band", "tree", "neutral"),
            ("neutral", "tree"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
        ),
    ),
    C(
        "Keep to the road and avoid the trees.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "tree", "avoided"),
            ("avoided", "tree"),
            ("ge_prompt", "tree", HEADLINE),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
        ),
    ),
    C(
        "Prefer trails. Buildings are impassable.",
        "prior",
        SAMPLE_LAYERS,
        (("lethal", "building"), ("band", "building", "lethal"), ("band", "tree", "prior"), ("band", "water", "prior")),
    ),
    C(
        "Take the road, and wading through water is fine.",
        "prior",
        SAMPLE_LAYERS,
        (("band", "water", "neutral"), ("neutral", "water"), ("band", "tree", "prior"), ("band", "building", "prior")),
    ),
    C(
        "follow the trail",
        "prior",
        ("trail", "railway", "road", "farmland"),
        (("preferred", "trail"), ("avoided", "railway"), ("neutral", "farmland")),
        why="farmland is no hazard: unmentioned, it stays neutral; railway takes its prior",
    ),
    # ------------------------------------------------------------------ 9. outcomes
    C("The buildings are perfectly fine.", "outcome", SAMPLE_LAYERS, (("costmap_ok",), ("permission_note",))),
    C("Crossing the water is alright.", "outcome", SAMPLE_LAYERS, (("costmap_ok",), ("permission_note",))),
    C("You're allowed to walk through the trees.", "outcome", SAMPLE_LAYERS, (("costmap_ok",), ("permission_note",))),
    C("The road and the grass are both fine.", "outcome", SAMPLE_LAYERS, (("costmap_ok",), ("permission_note",))),
    C("Good morning, team!", "outcome", SAMPLE_LAYERS, (("error",), ("cli_exit", 2))),
    C("Make the route pretty.", "outcome", SAMPLE_LAYERS, (("error",), ("cli_exit", 2))),
    C("just do your best", "outcome", SAMPLE_LAYERS, (("error",), ("cli_exit", 2))),
    C("Thanks in advance.", "outcome", SAMPLE_LAYERS, (("error",),)),
    C(
        "Prefer the trail and the road, the grass is okay, and avoid the baseball field.",
        "outcome",
        SAMPLE_LAYERS,
        (
            ("cli_band", "road", "preferred"),
            ("cli_band", "grass", "neutral"),
            ("cli_band", "tree", "prior"),
            ("cli_band", "building", "prior"),
            ("cli_band", "baseball field", "avoided"),
        ),
    ),
    C(
        "The water is a no-go.",
        "outcome",
        SAMPLE_LAYERS,
        (("cli_band", "water", "lethal"), ("cli_band", "tree", "prior"), ("costmap_ok",)),
    ),
]

#: Prompts whose expected reading is a judgement call (for the other engineer to decide).
DOUBTFUL: dict[str, str] = {
    "never wander off the trail": "could 'never' make it a hard rule (keep out of everything off the trail)? "
    "only 'trail preferred, not lethal' is asserted",
    "Stick to the streets.": "synonym, not a typo: does the note quoting the word as written apply?",
    "keep to the lanes where possible": "synonym, not a typo: does the note quoting the word as written apply?",
    "Keep to the woods.": "synonym, not a typo: does the note quoting the word as written apply?",
    "walk on the dirt, not the grass": "'dirt' -> bare soil (matching.SYNONYMS), or trail / road? "
    "'not the grass' read as: grass worse than dirt",
    "Wading through the creek is fine.": "creek is inside water: a permission makes the water layer neutral",
    "As a last resort you may take the road, but prefer the vegetation.": "'you may' vs 'as a last resort'",
    "The grass is better than the trees, and the trees are better than the buildings.": "trees and buildings "
    "have priors: a chain must still order them strictly (tree < building) and put grass below tree",
    "I want the trail; the road is a last resort.": "'I want X' read as a preference for X",
    "Good morning, team!": "'team' is an unknown word: the interpreter must not make an entity of it",
    "Make the route pretty.": "'route' must not become an entity",
}


# ==============================================================================================
# Probes: the cost a program gives a layer
# ==============================================================================================

PROBE_N = 128
CENTRE = PROBE_N // 2
SQUARE = slice(16, 112)  # the present layers' square: 96 px at 1 m
NEAR_GAP_PX = 3  # "near": the other layer's nearest pixel 3 m from the probe
FAR_GAP_PX = 40  # "far": 40 m away (beyond a 10 m default "near" and a stated 15 m)
OTHER_SIDE = 9  # the other layer: a 9 x 9 square east of the probe


def layer_cost(
    program_text: str,
    layer_names: Sequence[str],
    present: Sequence[str] = ("vegetation",),
    near: str | None = None,
    gap: int = NEAR_GAP_PX,
) -> tuple[float, bool, bool]:
    """(cost, lethal, keep_out) at the centre of a square covered by ``present`` (1 m pixels).

    With ``near``, that layer covers a 9 x 9 square whose nearest pixel is ``gap`` pixels east of
    the probe (cut out of the present square). Evaluated with the project's cost language.
    """
    from overseec_core.costlang import check_program, evaluate_program, normalise_entity_name

    program = check_program(program_text, list(layer_names))
    shape = (PROBE_N, PROBE_N)
    square = np.zeros(shape, dtype=bool)
    square[SQUARE, SQUARE] = True
    other = np.zeros(shape, dtype=bool)
    if near is not None:
        half = OTHER_SIDE // 2
        other[CENTRE - half : CENTRE + half + 1, CENTRE + gap : CENTRE + gap + OTHER_SIDE] = True
    on = {normalise_entity_name(n) for n in present}
    near_name = normalise_entity_name(near) if near is not None else None
    masks = {}
    for e in program.entities:
        n = normalise_entity_name(e)
        m = (square & ~other) if n in on else np.zeros(shape, dtype=bool)
        if n == near_name:
            m = m | other
        masks[e] = m
    result = evaluate_program(program, masks, {}, sampling=(1.0, 1.0), shape=shape)
    return (
        float(result.cost[CENTRE, CENTRE]),
        bool(result.lethal[CENTRE, CENTRE]),
        bool(result.keep_out[CENTRE, CENTRE]),
    )


class CaseFailure(Exception):
    """The prompt could not even be read (interpretation or fitting raised)."""


@dataclass
class Reading:
    """A prompt read on a case's layers: the interpretation, the fitted program, probe costs."""

    prompt: str
    layers: tuple[str, ...]
    interp: object | None = None
    resolved: object | None = None
    error: str | None = None
    _costs: dict = field(default_factory=dict)

    @classmethod
    def of(cls, prompt: str, layers: Sequence[str]) -> Reading:
        from overseec_core.interpret.offline import interpret_offline
        from overseec_core.synthesize.fit import fit_program

        r = cls(prompt, tuple(layers))
        try:
            r.interp = interpret_offline(prompt)
            r.resolved = fit_program(r.interp, list(layers))
        except Exception as exc:  # reported as the reason of every expectation that needs it
            r.error = f"{type(exc).__name__}: {exc}"
        return r

    def need(self) -> None:
        if self.error is not None:
            raise CaseFailure(self.error)

    def cost(self, layer: str, near: str | None = None, gap: int = NEAR_GAP_PX) -> tuple[float, bool, bool]:
        self.need()
        key = (layer, near, gap)
        if key not in self._costs:
            assert self.resolved is not None
            self._costs[key] = layer_cost(self.resolved.text, self.layers, (layer,), near, gap)
        return self._costs[key]

    def layer_of(self) -> dict[str, tuple[str, ...]]:
        self.need()
        return {m.entity: tuple(m.layers) for m in getattr(self.resolved, "mapping", ())}

    def prefs_on(self, layer: str) -> tuple[list, bool]:
        """Preferences landing on ``layer``: the stated ones when any (True), else the others."""
        self.need()
        layer_of = self.layer_of()
        prefs = [p for p in self.interp.preferences if p.entity == layer or layer in layer_of.get(p.entity, ())]
        stated = [p for p in prefs if p.phrase]
        return (stated, True) if stated else (prefs, False)

    def notes(self) -> list[str]:
        out = list(getattr(self.interp, "notes", ()) or ())
        out += list(getattr(self.resolved, "notes", ()) or ())
        return out


def _fmt(c: tuple[float, bool, bool]) -> str:
    cost, lethal, keep = c
    return f"{cost:.3f}" + (" lethal" if lethal else "") + (" keep_out" if keep else "")


def _band_of_cost(c: tuple[float, bool, bool]) -> str:
    cost, lethal, _ = c
    if lethal:
        return "lethal"
    if abs(cost - NEUTRAL) <= EPS:
        return "neutral"
    return "preferred" if cost < NEUTRAL else "avoided"


# ==============================================================================================
# Checks
# ==============================================================================================


def _level(r: Reading, kind: str, layer: str) -> str | None:
    c = r.cost(layer)
    cost, lethal, keep = c
    ok = {
        "preferred": not lethal and cost < NEUTRAL - EPS,
        "neutral": not lethal and not keep and abs(cost - NEUTRAL) <= EPS,
        "avoided": not lethal and cost > NEUTRAL + EPS,
        "lethal": lethal,
        "not_lethal": not lethal,
    }[kind]
    return None if ok else f"{layer} should be {kind.replace('_', ' ')}; probe gives {_fmt(c)}"


def _order(r: Reading, kind: str, a: str, b: str) -> str | None:
    ca, cb = r.cost(a), r.cost(b)
    if ca[1] or cb[1]:
        return f"{kind} {a} {b}: neither side may be lethal ({a} {_fmt(ca)}, {b} {_fmt(cb)})"
    if kind == "below" and not ca[0] < cb[0] - EPS:
        return f"{a} should cost strictly less than {b}: {_fmt(ca)} vs {_fmt(cb)}"
    if kind == "not_below" and not ca[0] >= cb[0] - EPS:
        return f"{a} should cost at least as much as {b}: {_fmt(ca)} vs {_fmt(cb)}"
    return None


def _condition(r: Reading, kind: str, x: str, y: str, band: str | None = None) -> str | None:
    near = r.cost(x, near=y, gap=NEAR_GAP_PX)
    far = r.cost(x, near=y, gap=FAR_GAP_PX)
    where = f"{x} {NEAR_GAP_PX} m from {y}: {_fmt(near)}; {FAR_GAP_PX} m from {y}: {_fmt(far)}"
    if kind == "far_band":
        got = _band_of_cost(far)
        return None if got == band else f"{x} away from {y} should be {band}, is {got} ({where})"
    near_cost = 1.0 if near[1] else near[0]
    far_cost = 1.0 if far[1] else far[0]
    if kind == "near_above_far":
        if far[1]:
            return f"{x} away from {y} must not be lethal ({where})"
        return None if near_cost > far_cost + EPS else f"{x} near {y} should cost more than away from it ({where})"
    if near[1]:
        return f"{x} near {y} must not be lethal ({where})"
    return None if near_cost < far_cost - EPS else f"{x} near {y} should cost less than away from it ({where})"


def _cross(r: Reading, kind: str, layer: str) -> str | None:
    r.need()
    layer_of = r.layer_of()
    cues = [
        c for c in r.interp.cues if c.kind == "no_cross" and (c.entity == layer or layer in layer_of.get(c.entity, ()))
    ]
    if kind == "no_cross":
        hard = [c for c in cues if c.hard]
        if hard:
            return None
        got = "; ".join(f"{c.kind}({c.entity}, hard={c.hard})" for c in r.interp.cues) or "none"
        return f"no hard no_cross cue on {layer} (cues: {got})"
    if cues:
        return f"a soft 'try not to / avoid crossing' made a no_cross cue on {layer}: {cues}"
    return None


def _band(r: Reading, layer: str, band: str) -> str | None:
    prefs, stated = r.prefs_on(layer)
    if not prefs:
        return f"no preference lands on layer {layer}"
    got = []
    for p in prefs:
        b = getattr(p, "band", None)
        got.append(f"{p.entity}:{b}{' prior' if getattr(p, 'prior', False) else ''}")
        if b != band or (band == "prior" and (stated or getattr(p, "prior", None) is not True)):
            return f"layer {layer} should take band {band!r}; preferences on it: {', '.join(got)}" + (
                "" if b is not None else " (Preference has no .band)"
            )
    return None


_QUOTES = "'\"\u2018\u2019\u201c\u201d"


def _note_quotes(r: Reading, word: str) -> str | None:
    """A note quotes the word as written ("read 'vegitation' as 'vegetation'"), or, for a word
    that is an entity's own name in the plural ("streets"), the entity-to-layer mapping names it
    ("street -> road (synonym)")."""
    r.need()
    forms = "|".join(re.escape(w) for w in dict.fromkeys((word, singularise(word.lower()))))
    quoted = re.compile(rf"[{_QUOTES}]({forms})[{_QUOTES}]", re.IGNORECASE)
    mapped = re.compile(rf"(^|[:;] )({forms}) -> (?!unmatched)", re.IGNORECASE)
    notes = r.notes()
    if any(quoted.search(n) or mapped.search(n) for n in notes):
        return None
    return f"no note quotes {word!r} as written, nor maps it to a layer (notes: {notes})"


def _not_unparsed(r: Reading, word: str) -> str | None:
    r.need()
    bad = [u for u in r.interp.unparsed if word.lower() in u.lower()]
    return f"{word!r} left unparsed: {bad}" if bad else None


def _ge_prompt(r: Reading, layer: str, other: str) -> str | None:
    mine = r.cost(layer)
    ref = Reading.of(other, r.layers)
    if ref.error:
        return f"reference prompt {other!r} fails: {ref.error}"
    theirs = ref.cost(layer)
    mine_c = 1.0 if mine[1] else mine[0]
    theirs_c = 1.0 if theirs[1] else theirs[0]
    if mine_c >= theirs_c - EPS:
        return None
    return f"{layer} costs {_fmt(mine)} here, below its level under {other!r} ({_fmt(theirs)})"


# ---------------------------------------------------------------- outcome checks (costmap stage, CLI)


def write_label_scene(folder: Path, layers: Sequence[str]) -> tuple[Path, Path]:
    """A 64 x 64 label raster at 0.5 m: one vertical stripe per layer, unlabelled ground between."""
    import rasterio
    from rasterio.crs import CRS
    from rasterio.transform import from_origin

    folder.mkdir(parents=True, exist_ok=True)
    labels = np.zeros((64, 64), dtype=np.uint8)
    width = 64 // (len(layers) + 1)
    for i in range(len(layers)):
        labels[:, (i + 1) * width : (i + 1) * width + max(width - 2, 1)] = i + 1
    path = folder / "labels.tif"
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=64,
        height=64,
        count=1,
        dtype="uint8",
        crs=CRS.from_epsg(32633),
        transform=from_origin(500000.0, 4000000.0, 0.5, 0.5),
    ) as ds:
        ds.write(labels, 1)
    classes = folder / "classes.json"
    classes.write_text(json.dumps({str(i + 1): name for i, name in enumerate(layers)}), encoding="utf-8")
    return path, classes


def _run_costmap(case: Case, workdir: Path):
    """(result, error): the costmap stage on a synthetic scene of the case's layers."""
    from overseec_core.pipeline import run_costmap
    from overseec_core.synthesize.options import CostmapOptions

    labels, classes = write_label_scene(workdir / "scene", case.layers)
    n = len(list(workdir.glob("cm*")))
    out = workdir / f"cm{n:03d}" / "costmap.tif"
    out.parent.mkdir(parents=True)
    try:
        return run_costmap(CostmapOptions(out=out, labels=labels, classes=classes, prompt=case.prompt)), None
    except Exception as exc:
        return None, exc


def _outcome(case: Case, kind: str, workdir: Path, memo: dict) -> str | None:
    from overseec_core.errors import InputError, InterpretError

    if "costmap" not in memo:
        memo["costmap"] = _run_costmap(case, workdir)
    result, exc = memo["costmap"]
    if kind == "error":
        if isinstance(exc, InputError | InterpretError):
            return None
        if exc is not None:
            return f"raised {type(exc).__name__} (not InputError/InterpretError): {exc}"
        return f"no error: a costmap was made (notes: {list(result.notes)})"
    if exc is not None:
        return f"costmap stage raised {type(exc).__name__}: {exc}"
    if kind == "costmap_ok":
        return None
    notes = list(result.notes)
    r = Reading.of(case.prompt, case.layers)
    if r.interp is not None:
        notes += list(r.interp.notes)
    if any("permission" in n.lower() and "only" in n.lower() for n in notes):
        return None
    return f"no note says the prompt is permission only (notes: {notes})"


def _cli(argv: list[str]) -> tuple[int, str]:
    from overseec_core.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(argv)
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else 1
    return rc, out.getvalue() + err.getvalue()


def _cli_exit(case: Case, want: int, workdir: Path) -> str | None:
    labels, classes = write_label_scene(workdir / "scene", case.layers)
    out = workdir / "cli" / "costmap.tif"
    out.parent.mkdir(parents=True, exist_ok=True)
    rc, text = _cli(
        [
            "-q",
            "costmap",
            "--labels",
            str(labels),
            "--classes",
            str(classes),
            "--prompt",
            case.prompt,
            "--out",
            str(out),
        ]
    )
    return None if rc == want else f"`overseec costmap --prompt` exited {rc}, not {want}: {text.strip()[-300:]}"


def _cli_band(case: Case, entity: str, word: str, memo: dict) -> str | None:
    if "cli" not in memo:
        memo["cli"] = _cli(["-q", "interpret", "--offline", case.prompt])
    rc, text = memo["cli"]
    if rc != 0:
        return f"`overseec interpret` exited {rc}: {text.strip()[-300:]}"
    rows = [ln for ln in text.splitlines() if re.match(rf"\s*{re.escape(entity)}\s", ln, re.IGNORECASE)]
    if not rows:
        return f"`overseec interpret` prints no row for {entity!r}"
    if any(re.search(rf"\b{word}\b", ln[ln.lower().index(entity) + len(entity) :], re.I) for ln in rows):
        return None
    return f"`overseec interpret` row for {entity!r} lacks the word {word!r}: {rows}"


# ---------------------------------------------------------------- one case


_READING_CHECKS = {
    "preferred": lambda r, e: _level(r, e[0], e[1]),
    "neutral": lambda r, e: _level(r, e[0], e[1]),
    "avoided": lambda r, e: _level(r, e[0], e[1]),
    "lethal": lambda r, e: _level(r, e[0], e[1]),
    "not_lethal": lambda r, e: _level(r, e[0], e[1]),
    "below": lambda r, e: _order(r, e[0], e[1], e[2]),
    "not_below": lambda r, e: _order(r, e[0], e[1], e[2]),
    "near_above_far": lambda r, e: _condition(r, *e),
    "near_below_far": lambda r, e: _condition(r, *e),
    "far_band": lambda r, e: _condition(r, *e),
    "no_cross": lambda r, e: _cross(r, e[0], e[1]),
    "no_no_cross": lambda r, e: _cross(r, e[0], e[1]),
    "band": lambda r, e: _band(r, e[1], e[2]),
    "note_quotes": lambda r, e: _note_quotes(r, e[1]),
    "not_unparsed": lambda r, e: _not_unparsed(r, e[1]),
    "ge_prompt": lambda r, e: _ge_prompt(r, e[1], e[2]),
}
_OUTCOME_CHECKS = {
    "costmap_ok": lambda c, e, w, m: _outcome(c, e[0], w, m),
    "permission_note": lambda c, e, w, m: _outcome(c, e[0], w, m),
    "error": lambda c, e, w, m: _outcome(c, e[0], w, m),
    "cli_exit": lambda c, e, w, m: _cli_exit(c, e[1], w),
    "cli_band": lambda c, e, w, m: _cli_band(c, e[1], e[2], m),
}
#: Every expectation kind a case may use.
KINDS = frozenset(_READING_CHECKS) | frozenset(_OUTCOME_CHECKS)
NEEDS_READING = frozenset(_READING_CHECKS)


def check_expectation(case: Case, exp: tuple, reading: Reading | None, workdir: Path, memo: dict) -> str | None:
    """None when the expectation holds, else why not."""
    kind = exp[0]
    if kind not in KINDS:
        raise ValueError(f"unknown expectation {exp!r}")
    try:
        if kind in _READING_CHECKS:
            assert reading is not None
            return _READING_CHECKS[kind](reading, exp)
        return _OUTCOME_CHECKS[kind](case, exp, workdir, memo)
    except CaseFailure as exc:
        return f"cannot read the prompt on layers {list(case.layers)}: {exc}"
    except Exception as exc:  # a check must report, not crash the report
        return f"{type(exc).__name__} while checking: {exc}"


def check_case(case: Case, workdir: Path | None = None) -> list[str]:
    """Every failed expectation of the case, as 'expectation: reason' (empty list = pass)."""
    with contextlib.ExitStack() as stack:
        if workdir is None:
            workdir = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="mission-")))
        workdir.mkdir(parents=True, exist_ok=True)
        reading = Reading.of(case.prompt, case.layers) if any(e[0] in NEEDS_READING for e in case.expect) else None
        memo: dict = {}
        failures = []
        for exp in case.expect:
            why = check_expectation(case, exp, reading, workdir, memo)
            if why is not None:
                failures.append(f"{exp}: {why}")
        return failures


# ==============================================================================================
# Corpus invariants (checked by the tests): enough new prompts, enough per family
# ==============================================================================================

MIN_CASES = 70
MIN_PER_FAMILY = 7
#: Files whose prompts the corpus must not repeat word for word (the headline prompt excepted).
OLD_PROMPT_FILES = ("tests/interpret/test_offline.py", "tests/invariants_data.py")


#: The issue's and the brief's own example prompts (the headline excepted): not to be repeated either.
EXAMPLE_PROMPTS = (
    "prefer vegetation, roads are a last resort",
    "I would rather cross farmland than forest, and the lake is off limits",
    "avoid the buildings",
    "you may walk among the trees",
    "the river is off limits",
    "buildings are fine",
    "crossing water is ok",
    "hello there",
    "make it nice",
    "don't stray from the road",
    "stay off the road",
    "keep off the road",
    "do not cross the railway except at the road",
)


def normalise_prompt(text: str) -> str:
    return " ".join(re.sub(r"[^a-z0-9 ]+", " ", text.lower().replace("'", "")).split())


def old_prompts(repo: Path) -> set[str]:
    """Every string literal of the older prompt files, normalised."""
    import ast

    out = {normalise_prompt(p) for p in EXAMPLE_PROMPTS}
    for rel in OLD_PROMPT_FILES:
        path = repo / rel
        if not path.exists():
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                out.add(normalise_prompt(node.value))
    return out


# ==============================================================================================
# Scene-level cases: directional invariants on real maps (harness in test_mission_language.py)
# ==============================================================================================


@dataclass(frozen=True)
class SceneCase:
    """Prompt A against baseline B between fixed pixels of a scene, measured on the classes.

    Relations (route shares in ground metres; the premise is checked on B):
    ``more_on`` / ``less_on`` / ``zero_on`` as in tests/invariants_data.py;
    ``uses``: A plans a route (nothing it says is lethal blocks it) that runs on the classes
    (they must be crossed: both ends are on opposite sides), and B's does too;
    ``farther``: A's closest approach to the classes is strictly farther than B's.
    """

    scene: str
    start: tuple[int, int]
    goal: tuple[int, int]
    prompt_a: str
    prompt_b: str
    classes: tuple[str, ...]
    relation: str
    family: str

    @property
    def id(self) -> str:
        words = re.sub(r"[^a-z0-9 ]+", "", self.prompt_a.lower()).split()
        return f"{self.scene}-{self.family}-{self.relation}-" + "_".join(words[:6])


S = SceneCase
SCENE_CASES: list[SceneCase] = [
    # 1. negation over motion verbs
    S(
        "nb1",
        (20, 140),
        (290, 140),
        "don't wander off the road",
        "avoid the buildings",
        ("road",),
        "more_on",
        "negation_motion",
    ),
    S(
        "nb1",
        (10, 154),
        (280, 154),
        "keep off the roadway",
        "avoid the buildings",
        ("road",),
        "less_on",
        "negation_motion",
    ),
    S(
        "sample",
        (80, 790),
        (680, 630),
        "do not stray from the trail",
        "avoid the buildings",
        ("trail",),
        "more_on",
        "negation_motion",
    ),
    # 2. last resort
    S(
        "sample",
        (20, 640),
        (600, 640),
        "prefer the grass; the road is a last resort",
        "avoid the buildings",
        ("road",),
        "less_on",
        "last_resort",
    ),
    S(
        "nb1",
        (10, 154),
        (280, 154),
        "go over open ground, roads only as a last resort",
        "avoid the water",
        ("road",),
        "less_on",
        "last_resort",
    ),
    # 3. comparatives and chains
    S(
        "sample",
        (80, 790),
        (680, 630),
        "trail over road over grass",
        "avoid the buildings",
        ("trail",),
        "more_on",
        "comparative",
    ),
    S(
        "nb2",
        (60, 90),
        (160, 200),
        "I'd rather walk through vegetation than past the buildings",
        "avoid the water",
        ("vegetation",),
        "more_on",
        "comparative",
    ),
    # 4. conditions
    S(
        "sample",
        (760, 330),
        (1000, 520),
        "grass is fine unless close to the buildings",
        "avoid the water",
        ("building",),
        "farther",
        "condition",
    ),
    # 5. scope of off limits
    S(
        "nb1",
        (5, 215),
        (260, 250),
        "I would sooner cross vegetation than buildings; the lake is a no-go",
        "you can wade through the lake",
        ("water (Hydro)",),
        "zero_on",
        "scope",
    ),
    S(
        "sample",
        (60, 560),
        (420, 980),
        "rather the trees than the buildings, and the river is off limits",
        "avoid the buildings",
        ("tree",),
        "uses",
        "scope",
    ),
    # 6. do not cross / never cross
    S(
        "nb2",
        (258, 5),
        (362, 300),
        "do not cross the railway",
        "walking on the railway is fine",
        ("railway (Train)",),
        "less_on",
        "no_cross",
    ),
    S(
        "nb2",
        (200, 60),
        (330, 60),
        "never cross the railway",
        "avoid the buildings",
        ("railway (Train)",),
        "uses",
        "no_cross",
    ),
    S(
        "nb2",
        (258, 5),
        (362, 300),
        "try not to cross the tracks",
        "the railway is fine",
        ("railway (Train)",),
        "less_on",
        "no_cross",
    ),
]

# ---------------------------------------------------------------- the priors figure
PRIOR_SCENES = ("sample", "nb1", "nb2")
PRIOR_PAIRS = 40
PRIOR_SEED = 20250220
PRIOR_TOLERANCE = 1.2
#: The paper-style rank costmap: rank -> cost, per class name (absent classes are left out).
PRIOR_RANK_COSTS: dict[str, float] = {
    "road": 0.0,
    "trail": 0.0,
    "grass": 0.25,
    "vegetation": 0.25,  # the New Brunswick clips' vegetation stands for the paper's grass
    "baseball field": 0.5,
    "tree": 0.75,
    "building": 1.0,
    "water": 1.0,
}
#: Classes (classes.json names) whose metres the figure counts: the unmentioned hazards.
PRIOR_HAZARD_CLASSES = {
    "sample": ("building", "water"),
    "nb1": ("building", "water (Hydro)"),
    "nb2": ("building", "water (Hydro)"),
}


def rank_program(layer_names: Sequence[str]) -> str:
    """The hand-written rank costmap program over the layers that exist (unlabelled ground 0.5)."""
    terms = [
        f'{cost - NEUTRAL:g} * P["{name}"]'
        for name, cost in PRIOR_RANK_COSTS.items()
        if name in layer_names and cost != NEUTRAL
    ]
    lines = ["# paper-style ranks: road, trail 1; grass 2; baseball field 3; tree 4; building, water 5"]
    lines.append(f"acc = sum({', '.join(terms)})" if len(terms) > 1 else f"acc = {terms[0]}")
    lines.append("cost = clip(0.5 + acc, 0.0, 1.0)")
    return "\n".join(lines) + "\n"


def literal_prompts(repo: Path, patterns: Sequence[str]) -> set[str]:
    """Every string literal of the files matching ``patterns`` (below ``repo``), plus the issue's
    example prompts, normalised: what a held-out set must not repeat."""
    import ast

    out = {normalise_prompt(p) for p in EXAMPLE_PROMPTS}
    for pattern in patterns:
        for path in sorted(repo.glob(pattern)):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Constant) and isinstance(node.value, str):
                    out.add(normalise_prompt(node.value))
    return out


#: Expectation kinds that name two layers (the others name one).
TWO_LAYER_KINDS = ("below", "not_below", "near_above_far", "near_below_far", "far_band")


def format_problems(case: Case) -> list[str]:
    """What is malformed in a case's expectations (empty = well formed)."""
    out = [] if case.expect else [f"{case.id}: no expectation"]
    for e in case.expect:
        kind = e[0]
        names = e[1:3] if kind in TWO_LAYER_KINDS else e[1:2]
        if kind not in KINDS:
            out.append(f"{case.id}: unknown kind {e}")
        elif (
            kind in NEEDS_READING and kind not in ("note_quotes", "not_unparsed") and not set(names) <= set(case.layers)
        ):
            out.append(f"{case.id}: {e} names a layer the case lacks")
        elif kind in ("note_quotes", "not_unparsed") and not (
            isinstance(e[1], str) and e[1].lower() in case.prompt.lower()
        ):
            out.append(f"{case.id}: {e} quotes no word of the prompt")
        elif (kind in ("band", "cli_band") and e[2] not in BANDS) or (kind == "far_band" and e[3] not in BANDS):
            out.append(f"{case.id}: {e} names an unknown band")
        elif kind == "ge_prompt" and not (isinstance(e[2], str) and e[2] != case.prompt):
            out.append(f"{case.id}: {e} compares the prompt with itself")
        elif kind == "cli_exit" and not isinstance(e[1], int):
            out.append(f"{case.id}: {e} needs an integer exit status")
    return out
