"""The one mapping from the plugin's forms to the core: worker command lines and light helpers.

The dock and the Processing algorithms both go through this package, so the same parameters
mean the same thing everywhere, and QGIS computes nothing itself:

* every stage (reading check, interpret, segment, costmap, run) is an ``overseec
  --json-progress <command> ...`` argv for the worker process (:mod:`.argv`), never a shell
  string; results come back as the CLI's ``--json`` document (:mod:`.results` reads them).
  QGIS's own Python (no rasterio, no planner kernel on Windows and macOS) only checks and edits
  text: the cost program (``costlang``), entity tables, interpretations (this module);
* the LLM endpoint, model and API key reach the worker through the environment the CLI reads
  (``OVERSEEC_LLM_URL``, ``OVERSEEC_LLM_MODEL``, ``OVERSEEC_LLM_API_KEY``), never its command
  line (visible to every user in ``ps``; a URL may hold credentials).

Callers use ``jobs.<name>`` for all three parts (the argv builders and result readers are
re-exported here). Core modules are imported inside functions: loading the plugin stays cheap
and never pulls in anything heavy (and never torch). :func:`layer_names` and
:func:`fit_to_layers` use the core's layer reader when QGIS's Python has rasterio, and fall back
to the entities table otherwise (the worker's costmap then checks the names).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from overseec_core import runfiles
from overseec_core.errors import CostProgramError, InputError, OverseecError  # noqa: F401 -- re-exported

from .. import envcheck
from ..params import BUILT_IN_PRIORS, OFFLINE, LlmSettings, Params, Priors
from ..worker import configured_worker, find_worker, worker_env  # noqa: F401 -- worker_env re-exported
from .argv import (  # noqa: F401 -- re-exported: callers use jobs.<name>
    API_KEY_ENV,
    LLM_MODEL_ENV,
    LLM_URL_ENV,
    corridor_command,
    costmap_command,
    info_command,
    interpret_command,
    llm_cli,
    pairs_command,
    program_input_path,
    run_command,
    segment_command,
    with_thresholds,
    write_interpretation,
)
from .results import (  # noqa: F401 -- re-exported
    CostmapSummary,
    describe_info,
    interpretation_from_json,
    result_document,
    run_json,
)


def core_version() -> str:
    """The core's version: the dock re-runs its environment check once per new version."""
    from overseec_core import __version__

    return __version__


# --------------------------------------------------------------------------------------------
# Input
# --------------------------------------------------------------------------------------------


def layer_file(layer) -> str:
    """The file behind a GDAL raster layer ('' for non-file sources such as WMS)."""
    if layer.providerType() != "gdal":
        return ""
    path = layer.source().split("|")[0]
    return path if Path(path).is_file() else ""


def no_worker_message() -> str:
    """Why there is no worker, in one line (the environment check's first problem)."""
    report = envcheck.check_worker(None)
    return report.problems[0] if report.problems else "no overseec environment"


# --------------------------------------------------------------------------------------------
# Interpret and the cost program
# --------------------------------------------------------------------------------------------


def check_program(text: str, entity_names: Sequence[str]):
    """Check a cost program against the entity names with the core's checker (runs in QGIS's own
    Python: costlang needs no rasterio)."""
    from overseec_core.costlang import check_program as check

    return check(text, entity_names)


def edited_interpretation(base, prompt: str, rows: Sequence[Mapping[str, Any]], program: str):
    """The interpretation with the dock's edits: entity table rows and program text."""
    from overseec_core.schema import Entity, Interpretation

    entities = tuple(
        Entity(
            name=r["name"], geometry=r["geometry"], prompts=tuple(r.get("prompts") or ()), threshold=r.get("threshold")
        )
        for r in rows
    )
    if base is None:
        return Interpretation(prompt=prompt, entities=entities, preferences=(), program=program, source="edited")
    return replace(base, prompt=prompt or base.prompt, entities=entities, program=program)


def entities_from_file(path: str | os.PathLike):
    """An Interpretation holding the entities of a JSON file (a list of entities, or any document
    with "entities", e.g. `overseec interpret --json`), read by the core's entity parser (the
    one `overseec segment --entities-json` uses)."""
    from overseec_core.interpret.entity_input import load_entities_json
    from overseec_core.schema import Interpretation

    return Interpretation(
        prompt="", entities=tuple(load_entities_json(Path(path))), preferences=(), source=f"file:{Path(path).name}"
    )


def interpret(
    prompt: str,
    llm: LlmSettings = OFFLINE,
    worker: Path | None = None,
    timeout_s: float = 300.0,
    priors: Priors = BUILT_IN_PRIORS,
):
    """Prompt -> Interpretation, by ``overseec interpret --json`` in the worker (the settings'
    worker unless given: :func:`.worker.configured_worker`), waiting for it here: for scripts
    and tests; the dock runs the same command in a task."""
    if worker is None:
        worker = configured_worker()
    if worker is None:
        raise InputError(no_worker_message())
    return interpretation_from_json(run_json(*interpret_command(worker, prompt, llm, priors), timeout_s=timeout_s))


