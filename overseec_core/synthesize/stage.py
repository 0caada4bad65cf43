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
from overseec_core.synthesize.terrain import TerrainSource, require_dem, with_prompt_terrain

#: Tag on the costmap naming the DEM its terrain fields came from.
TAG_DEM = "OVERSEEC_DEM_FILE"


def _terrain_text(options: CostmapOptions, text: str, from_prompt: bool) -> str:
    """The program text, with the terrain term appended to a prompt's program when a DEM is given
    (a prompt cannot name slopes; a program file or text says what it wants itself)."""
    if options.dem is not None and from_prompt:
        return with_prompt_terrain(text)
    return text


def _open_terrain(options: CostmapOptions, program, grid, progress: Progress | None) -> TerrainSource | None:
    """The DEM's terrain fields when the program reads them (a one-line error naming --dem when it
    reads them and none was given); None when there is no DEM or the program does not read it."""
    require_dem(program, options.dem)
    if options.dem is None or not program.terrain:
        return None
    terrain = TerrainSource(options.dem, grid)
    if progress is not None:
        progress.message(terrain.describe())
    return terrain


def _unused_dem_warnings(options: CostmapOptions, program) -> tuple[str, ...]:
    """A warning when a DEM is given and the program reads neither terrain field."""
    if options.dem is None or program.terrain:
        return ()
    return (f"--dem {options.dem}: the program reads neither slope nor roughness; the DEM is not used",)


def _terrain_summary(
    options: CostmapOptions, terrain: TerrainSource | None, fields: tuple[str, ...], missing: int, grid
) -> dict | None:
    """What the manifest and the result say about the DEM (None without --dem)."""
    if options.dem is None:
        return None
    total = grid.width * grid.height
    return {
        "dem": str(options.dem),
        "used": terrain is not None,
        "fields": [] if terrain is None else list(fields),
        "unit": None if terrain is None else terrain.dem.unit,
        "missing_pixels": missing,
        "missing_fraction": missing / total if total else 0.0,
    }


def _terrain_tags(options: CostmapOptions, terrain: TerrainSource | None) -> dict[str, str]:
    """The costmap's tag naming the DEM its terrain came from (none when no DEM was used)."""
    return {} if terrain is None else {TAG_DEM: str(options.dem)}


def _close(source, terrain: TerrainSource | None) -> None:
    """Close the layers and the DEM."""
    source.close()
    if terrain is not None:
        terrain.close()


def _record_terrain(
    run: RunDir, options: CostmapOptions, terrain, program, stats, grid, progress: Progress | None
) -> tuple[dict | None, tuple[str, ...]]:
    """Record the DEM's use in the manifest ("terrain") and say how many cells it left without
    elevation: (the summary, the warnings)."""
    if options.dem is not None:
        run.record_input("dem", options.dem)
    missing = stats.terrain_missing_pixels
    summary = _terrain_summary(options, terrain, program.terrain, missing, grid)
    if summary is not None:
        run.set("terrain", summary)
    warning = _missing_warning(options, missing, grid)
    if warning is None:
        return summary, ()
    if progress is not None:
        progress.message(f"warning: {warning}")
    return summary, (warning,)


def _missing_warning(options: CostmapOptions, missing: int, grid) -> str | None:
    """The warning for cells the DEM leaves without elevation (None when it covers the grid)."""
    if not missing:
        return None
    pct = 100.0 * missing / max(grid.width * grid.height, 1)
    return (
        f"--dem {options.dem}: {missing} cells ({pct:.3g} % of the grid) have no elevation "
        "(outside the DEM or its nodata); they are nodata in the costmap"
    )


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
    terrain: TerrainSource | None = None
    try:
        check_pixels(source.grid.width, source.grid.height, source.inputs[0] if source.inputs else out, "entity layer")
        overrides = load_overrides(options.overrides, source.grid) if options.overrides else None
        extra_inputs = [p for p in (options.program, options.dem, *options.overrides) if p is not None]
        check_outputs([out, lethal_out], list(source.inputs) + extra_inputs)
        same_program = options.program is not None and Path(options.program).resolve() == program_out.resolve()
        if not same_program:
            check_outputs([program_out], list(source.inputs) + extra_inputs)
        resolved = resolve_program(options, source.names, interpretation)
        program = check_program(_terrain_text(options, resolved.text, bool(prompt)), source.names)
        terrain = _open_terrain(options, program, source.grid, progress)
        t_program = _time.perf_counter() - t0
        warnings = source.warnings + resolved.warnings + program.warnings + _unused_dem_warnings(options, program)
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
                "dem": None if options.dem is None else str(options.dem),
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
        tags.update(_terrain_tags(options, terrain))
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
                terrain=terrain,
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
        terrain_summary, terrain_warnings = _record_terrain(
            run, options, terrain, program, stats, source.grid, progress
        )
        warnings += terrain_warnings
        run.save()
    finally:
        _close(source, terrain)
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
        terrain=terrain_summary,
    )
