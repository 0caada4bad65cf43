"""Interpret a prompt with an LLM: the paper's two calls, with validation and bounded repair.

1. **Entities**: the ``entities`` template asks for entities (linear/areal), preferences,
   hierarchy, cues and unparsed fragments as one JSON object, with JSON-schema structured output
   where the server supports it. The reply is parsed tolerantly (code fences stripped, the first
   JSON object found) and validated field by field; an unusable reply goes back to the LLM with
   the reason, at most ``config.attempts`` times in all.
2. **Program**: the ``program`` template gives the prompt, the merged entities/preferences (JSON),
   the cost language's :func:`~overseec_core.costlang.operator_reference` and the program the
   preferences give mechanically. The reply is checked with
   :func:`~overseec_core.costlang.check_program`; an invalid program goes back with the
   CostProgramError (line, column, message), at most ``config.attempts`` times. If it is still
   invalid, the mechanical program is used and the notes say so.

LLM output is data: JSON is parsed with :mod:`json`, programs by the cost language's checker;
nothing from a reply is ever executed. Notes show the endpoint as ``config.display_url`` and pass
through ``config.redact``: the API key and URL credentials never reach the manifest.

Failures of the LLM itself (unreachable, HTTP errors after retries, timeouts) raise
:class:`~overseec_core.errors.LLMError` -- the user asked for an LLM and should hear it is not
there -- unless ``config.fallback_offline`` is set, in which case the offline interpreter answers
and the notes say why.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from typing import Any

from overseec_core.costlang import Program, check_program, operator_reference
from overseec_core.costlang.scale import check_scale
from overseec_core.errors import CostProgramError, LLMError
from overseec_core.interpret import lexicon
from overseec_core.interpret.llm import LLMConfig
from overseec_core.interpret.llm_client import ChatClient
from overseec_core.interpret.merge import finalize, make_entity, synthesize_program
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.priors import PriorTable
from overseec_core.interpret.templates import load_template, template_ids
from overseec_core.progress import Progress, check_cancelled
from overseec_core.schema import CUE_KINDS, DEFAULT_ENTITIES, GEOMETRIES, Cue, Entity, Interpretation

#: At most this many entities from one reply (more is a runaway reply, not a mission).
MAX_ENTITIES = 32
MAX_NAME_CHARS = 64
#: Largest cue distance accepted from a reply (the cost language's radius limit).
MAX_CUE_METRES = 500.0

_STR = {"type": "string"}
_NULLABLE_NUM = {"type": ["number", "null"]}
_NULLABLE_STR = {"type": ["string", "null"]}


def _obj(props: dict) -> dict:
    return {"type": "object", "additionalProperties": False, "required": list(props), "properties": props}


#: JSON schema of the entity reply. Strict-mode compatible (every property required, no extra
#: ones) and without numeric bounds, which some servers refuse; parse_entity_reply checks ranges.
ENTITY_SCHEMA: dict[str, Any] = _obj(
    {
        "entities": {
            "type": "array",
            "items": _obj(
                {
                    "name": _STR,
                    "geometry": {"type": "string", "enum": list(GEOMETRIES)},
                    "prompts": {"type": "array", "items": _STR},
                }
            ),
        },
        "preferences": {
            "type": "array",
            "items": _obj(
                {
                    "entity": _STR,
                    "rank": {"type": "integer"},
                    "weight": {"type": "number"},
                    "lethal": {"type": "boolean"},
                }
            ),
        },
        "hierarchy": {"type": "array", "items": _obj({"child": _STR, "parent": _STR})},
        "cues": {
            "type": "array",
            "items": _obj(
                {
                    "kind": {"type": "string", "enum": list(CUE_KINDS)},
                    "entity": _STR,
                    "metres": _NULLABLE_NUM,
                    "other": _NULLABLE_STR,
                    "hard": {"type": "boolean"},
                }
            ),
        },
        "unparsed": {"type": "array", "items": _STR},
    }
)


def response_format() -> dict[str, Any]:
    """The ``response_format`` asking for ENTITY_SCHEMA (OpenAI / vLLM / Ollama / llama.cpp)."""
    return {
        "type": "json_schema",
        "json_schema": {"name": "overseec_interpretation", "strict": True, "schema": ENTITY_SCHEMA},
    }


class ReplyError(ValueError):
    """A reply that cannot be used; the message goes back to the LLM."""


# ----------------------------------------------------------------------------- tolerant parsing

_FENCE = re.compile(r"```[ \t]*[A-Za-z0-9_+.-]*[ \t]*\r?\n(.*?)```", re.DOTALL)


def extract_json_object(text: str) -> dict:
    """The first JSON object in a reply: whole text, else inside a code fence, else anywhere."""
    text = (text or "").strip()
    if not text:
        raise ReplyError("the reply is empty")
    candidates = [text] + [m.group(1).strip() for m in _FENCE.finditer(text)]
    first_error = None
    for cand in candidates:
        try:
            value = json.loads(cand)
        except ValueError as exc:
            first_error = first_error or exc
            continue
        if isinstance(value, dict):
            return value
    decoder = json.JSONDecoder()
    for tries, match in enumerate(re.finditer(r"\{", text)):
        if tries >= 200:
            break
        try:
            value, _ = decoder.raw_decode(text, match.start())
        except ValueError:
            continue
        if isinstance(value, dict):
            return value
    detail = (
        f" ({first_error.msg} at line {first_error.lineno}, column {first_error.colno})"
        if isinstance(first_error, json.JSONDecodeError)
        else ""
    )
    raise ReplyError(f"the reply contains no valid JSON object{detail}")


def extract_program(text: str) -> str:
    """The program in a reply: the first fenced block, a JSON {"program": ...}, or the text."""
    text = (text or "").strip()
    m = _FENCE.search(text)
    if m:
        return m.group(1).strip()
    if text.startswith("{"):
        try:
            value = json.loads(text)
            if isinstance(value, dict) and isinstance(value.get("program"), str):
                return value["program"].strip()
        except ValueError:
            pass
    if text.startswith("```"):  # an unterminated fence
        text = text.split("\n", 1)[1] if "\n" in text else ""
    return text.strip()


def _name(value: Any, where: str) -> str:
    if not isinstance(value, str):
        raise ReplyError(f"{where} must be a string, got {type(value).__name__}")
    name = " ".join(value.replace('"', " ").split()).lower()
    if not name or not any(ch.isalpha() for ch in name):
        raise ReplyError(f"{where} {value!r} is not an entity name")
    if len(name) > MAX_NAME_CHARS or any(ord(ch) < 32 for ch in name):
        raise ReplyError(f"{where} {value[:40]!r}... is too long or has control characters")
    return name


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool):
        raise ReplyError(f"{where} must be a number, got a boolean")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ReplyError(f"{where} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ReplyError(f"{where} must be finite, got {value!r}")
    return x


def _bool(value: Any, where: str) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip().lower() in ("true", "false"):
        return value.strip().lower() == "true"
    if value in (0, 1):
        return bool(value)
    raise ReplyError(f"{where} must be true or false, got {value!r}")


def _list(obj: dict, key: str) -> list:
    value = obj.get(key, [])
    if value is None:
        return []
    if not isinstance(value, list):
        raise ReplyError(f'"{key}" must be a list, got {type(value).__name__}')
    return value


@dataclasses.dataclass(frozen=True)
class EntityReply:
    """A validated entity reply, before merging with the defaults."""

    entities: tuple[Entity, ...]
    stated: dict[str, tuple[float, bool]]
    hierarchy: tuple[tuple[str, str], ...]
    cues: tuple[Cue, ...]
    unparsed: tuple[str, ...]
    notes: tuple[str, ...]


def parse_entity_reply(obj: dict) -> EntityReply:  # noqa: C901
    """Validate and normalise an entity reply; raise ReplyError with what to fix."""
    if not isinstance(obj, dict):
        raise ReplyError("the reply must be a JSON object")
    if "entities" not in obj:
        raise ReplyError('the reply has no "entities" list')
    notes: list[str] = []
    entities: dict[str, Entity] = {}
    raw_entities = _list(obj, "entities")
    if len(raw_entities) > MAX_ENTITIES:
        raise ReplyError(f"{len(raw_entities)} entities; name at most {MAX_ENTITIES}")
    for i, e in enumerate(raw_entities):
        if isinstance(e, str):
            e = {"name": e}
        if not isinstance(e, dict):
            raise ReplyError(f"entities[{i}] must be an object with name and geometry")
        name = _name(e.get("name"), f"entities[{i}].name")
        geometry = e.get("geometry")
        if geometry not in GEOMETRIES:
            guess = lexicon.geometry_of(name)
            if geometry is not None:
                notes.append(f"entity '{name}': geometry {geometry!r} is not linear/areal; used {guess}")
            geometry = guess
        prompts = tuple(
            " ".join(str(p).split())[:MAX_NAME_CHARS]
            for p in (e.get("prompts") or [])
            if isinstance(p, str) and p.strip()
        )[:3]
        if name not in entities:
            entities[name] = make_entity(name, geometry, prompts)
    stated: dict[str, tuple[float, bool]] = {}
    ranks: dict[str, int] = {}
    for i, p in enumerate(_list(obj, "preferences")):
        if not isinstance(p, dict):
            raise ReplyError(f"preferences[{i}] must be an object with entity, rank, weight, lethal")
        name = _name(p.get("entity"), f"preferences[{i}].entity")
        if name not in entities:
            entities[name] = make_entity(name)
            notes.append(f"preference for '{name}', which the reply did not list as an entity; added it")
        lethal = _bool(p.get("lethal", False), f"preferences[{i}].lethal")
        if p.get("rank") is not None:
            ranks[name] = max(1, int(_number(p["rank"], f"preferences[{i}].rank")))
        if p.get("weight") is None:
            if lethal:
                stated[name] = (1.0, True)
            elif name not in ranks:
                raise ReplyError(f"preferences[{i}] ('{name}') has neither weight nor rank")
            continue
        w = _number(p["weight"], f"preferences[{i}].weight")
        if not 0.0 <= w <= 1.0:
            notes.append(f"'{name}': weight {w:g} is outside [0, 1]; clipped")
            w = min(1.0, max(0.0, w))
        if name in stated:
            notes.append(f"'{name}' has two preferences; kept the last")
        stated[name] = (1.0 if lethal else w, lethal)
    missing = [n for n in ranks if n not in stated]
    if missing:  # weights from ranks: rank 1 -> PREFER ... worst rank -> AVOID
        top = max(ranks.values())
        for n in missing:
            frac = (ranks[n] - 1) / (top - 1) if top > 1 else 0.0
            stated[n] = (round(lexicon.PREFER + frac * (lexicon.AVOID - lexicon.PREFER), 6), False)
        notes.append(f"weights derived from ranks for {', '.join(missing)}")
    pairs: list[tuple[str, str]] = []
    for i, h in enumerate(_list(obj, "hierarchy")):
        if isinstance(h, dict):
            child, parent = h.get("child"), h.get("parent")
        elif isinstance(h, (list, tuple)) and len(h) == 2:
            child, parent = h
        else:
            raise ReplyError(f'hierarchy[{i}] must be {{"child": ..., "parent": ...}}')
        pairs.append((_name(child, f"hierarchy[{i}].child"), _name(parent, f"hierarchy[{i}].parent")))
    cues: list[Cue] = []
    for i, c in enumerate(_list(obj, "cues")):
        if not isinstance(c, dict):
            raise ReplyError(f"cues[{i}] must be an object with kind, entity, metres, other")
        kind = str(c.get("kind", "")).strip().lower()
        kind = {"center": "centre", "middle": "centre", "edge": "side", "sides": "side", "edges": "side"}.get(
            kind, kind
        )
        entity = _name(c.get("entity"), f"cues[{i}].entity")
        other = _name(c["other"], f"cues[{i}].other") if c.get("other") not in (None, "") else None
        metres = None
        if c.get("metres") is not None:
            metres = _number(c["metres"], f"cues[{i}].metres")
            if metres <= 0 or metres > MAX_CUE_METRES:
                clipped = min(MAX_CUE_METRES, max(0.5, metres))
                notes.append(
                    f"{kind} cue on '{entity}': {metres:g} m is outside (0, {MAX_CUE_METRES:g}] m; used {clipped:g} m"
                )
                metres = clipped
        if kind in ("unless_near", "if_near") and other is None:
            notes.append(f"{kind} cue on '{entity}' names no other entity; dropped")
            continue
        for named in (entity, other):
            if named is not None and named not in entities:
                entities[named] = make_entity(named)
        hard = _bool(c.get("hard", False), f"cues[{i}].hard") if c.get("hard") is not None else False
        if kind in ("near", "far", "unless_near", "if_near") and metres is None:
            graded = kind in ("near", "far") and not hard
            metres = lexicon.DEFAULT_GRADED_DISTANCE_M if graded else lexicon.DEFAULT_CUE_DISTANCE_M
        cues.append(Cue(kind, entity, metres, other, hard))
    unparsed = tuple(" ".join(str(u).split()) for u in _list(obj, "unparsed") if str(u).strip())
    for name in (n for pair in pairs for n in pair):
        if name not in entities and name not in dict(DEFAULT_ENTITIES):
            entities[name] = make_entity(name)
    return EntityReply(tuple(entities.values()), stated, tuple(pairs), tuple(cues), unparsed, tuple(notes))


# ----------------------------------------------------------------------------- the two calls


def _entities_json(it: Interpretation) -> str:
    doc = it.to_json()
    keep = {k: doc[k] for k in ("entities", "preferences", "hierarchy", "cues")}
    for e in keep["entities"]:
        e.pop("threshold", None)
    return json.dumps(keep, indent=1)


def _ask_entities(
    client: ChatClient, config: LLMConfig, prompt: str, progress: Progress | None
) -> tuple[EntityReply, list[str]]:
    tpl = load_template("entities")
    defaults = ", ".join(f'"{n}" ({g})' for n, g in DEFAULT_ENTITIES)
    messages = [
        {
            "role": "system",
            "content": tpl.render("system", defaults=defaults, schema=json.dumps(ENTITY_SCHEMA, indent=1)),
        },
        {"role": "user", "content": tpl.render("user", prompt=prompt)},
    ]
    notes: list[str] = []
    last: ReplyError | None = None
    for attempt in range(1, config.attempts + 1):
        if progress is not None:
            check_cancelled(progress)
        text = client.complete(messages, response_format=response_format())
        try:
            reply = parse_entity_reply(extract_json_object(text))
        except ReplyError as exc:
            last = exc
            notes.append(f"entity reply {attempt} unusable: {exc}")
            if progress is not None:
                progress.message(f"LLM entity reply unusable ({exc}); asking again")
            messages += [
                {"role": "assistant", "content": text},
                {"role": "user", "content": tpl.render("repair", error=str(exc))},
            ]
            continue
        return reply, notes
    raise LLMError(f"the LLM gave no usable entity reply in {config.attempts} attempts (last problem: {last})")


def _check_terrain(program: Program, terrain: bool) -> None:
    """Refuse a program that reads a terrain field (``slope``, ``roughness``) when the run has no
    DEM: the reference did not offer them, and the costmap would fail on them later."""
    used = program.terrain
    if used and not terrain:
        raise CostProgramError(
            f"'{used[0]}' is a terrain field and this run has no DEM; use only the entity layers", None, None
        )


def _ask_program(
    client: ChatClient,
    config: LLMConfig,
    it: Interpretation,
    baseline: str,
    progress: Progress | None,
    terrain: bool = False,
) -> tuple[str | None, list[str]]:
    """The LLM's program if valid within the attempts, else None; plus notes.

    ``terrain``: the run has a DEM, so the reference offers ``slope`` and ``roughness``."""
    tpl = load_template("program")
    names = [e.name for e in it.entities]
    messages = [
        {
            "role": "system",
            "content": tpl.render(
                "system", reference=operator_reference(terrain), names=", ".join(json.dumps(n) for n in names)
            ),
        },
        {
            "role": "user",
            "content": tpl.render("user", prompt=it.prompt, entities=_entities_json(it), baseline=baseline.strip()),
        },
    ]
    notes: list[str] = []
    last = ""
    for attempt in range(1, config.attempts + 1):
        if progress is not None:
            check_cancelled(progress)
        text = client.complete(messages)
        program = extract_program(text)
        try:
            if not program:
                raise CostProgramError("the reply contains no program", None, None)
            checked = check_program(program, names)
            _check_terrain(checked, terrain)
            check_scale(checked, it.preferences, it.hierarchy, it.cues)
        except CostProgramError as exc:
            last = str(exc)
            notes.append(f"program {attempt} invalid: {last}")
            if progress is not None:
                progress.message(f"LLM program invalid ({last}); asking again")
            messages += [
                {"role": "assistant", "content": text},
                {"role": "user", "content": tpl.render("repair", error=last)},
            ]
            continue
        notes.append(f"program: written by the LLM, valid on attempt {attempt}")
        notes.extend(f"program warning: {w}" for w in checked.warnings)
        return program + ("\n" if not program.endswith("\n") else ""), notes
    notes.append(
        f"program: the LLM's program was still invalid after {config.attempts} attempts "
        f"(last error: {last}); used the program derived from the preferences instead"
    )
    return None, notes


def _redacted(config: LLMConfig, notes: tuple[str, ...]) -> tuple[str, ...]:
    """``notes`` without the configuration's secrets: notes go to the manifest and the screen.

    Replies are already redacted by the client; this also covers text built here (error messages
    quoted in notes), so no path from a secret to a note is left to chance.
    """
    return tuple(config.redact(n) for n in notes)


def interpret_llm(
    prompt: str,
    config: LLMConfig,
    *,
    progress: Progress | None = None,
    client: ChatClient | None = None,
    priors: PriorTable | None = None,
    terrain: bool = False,
) -> Interpretation:
    """Interpret ``prompt`` with the LLM in ``config`` (two calls); see the module docstring.

    The LLM's stated preferences are merged with ``priors`` (None = built-in) exactly as the
    offline interpreter's are, and its program must keep the merged levels (``check_scale``).
    ``terrain``: the run has a DEM (``--dem``), so the program call offers the terrain fields
    ``slope`` (degrees) and ``roughness`` (metres); without one they are neither offered nor
    accepted."""
    client = client or ChatClient(config, progress=progress)
    head = [f"interpreter: LLM {config.model} at {config.display_url}", f"templates: {', '.join(template_ids())}"]
    if progress is not None:
        progress.begin("interpret", 2, unit="call")
    try:
        try:
            reply, e_notes = _ask_entities(client, config, prompt, progress)
        except LLMError as exc:
            if not config.fallback_offline:
                raise
            it = interpret_offline(prompt, priors=priors)
            return dataclasses.replace(
                it, notes=_redacted(config, (f"LLM failed ({exc}); interpreted offline",) + it.notes)
            )
        if progress is not None:
            progress.advance()
        if not client.structured_ok and config.structured:
            e_notes.append("the server does not support structured output; reply parsed tolerantly")
        it = finalize(
            prompt,
            mentioned=reply.entities,
            stated=reply.stated,
            hierarchy=reply.hierarchy,
            cues=reply.cues,
            unparsed=reply.unparsed,
            notes=head + e_notes + list(reply.notes),
            source=f"llm:{config.model}",
            program="",
            priors=priors,
        )
        baseline = synthesize_program(it.entities, it.preferences, it.hierarchy, it.cues)
        try:
            program, p_notes = _ask_program(client, config, it, baseline, progress, terrain)
        except LLMError as exc:
            if not config.fallback_offline:
                raise
            program, p_notes = None, [f"program: LLM failed ({exc}); used the program derived from the preferences"]
        if progress is not None:
            progress.advance()
        return dataclasses.replace(it, program=program or baseline, notes=_redacted(config, it.notes + tuple(p_notes)))
    finally:
        if progress is not None:
            progress.end()