# --------------------------------------------------------------------------------------------
# Worker commands
# --------------------------------------------------------------------------------------------


def find_worker_for(settings) -> Path | None:
    """The worker (`overseec` command) the settings lead to: their command path, else their venv,
    else one found from the plugin's folder; None when there is none."""
    return find_worker(settings.worker_path, settings.venv, Path(__file__).parent.parent)  # the plugin's folder


#: Share of a run's time per stage, for one overall progress bar (segmentation dominates).
RUN_WEIGHTS = {"interpret": 1.0, "segment": 70.0, "refine": 20.0, "costmap": 3.0, "plan": 2.0, "evaluate": 1.0}


def stage_weights(command: str, params: Params, segments: bool = True) -> dict[str, float]:
    """The stages a worker command reports and their weights: refine only when it runs, no
    segmentation at all when a class raster stands in for the masks."""
    stages = {"segment": ("segment", "refine"), "run": tuple(RUN_WEIGHTS)}.get(command, (command,))
    skip = ({"refine"} if not params.refine else set()) | ({"segment", "refine"} if not segments else set())
    return {s: RUN_WEIGHTS.get(s, 1.0) for s in stages if s not in skip}


def parse_entities(text: str) -> list[dict]:
    """'road:linear, grass, baseball field:areal' -> entity rows, through the core's one entity
    parser (``overseec_core.interpret.entity_input``: without a geometry, the lexicon's, as the CLI does)."""
    from overseec_core.interpret.entity_input import parse_entity_list

    return [{"name": e.name, "geometry": e.geometry, "threshold": None, "prompts": []} for e in parse_entity_list(text)]


# --------------------------------------------------------------------------------------------
# Entity layers and the costmap
# --------------------------------------------------------------------------------------------


def layer_names(
    masks_dir: str | os.PathLike | None = None,
    labels: str | os.PathLike | None = None,
    classes: str | os.PathLike | None = None,
) -> tuple[str, ...]:
    """Entity names the costmap stage will see for these layer sources (the core decides).

    Raises ImportError where QGIS's Python cannot read rasters with the core (no rasterio):
    callers then check against the entities table and leave the layers to the worker."""
    from overseec_core.synthesize.layers import open_layers
    from overseec_core.synthesize.options import CostmapOptions

    options = CostmapOptions(
        out=Path(runfiles.COSTMAP), masks=_path(masks_dir), labels=_path(labels), classes=_path(classes)
    )
    source = open_layers(options)
    try:
        return tuple(source.names)
    finally:
        source.close()


def fit_to_layers(interp, names: Sequence[str], aliases_text: str = "", priors: Priors = BUILT_IN_PRIORS):
    """The interpretation's program fitted to the layers' names (matching, aliases, and the
    ``priors`` it was interpreted with for layers no entity stands for), as `overseec costmap
    --prompt` fits it; InputError for bad aliases, a bad priors file or nothing matched."""
    from overseec_core.interpret.matching import parse_aliases
    from overseec_core.synthesize.fit import fit_program

    try:
        aliases = parse_aliases(aliases_text)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    return fit_program(interp, list(names), dict(aliases), priors.table())


def _path(p: str | os.PathLike | None) -> Path | None:
    return Path(p) if p else None


def next_costmap_path(folder: str | os.PathLike) -> Path:
    """``costmap.tif``, then ``costmap-2.tif``, ...: each re-prompt keeps its own costmap, program
    and layer, so earlier layers (and their provenance) stay as they were."""
    folder = Path(folder)
    first = Path(runfiles.COSTMAP)
    if not (folder / first).exists():
        return folder / first
    n = 2
    while (folder / f"{first.stem}-{n}{first.suffix}").exists():
        n += 1
    return folder / f"{first.stem}-{n}{first.suffix}"


def replace_params(params: Params, **changes) -> Params:
    """A copy of ``params`` with ``changes`` applied (Params is frozen)."""
    return replace(params, **changes)


def crs_text(crs) -> str:
    """A QgsCoordinateReferenceSystem as text the core parses (EPSG:XXXX, else WKT)."""
    return crs.authid() if crs.authid().upper().startswith("EPSG:") else crs.toWkt()


# --------------------------------------------------------------------------------------------
# Environment
# --------------------------------------------------------------------------------------------


def check_worker_env(worker: Path | None) -> envcheck.EnvReport:
    """Check the worker's environment (packages, versions, model weights) in a subprocess; with no
    worker, a report saying it was not found and how to set one up."""
    return envcheck.check_worker(worker)


def environment_report(settings, progress=None) -> envcheck.EnvReport:
    """The worker check (packages, and the weights of the models the settings name): every
    stage runs there. QGIS's Python only borrows the environment's packages where it can (for
    matching program names to the entity layers as you type); lacking them is no problem."""
    worker = find_worker_for(settings)
    envcheck.ensure_core_importable(settings.venv or None, worker)
    p = settings.params
    return envcheck.check_worker(
        worker,
        clipseg_model=p.clipseg_model,
        sam_model=p.sam_model,
        refine=p.refine,
        refiner=p.refiner,
        segmenter=p.segmenter,
        model=p.model,
    )
