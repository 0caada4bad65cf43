"""Synthesize's front door: an interpretation (or a program) + entity layers -> costmap.tif, its
lethal sidecar and the program text, with the run folder's manifest.
"""

from __future__ import annotations

import json
import time as _time
from pathlib import Path

from overseec_core import runfiles
from overseec_core.costlang import check_program
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.manifest import RunDir
from overseec_core.io.transaction import transactional
from overseec_core.limits import check_pixels
from overseec_core.progress import Progress
from overseec_core.schema import Interpretation
from overseec_core.synthesize.engine import TAG_PROGRAM, check_outputs, compose_costmap, output_paths
from overseec_core.synthesize.fit import resolve_program
from overseec_core.synthesize.layers import open_layers
from overseec_core.synthesize.options import CostmapOptions, CostmapResult
from overseec_core.synthesize.overrides import TAG_OVERRIDES, load_overrides, record_overrides, tag_value


# --- stage: costmap ---
@transactional
def run_synthesize(
    options: CostmapOptions,
    progress: Progress | None = None,
    command_args: dict | None = None,
    *,
    prompt: str | None = None,
    interpretation: Interpretation | None = None,
) -> CostmapResult:
    """Program + entity layers -> costmap.tif, its lethal sidecar and the program text, beside
    each other in ``options.out``'s folder (whose manifest records inputs, program and timings).
    Only reads mask/label/vector files: re-prompting never re-runs segmentation.

    The prompt behind the program (``options.prompt``, or ``prompt`` when the program text was
    made from one elsewhere, as `run` does) goes into the costmap's tags (``OVERSEEC_PROMPT``)
    and the manifest, so that every path planned on it carries the prompt (GPX/KML names).

    A prompt's program is fitted from ``interpretation``, made before this stage
    (:func:`overseec_core.pipeline.run_costmap` chains Interpret and Synthesize)."""
    t0 = _time.perf_counter()
    prompt = options.prompt if prompt is None else prompt
    out, lethal_out, program_out = output_paths(options.out)
    source = open_layers(options)
    try:
        check_pixels(source.grid.width, source.grid.height, source.inputs[0] if source.inputs else out, "entity layer")
        overrides = load_overrides(options.overrides, source.grid) if options.overrides else None
        extra_inputs = [p for p in (options.program, *options.overrides) if p is not None]
        check_outputs([out, lethal_out], list(source.inputs) + extra_inputs)
        same_program = options.program is not None and Path(options.program).resolve() == program_out.resolve()
        if not same_program:
            check_outputs([program_out], list(source.inputs) + extra_inputs)
        resolved = resolve_program(options, source.names, interpretation)
        program = check_program(resolved.text, source.names)
        t_program = _time.perf_counter() - t0
        warnings = source.warnings + resolved.warnings + program.warnings
        if progress is not None:
            for note in resolved.notes:
                progress.message(note)
            for warning in warnings:
                progress.message(f"warning: {warning}")
        run = RunDir(out.parent, command="costmap", args=command_args)
        for i, path in enumerate(source.inputs):
            run.record_input(f"costmap_layer_{i + 1}_{Path(path).name}", path)
        if options.program is not None:
            run.record_input("cost_program", options.program)
        run.update_parameters(
            costmap={
                "block_size": options.block_size,
                "line_width_m": options.line_width_m,
                "prompt": prompt,
                "priors": options.prior_table().to_json() if options.prompt is not None else None,
            }
        )
        tags = {
            TAG_PROGRAM: program_out.name,
            "OVERSEEC_PROGRAM_SOURCE": resolved.source,
            "OVERSEEC_PROGRAM_ENTITIES": json.dumps(list(program.entities)),
        }
        if prompt:
            tags[runfiles.TAG_PROMPT] = prompt
        if overrides is not None:
            tags[TAG_OVERRIDES] = tag_value(overrides)
        with run.stage("costmap"):
            stats = compose_costmap(
                program,
                source,
                out,
                lethal_out,
                block_size=options.block_size,
                tags=tags,
                progress=progress,
                overrides=overrides,
            )
            if not same_program:
                write_text_atomic(program_out, program.text)
        run.set(
            "cost_program",
            {
                "file": program_out.name,
                "text": program.text,
                "source": resolved.source,
                "entities": list(program.entities),
                "notes": list(resolved.notes),
                "warnings": list(warnings),
                "entity_layers": [m.to_json() for m in resolved.mapping],
                "aliases": dict(options.aliases),
                "interpretation": resolved.interpretation,
            },
        )
        run.set(
            "costmap",
            {
                "file": out.name,
                "lethal_file": lethal_out.name,
                "halo_px": list(stats.halo),
                "valid_pixels": stats.valid_pixels,
                "lethal_pixels": stats.lethal_pixels,
                "keep_out_pixels": stats.keep_out_pixels,
                "mean_cost": stats.mean_cost,
            },
        )
        override_summary = record_overrides(run, overrides, stats.overrides, "costmap", progress)
        run.save()
    finally:
        source.close()
    timings = {
        "program_s": round(t_program, 4),
        "compose_s": round(stats.seconds, 4),
        "total_s": round(_time.perf_counter() - t0, 4),
    }
    return CostmapResult(
        costmap=out,
        lethal=lethal_out,
        program_file=program_out,
        manifest=run.manifest_path,
        program=program.text,
        program_source=resolved.source,
        entities=program.entities,
        layers=source.names,
        notes=resolved.notes,
        warnings=warnings,
        halo=stats.halo,
        blocks=stats.blocks,
        valid_pixels=stats.valid_pixels,
        lethal_pixels=stats.lethal_pixels,
        mean_cost=stats.mean_cost,
        timings=timings,
        keep_out_pixels=stats.keep_out_pixels,
        overrides=override_summary,
    )
