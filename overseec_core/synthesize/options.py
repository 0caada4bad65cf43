"""What the costmap stage is asked for and what it answers: options, the resolved program, the result."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from overseec_core import defaults
from overseec_core.interpret.priors import PriorTable, resolve_priors


@dataclass(frozen=True)
class CostmapOptions:
    """What `overseec costmap` (and the QGIS task) asks for.

    Layers: ``masks`` (a segment output folder) and/or ``labels`` + ``classes`` and/or
    ``vectors`` ("name=path" strings; rasterised on the grid of the other layers, or of ``grid``).
    Program: exactly one of ``prompt`` (interpreted offline), ``program`` (a file) or
    ``program_text``.
    """

    out: Path
    masks: Path | None = None
    labels: Path | None = None
    classes: Path | None = None
    vectors: tuple[str, ...] = ()
    grid: Path | None = None
    prompt: str | None = None
    program: Path | None = None
    program_text: str | None = None
    line_width_m: float = 0.0
    block_size: int = defaults.COMPOSE_BLOCK
    #: Prompt entity -> layer name, for names the matching rules do not find ("lake" -> "water").
    aliases: tuple[tuple[str, str], ...] = ()
    #: Override polygon files (overseec_core.synthesize.overrides), applied after the program.
    overrides: tuple[Path, ...] = ()
    #: The prior table for hazards a prompt leaves unsaid (``interpret.priors``): a JSON file
    #: replacing the built-in one; ``no_priors`` switches priors off. Prompts only.
    priors: Path | None = None
    no_priors: bool = False
    #: A DEM (any GDAL raster, any CRS and resolution; elevations in metres unless the file says
    #: feet): resampled onto the grid, it gives programs the terrain fields ``slope`` and
    #: ``roughness`` (:mod:`overseec_core.synthesize.terrain`).
    dem: Path | None = None
    #: ``--strict``: a prompt clause that was not understood is an error (exit 2), not a warning.
    strict: bool = False

    def prior_table(self) -> PriorTable:
        """The priors a prompt is read with (one-line InputError for a bad file)."""
        return resolve_priors(self.priors, enabled=not self.no_priors)


@dataclass(frozen=True)
class ResolvedProgram:
    """The program text to run, where it came from, and what was said on the way."""

    text: str
    source: str  # "file", "text", "prompt:<interpreter source>"
    notes: tuple[str, ...] = ()
    interpretation: dict | None = None
    #: How the prompt's entities were matched to the layers (see interpret.matching).
    mapping: tuple = ()
    warnings: tuple[str, ...] = ()
    #: The prompt's words about entities that match no layer ("avoid the helipad" over layers
    #: without one): they have no effect, so ``--strict`` refuses them as it refuses unread clauses.
    no_effect: tuple[str, ...] = ()


@dataclass(frozen=True)
class CostmapResult:
    """What the costmap stage wrote and how."""

    costmap: Path
    lethal: Path
    program_file: Path
    manifest: Path
    program: str
    program_source: str
    entities: tuple[str, ...]  # entities the program reads
    layers: tuple[str, ...]  # entities the inputs provide
    notes: tuple[str, ...]
    warnings: tuple[str, ...]
    halo: tuple[int, int]
    blocks: int
    valid_pixels: int
    lethal_pixels: int
    mean_cost: float | None
    timings: dict[str, float]
    keep_out_pixels: int = 0
    #: Summary of the override polygons applied (overrides.OverrideSet.summary), if any.
    overrides: dict | None = None
    #: The DEM's use (file, fields read, cells it left without elevation), None without --dem.
    terrain: dict | None = None

    def to_json(self) -> dict:
        return {
            "costmap": str(self.costmap),
            "lethal": str(self.lethal),
            "program_file": str(self.program_file),
            "manifest": str(self.manifest),
            "program": self.program,
            "program_source": self.program_source,
            "entities": list(self.entities),
            "layers": list(self.layers),
            "notes": list(self.notes),
            "warnings": list(self.warnings),
            "halo": list(self.halo),
            "blocks": self.blocks,
            "valid_pixels": self.valid_pixels,
            "lethal_pixels": self.lethal_pixels,
            "keep_out_pixels": self.keep_out_pixels,
            "mean_cost": self.mean_cost,
            "timings": self.timings,
            "overrides": self.overrides,
            "terrain": self.terrain,
        }
