"""Interpret: a mission prompt -> entities, preferences, hierarchy, cues and a cost program.

Two interpreters produce the same :class:`~overseec_core.schema.Interpretation`:

- the **offline** interpreter (:mod:`.offline`): deterministic rules, no network; the default.
  Its grammar reads the tables of :mod:`.lexicon` in steps, one module each: :mod:`.tokens`,
  :mod:`.sentence` (mentions), :mod:`.conditions` (conditions and cues), :mod:`.comparisons`,
  :mod:`.clauses` (clauses and their tiers), :mod:`.statements` (the weights they come to);
- the **LLM** interpreter (:mod:`.llm_interpreter`): the paper's two calls to an
  OpenAI-compatible chat API (:mod:`.llm_client`, configured by :mod:`.llm`), with prompts from
  versioned templates (:mod:`.templates`).

Which one runs (:func:`interpret`): ``offline=True`` -> offline; ``offline=False`` -> the LLM
(``llm``, else the environment; an error if none is configured); ``offline=None`` -> the LLM when
one is given or configured in the environment (``OVERSEEC_LLM_URL``), else offline.
"""

from __future__ import annotations

from overseec_core.errors import InterpretError
from overseec_core.interpret.llm import LLMConfig, resolve_config
from overseec_core.interpret.llm_interpreter import interpret_llm
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.priors import BUILT_IN as BUILT_IN_PRIORS
from overseec_core.interpret.priors import PriorTable, load_priors, resolve_priors
from overseec_core.progress import Progress
from overseec_core.schema import CUE_KINDS, DEFAULT_ENTITIES, GEOMETRIES, Cue, Entity, Interpretation, Preference

#: Longest prompt accepted (characters): a mission, not a document.
MAX_PROMPT_CHARS = 4000


def check_prompt(prompt: str) -> str:
    """The prompt, stripped; InterpretError when it is empty, wordless or too long."""
    if not isinstance(prompt, str):
        raise InterpretError("the mission prompt must be text")
    text = prompt.strip()
    if not text:
        raise InterpretError(
            'the mission prompt is empty; say what the route should prefer or avoid, e.g. "prefer roads, avoid water"'
        )
    if not any(ch.isalpha() for ch in text):
        raise InterpretError(f"the mission prompt {text[:40]!r} has no words")
    if len(text) > MAX_PROMPT_CHARS:
        raise InterpretError(f"the mission prompt has {len(text)} characters; at most {MAX_PROMPT_CHARS} are accepted")
    return text


def interpret(
    prompt: str,
    *,
    offline: bool | None = None,
    llm: LLMConfig | None = None,
    progress: Progress | None = None,
    priors: PriorTable | None = None,
    terrain: bool = False,
) -> Interpretation:
    """Interpret a mission prompt (see the module docstring for which interpreter runs).

    ``priors``: the costs of hazards the prompt leaves unsaid (:mod:`.priors`; None = built-in).
    ``terrain``: the costmap will have a DEM, so the LLM may read ``slope`` and ``roughness`` (the
    offline interpreter's program gets its slope rule when the costmap is built)."""
    text = check_prompt(prompt)
    if offline is True:
        config = None
    else:
        config = llm or resolve_config()
        if config is None and offline is False:
            raise InterpretError(
                "no LLM configured: give --llm-url and --llm-model (or set "
                "OVERSEEC_LLM_URL and OVERSEEC_LLM_MODEL), or interpret offline"
            )
    if config is None:
        return interpret_offline(text, priors=priors)
    return interpret_llm(text, config, progress=progress, priors=priors, terrain=terrain)


__all__ = [
    "BUILT_IN_PRIORS",
    "CUE_KINDS",
    "DEFAULT_ENTITIES",
    "GEOMETRIES",
    "Cue",
    "Entity",
    "Interpretation",
    "LLMConfig",
    "MAX_PROMPT_CHARS",
    "Preference",
    "PriorTable",
    "check_prompt",
    "interpret",
    "load_priors",
    "resolve_config",
    "resolve_priors",
]
