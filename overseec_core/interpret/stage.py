"""Interpret's front door: a prompt -> an :class:`~overseec_core.schema.Interpretation`, with
its run-folder record.
"""

from __future__ import annotations

import os

from overseec_core import runfiles
from overseec_core.errors import InputError
from overseec_core.interpret import interpret
from overseec_core.interpret.llm import LLMConfig, resolve_config
from overseec_core.interpret.priors import BUILT_IN as BUILT_IN_PRIORS
from overseec_core.interpret.priors import PriorTable
from overseec_core.interpret.templates import template_ids
from overseec_core.io.manifest import RunDir, write_json_atomic
from overseec_core.io.write import check_output_path
from overseec_core.progress import Progress
from overseec_core.schema import Interpretation


def require_all_read(interp: Interpretation) -> None:
    """``--strict``: an :class:`InputError` (exit 2) naming every clause of the prompt that was not
    understood, so a batch run never plans on half a brief."""
    if interp.unparsed:
        quoted = "; ".join(repr(u) for u in interp.unparsed)
        raise InputError(
            f"--strict: {len(interp.unparsed)} clause(s) of the prompt were not understood: {quoted}; "
            "reword them, or drop --strict to run without them"
        )


# --- stage: interpret ---
def run_interpret(
    prompt: str,
    *,
    offline: bool | None = None,
    llm: LLMConfig | None = None,
    llm_url: str | None = None,
    llm_model: str | None = None,
    api_key: str | None = None,
    llm_key_env: str | None = None,
    llm_timeout: float | None = None,
    llm_retries: int | None = None,
    llm_fallback_offline: bool | None = None,
    out: str | os.PathLike | None = None,
    run_dir: str | os.PathLike | None = None,
    progress: Progress | None = None,
    command_args: dict | None = None,
    priors: PriorTable | None = None,
    terrain: bool = False,
) -> Interpretation:
    """Interpret: prompt -> entities, preferences, hierarchy, cues and a cost program.

    ``priors``: what hazards the prompt leaves unsaid cost (None = the built-in table); the
    table used is recorded in the run's manifest. ``terrain``: the costmap will have a DEM, so
    the LLM is offered ``slope`` and ``roughness`` (recorded in the manifest).

    The LLM runs when ``llm`` or ``llm_url`` is given, or ``OVERSEEC_LLM_URL`` is set and
    ``offline`` is not True; otherwise the offline interpreter. ``out`` gets the JSON document
    (atomically); ``run_dir`` gets it as ``interpretation.json`` plus a manifest entry
    (``interpretation``, the LLM settings without the key, templates, timing).
    """
    if offline and (llm is not None or llm_url):
        raise InputError("--offline and an LLM (--llm-url) were both given; choose one")
    config = llm
    if config is None and not offline:
        config = resolve_config(
            url=llm_url,
            model=llm_model,
            key_env=llm_key_env,
            api_key=api_key,
            timeout_s=llm_timeout,
            retries=llm_retries,
            fallback_offline=llm_fallback_offline,
        )
    if out is not None:
        check_output_path(out, [])  # before the (possibly slow) LLM calls
    run = RunDir(run_dir, command="interpret", args=command_args) if run_dir is not None else None
    table = BUILT_IN_PRIORS if priors is None else priors
    if run is None:
        result = interpret(prompt, offline=config is None, llm=config, progress=progress, priors=table, terrain=terrain)
    else:
        run.update_parameters(
            interpret={
                "interpreter": "llm" if config else "offline",
                "llm": config.describe() if config else None,
                "templates": list(template_ids()) if config else [],
                "priors": table.to_json(),
                "terrain": terrain,
            }
        )
        with run.stage("interpret"):
            result = interpret(
                prompt, offline=config is None, llm=config, progress=progress, priors=table, terrain=terrain
            )
        run.set("interpretation", result.to_json())
        write_json_atomic(run.file(runfiles.INTERPRETATION), result.to_json())
        run.save()
    if out is not None:
        write_json_atomic(out, result.to_json())
    return result
