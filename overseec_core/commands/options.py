"""The options several `overseec` commands take, each declared once (as rasterio's ``rio/options.py``).

A command module builds its parser from these builders and declares by hand only what is its own.
The spec the adapters are checked against (:mod:`overseec_core.commands.spec`) is read back from
the parsers, so an option declared here has the same spelling, type, choices and default in every
command that takes it (``tests/commands/test_options.py`` checks that every flag two commands share
is declared alike, naming the few that mean different things in different commands).

The argparse value types (:func:`finite_number`, :func:`whole_number` ...) live here too: a type is
part of an option's declaration, and a command's own options use the same ones.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from overseec_core import defaults, runfiles

# ------------------------------------------------------------------------------------------------
# Value types
# ------------------------------------------------------------------------------------------------


def finite_number(text: str) -> float:
    """argparse type: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, not {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, not {text!r}")
    return value


def non_negative_number(text: str) -> float:
    """argparse type: a finite number >= 0."""
    value = finite_number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, not {text!r}")
    return value


def whole_number(minimum: int):
    """argparse type factory: a whole number >= ``minimum``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, not {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected a number >= {minimum}, not {value}")
        return value

    parse.__name__ = f"whole number >= {minimum}"
    return parse


def entity_alias(text: str) -> tuple[str, str]:
    """argparse type: ENTITY=LAYER, a prompt entity name and the layer it stands for."""
    from overseec_core.interpret.matching import parse_alias

    try:
        return parse_alias(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def gsd_value(text: str) -> float | str:
    """argparse type of ``--gsd``: metres per pixel (a positive number) or ``auto``."""
    from overseec_core.errors import InputError
    from overseec_core.locate.gsd import parse_gsd

    try:
        value = parse_gsd(text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix(f"--gsd {text!r}: ")) from None
    if value is None:
        raise argparse.ArgumentTypeError("expected metres per pixel (e.g. 0.3) or 'auto'")
    return value


def box_threshold(text: str) -> float:
    """argparse type of ``--box-threshold``: a detector score in [0, 1)."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"expected a score between 0 and 1 (e.g. 0.2), not {text!r}")
    return value


#: Block sides of the streamed compose: at least 16 pixels (one TIFF tile's granularity).
block_size = whole_number(16)

# ------------------------------------------------------------------------------------------------
# Entity layers (costmap, compare)
# ------------------------------------------------------------------------------------------------


def add_entity_layer_options(parser: argparse.ArgumentParser, title: str) -> None:
    """--masks, --labels, --classes, --vector (repeatable), --grid and --line-width: the layers a
    costmap is composed over, combinable (``synthesize.layers``)."""
    layers = parser.add_argument_group(title)
    layers.add_argument(
        "--masks", type=Path, metavar="DIR", help=f"segment output folder holding {runfiles.MASKS} (+ {runfiles.PROBS})"
    )
    layers.add_argument("--labels", type=Path, metavar="FILE", help="class raster (GeoTIFF of integer class ids)")
    layers.add_argument("--classes", type=Path, metavar="FILE", help="classes.json of --labels: class id -> name")
    add_vector_option(layers, "a vector layer as an entity, e.g. road=roads.gpkg (repeatable)")
    layers.add_argument(
        "--grid", type=Path, metavar="FILE", help="raster whose grid vector-only layers are rasterised onto"
    )
    layers.add_argument(
        "--line-width",
        type=non_negative_number,
        default=0.0,
        metavar="METRES",
        help="buffer vector lines to this width (default 0: every pixel a line touches)",
    )


def add_vector_option(group, help: str) -> None:
    """--vector ENTITY=FILE (repeatable): a vector layer rasterised as an entity."""
    group.add_argument("--vector", action="append", default=[], metavar="ENTITY=FILE", help=help)


def add_block_size_option(parser: argparse.ArgumentParser) -> None:
    """--block-size: the side of the blocks a costmap is composed in (its memory bound)."""
    parser.add_argument(
        "--block-size",
        type=block_size,
        default=defaults.COMPOSE_BLOCK,
        metavar="PX",
        help="pixels per block side (memory bound; default 1024)",
    )


# ------------------------------------------------------------------------------------------------
# Prompt reading (interpret, costmap, compare, run)
# ------------------------------------------------------------------------------------------------


def add_priors_options(parser: argparse.ArgumentParser) -> None:
    """The shared --priors / --no-priors options of the commands that read prompts: what the
    hazards a prompt leaves unsaid cost (``interpret.priors``)."""
    from overseec_core.interpret.priors import BUILT_IN

    g = parser.add_mutually_exclusive_group()
    g.add_argument(
        "--priors",
        type=Path,
        metavar="FILE",
        help='JSON object of entity -> prior level in (0.5, 1], "obstacle" (= 1) or "lethal", replacing the built-in '
        f"priors of unsaid hazards ({BUILT_IN.describe()})",
    )
    g.add_argument(
        "--no-priors",
        action="store_true",
        help="no priors: what the prompt does not mention is neutral ground",
    )


def add_strict_option(parser: argparse.ArgumentParser) -> None:
    """The shared --strict option of the commands that read prompts into a costmap: a clause of
    the prompt that was not understood is an error (exit 2) instead of a warning, for batch runs."""
    parser.add_argument(
        "--strict",
        action="store_true",
        help="fail (exit 2) when any clause of the prompt was not understood, instead of warning and "
        "building the costmap without it",
    )


def add_alias_option(parser) -> None:
    """The shared --alias option of the commands that match prompt entities to layers."""
    parser.add_argument(
        "--alias",
        action="append",
        default=[],
        type=entity_alias,
        metavar="ENTITY=LAYER",
        help="the layer a prompt entity stands for when the names differ and the "
        "built-in matching misses it, e.g. lake=water (repeatable)",
    )


def add_llm_options(parser: argparse.ArgumentParser) -> None:
    """LLM options shared by the commands that interpret prompts (``interpret.llm``)."""
    g = parser.add_argument_group("LLM (OpenAI-compatible chat API; default: offline interpreter)")
    g.add_argument(
        "--llm-url", metavar="URL", help="base URL, e.g. http://localhost:11434/v1 (default: $OVERSEEC_LLM_URL)"
    )
    g.add_argument("--llm-model", metavar="NAME", help="model name (default: $OVERSEEC_LLM_MODEL)")
    g.add_argument(
        "--llm-key-env",
        metavar="VAR",
        help="environment variable holding the API key (default: OVERSEEC_LLM_API_KEY); "
        "keys are never passed on the command line",
    )
    g.add_argument("--llm-timeout", type=float, metavar="SECONDS", help="seconds per request (default 120)")
    g.add_argument(
        "--llm-retries",
        type=int,
        metavar="N",
        help="retries after timeouts, connection errors and HTTP 5xx (default 3)",
    )
    g.add_argument(
        "--llm-fallback-offline",
        action="store_true",
        default=None,
        help="if the LLM fails, interpret offline (with a note) instead of stopping",
    )


# ------------------------------------------------------------------------------------------------
# Imagery and segmentation (info, segment, run)
# ------------------------------------------------------------------------------------------------


def add_read_options(parser: argparse.ArgumentParser) -> None:
    """Options every command that reads imagery shares."""
    parser.add_argument(
        "--bands", metavar="BANDS", help="bands to read as R,G,B (e.g. 4,3,2), or one band for panchromatic"
    )
    parser.add_argument("--assume-crs", metavar="CRS", help="CRS for an image that has none (e.g. EPSG:32633)")


def add_tile_size_option(group) -> None:
    """--tile-size: the side of the segmentation tiles (``defaults.TILE_SIZE``)."""
    group.add_argument(
        "--tile-size",
        type=whole_number(1),
        default=defaults.TILE_SIZE,
        metavar="PX",
        help="segmentation tile side (default %(default)s)",
    )


def add_segmenter_options(group) -> None:
    """--segmenter (the registry's names), --model, --gsd and the boxes+sam settings, shared by
    `segment` and `run` (:func:`segmenter_settings` reads the last three back)."""
    from overseec_core.locate.segmenters import DEFAULT_SEGMENTER, SEGMENTERS, describe_segmenters, segmenter_names

    group.add_argument(
        "--segmenter",
        choices=segmenter_names(),
        default=DEFAULT_SEGMENTER,
        help=f"the coarse segmenter: {describe_segmenters()} (default %(default)s)",
    )
    group.add_argument(
        "--model",
        metavar="ID|PATH",
        help="the segmenter's model: hub id in the local cache, a model directory (or a file where the "
        "segmenter takes one); default: the segmenter's own ("
        + ", ".join(f"{i.name}: {i.default_model}" for i in SEGMENTERS.values())
        + ")",
    )
    group.add_argument(
        "--gsd",
        type=gsd_value,
        metavar="METRES|auto",
        help="processing resolution in ground metres per pixel: tiles are resampled to it for the model and "
        "the outputs written on the image's grid; auto: the model's trained resolution where it names one "
        "(semantic models' gsd_m), else native (default: native)",
    )
    group.add_argument(
        "--box-threshold",
        type=box_threshold,
        metavar="VALUE",
        help="boxes+sam: detector score a box needs, in [0, 1) (default: OWLv2 0.1, Grounding DINO 0.3)",
    )
    group.add_argument(
        "--max-boxes",
        type=whole_number(1),
        metavar="N",
        help="boxes+sam: boxes kept per entity and tile, best first (default 16); its boxes become masks by "
        "--sam-model while the refiner is sam (default facebook/sam-vit-base)",
    )


def segmenter_settings(args: argparse.Namespace) -> dict:
    """The ``SegmentOptions`` fields of :func:`add_segmenter_options`'s --gsd, --box-threshold and
    --max-boxes (None where not given: the backend's defaults, native resolution), and the SAM
    that boxes+sam turns its boxes into masks with: --sam-model while the refiner is SAM (the
    default; a SAM-HQ or SAM 2 checkpoint is not one), else its default."""
    from overseec_core.locate.refiners import DEFAULT_REFINER

    sam = getattr(args, "sam_model", None) if getattr(args, "refiner", DEFAULT_REFINER) == "sam" else None
    return {
        "gsd": getattr(args, "gsd", None),
        "box_threshold": getattr(args, "box_threshold", None),
        "max_boxes": getattr(args, "max_boxes", None),
        "sam_model": sam if getattr(args, "segmenter", None) == "boxes+sam" else None,
    }


def add_refiner_options(group) -> None:
    """--refiner (the refiners' table) and --sam-model (None: the refiner's default), shared by
    `segment` and `run`."""
    from overseec_core.locate.refiners import DEFAULT_REFINER, REFINERS, describe_refiners, refiner_names

    group.add_argument(
        "--refiner",
        choices=refiner_names(),
        default=DEFAULT_REFINER,
        help=f"the refiner of the coarse masks: {describe_refiners()} (default %(default)s)",
    )
    group.add_argument(
        "--sam-model",
        metavar="ID|DIR",
        help="the refiner's checkpoint: hub id in the local cache or a model directory; default: the "
        "refiner's own (" + ", ".join(f"{i.name}: {i.default_model}" for i in REFINERS.values()) + ")",
    )


# ------------------------------------------------------------------------------------------------
# Planning (plan, corridor, compare, run, eval)
# ------------------------------------------------------------------------------------------------


def add_point_options(group, crs_of: str, *, required: bool = False, vias: bool = True, note: str = "") -> None:
    """--start, --via (repeatable, in order; unless ``vias`` is False), --goal and --crs: the
    points of a route, in ``--crs`` (default: the CRS of ``crs_of``). ``note`` ends the help of
    --start and --goal (e.g. when they are needed)."""
    tail = f"; {note}" if note else ""
    group.add_argument(
        "--start",
        nargs=2,
        type=finite_number,
        required=required,
        metavar=("X", "Y"),
        help=f"start point (in --crs{tail})",
    )
    if vias:
        group.add_argument(
            "--via",
            nargs=2,
            type=finite_number,
            action="append",
            default=[],
            metavar=("X", "Y"),
            help="a point to pass through (repeatable, in order)",
        )
    group.add_argument(
        "--goal",
        nargs=2,
        type=finite_number,
        required=required,
        metavar=("X", "Y"),
        help=f"goal point (in --crs{tail})",
    )
    group.add_argument("--crs", metavar="CRS", help=f"CRS of the points (default: {crs_of}), e.g. EPSG:4326")


def add_mode_option(group) -> None:
    """--mode: the planner's search (``defaults.PLAN_MODES``), exact by default."""
    group.add_argument(
        "--mode",
        choices=defaults.PLAN_MODES,
        default=defaults.PLAN_MODE,
        help="exact (optimal, default) or fast (coarse-to-fine corridor, with a bound)",
    )


def add_neighbours_option(group) -> None:
    """--neighbours: the planner's steps (``defaults.PLAN_NEIGHBOURS``), an int on the namespace."""
    group.add_argument(
        "--neighbours",
        type=int,
        choices=defaults.PLAN_NEIGHBOURS,
        default=defaults.PLAN_NEIGHBOURS[0],
        help="steps: 8 neighbours (default) or 16, adding knight moves priced by the exact cell "
        "integral (closer to straight lines; needs the compiled kernel)",
    )


def add_costmap_read_options(parser: argparse.ArgumentParser) -> None:
    """How a costmap is read for planning, shared by `plan` and `corridor`: --base-cost-per-m,
    --lethal-threshold, --lethal, --override (repeatable) and --band."""
    from overseec_core.plan.paths import DEFAULT_BASE_COST_PER_M

    parser.add_argument(
        "--base-cost-per-m",
        type=non_negative_number,
        default=DEFAULT_BASE_COST_PER_M,
        metavar="COST",
        help=f"cost added per metre travelled (default {DEFAULT_BASE_COST_PER_M})",
    )
    parser.add_argument(
        "--lethal-threshold",
        type=finite_number,
        metavar="COST",
        help="cells with cost >= COST are impassable (in addition to the lethal sidecar)",
    )
    parser.add_argument(
        "--lethal",
        type=Path,
        metavar="FILE",
        help="lethal mask GeoTIFF (uint8, nonzero = impassable); default: the sidecar the "
        f"costmap names, or {runfiles.LETHAL} beside it",
    )
    parser.add_argument(
        "--override",
        type=Path,
        action="append",
        default=[],
        metavar="FILE",
        help="operator corrections applied in memory (the costmap file is unchanged): "
        "polygons with cost (0..1), lethal=1 or prefer=1 (repeatable)",
    )
    parser.add_argument(
        "--band",
        type=whole_number(1),
        metavar="N",
        help="the costmap band to plan on (needed when the raster has several)",
    )
