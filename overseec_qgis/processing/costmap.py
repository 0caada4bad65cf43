"""``overseec:costmap``: a costmap GeoTIFF from entity layers and preferences (``overseec costmap``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessingException,
    QgsProcessingOutputFile,
    QgsProcessingOutputNumber,
    QgsProcessingParameterFile,
    QgsProcessingParameterRasterDestination,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
)

from ..layers import Provenance
from . import loading
from .base import OverseecAlgorithm, temp_file
from .parameters import (
    ALIASES_FLAGS,
    LAYER_FLAGS,
    OVERRIDES_FLAGS,
    PRIORS_FLAGS,
    add_layer_sources,
    add_overrides,
    add_priors_parameters,
    aliases_args,
    layer_source_args,
    override_args,
    priors_args,
)


class CostmapAlgorithm(OverseecAlgorithm):
    """Build costmap: the costmap, its lethal sidecar and its program, from a prompt or a program."""

    ID = "costmap"
    TAGS = ("costmap", "cost surface", "traversability", "prompt", "mission")
    DISPLAY = "Build costmap"
    HELP = (
        "Composes a costmap GeoTIFF (float32 in [0, 1], lower = better) from entity layers and a "
        "prompt or cost program; also writes the lethal sidecar and the program text beside it. "
        "Only reads masks: re-prompting takes seconds. A prompt none of whose entities matches a "
        "layer is an error (add ALIASES), never a uniform costmap. Same as `overseec costmap`.\n"
        "Needs: entity layers (MASKS, or LABELS + CLASSES, or both) and exactly one of PROMPT, "
        "PROGRAM_TEXT or PROGRAM."
    )
    COMMAND = "costmap"
    #: PROGRAM_TEXT reaches the CLI as a program file.
    FLAGS = {
        **LAYER_FLAGS,
        "PROMPT": "--prompt",
        "PROGRAM_TEXT": "--program",
        "PROGRAM": "--program",
        **ALIASES_FLAGS,
        **PRIORS_FLAGS,
        **OVERRIDES_FLAGS,
        "DEM": "--dem",
        "OUTPUT": "--out",
    }

    def initAlgorithm(self, config=None) -> None:
        """Entity layers, the preferences (one of three kinds), aliases, priors, overrides, the GeoTIFF."""
        add_layer_sources(self)
        self.param(
            QgsProcessingParameterString(
                "PROMPT", "Preferences: mission prompt (interpreted offline)", multiLine=True, optional=True
            ),
            "e.g. 'prefer the roads, avoid the water'. One of PROMPT, PROGRAM_TEXT, PROGRAM.",
        )
        self.param(
            QgsProcessingParameterString(
                "PROGRAM_TEXT", "Preferences: cost program (text)", multiLine=True, optional=True
            ),
            "a program in the cost language, e.g. cost = where(M['road'], 0.1, 0.5).",
        )
        self.param(
            QgsProcessingParameterFile("PROGRAM", "Preferences: cost program (file)", optional=True),
            "e.g. the .program.txt an earlier costmap wrote.",
        )
        self.param(
            QgsProcessingParameterString(
                "ALIASES", "Entity aliases for the prompt (e.g. lake=water, compound=building)", optional=True
            ),
            "the layer a prompt entity stands for when the names differ and the matching misses it.",
            advanced=True,
        )
        add_priors_parameters(self)
        add_overrides(self)
        self.param(
            QgsProcessingParameterRasterLayer("DEM", "Elevation model (DEM) for slope and roughness", optional=True),
            "any CRS and resolution, metres unless the file says feet; a program reads slope (degrees) "
            "and roughness (metres), a prompt's costmap gets slopes above 15 degrees costlier.",
            advanced=True,
        )
        self.param(
            QgsProcessingParameterRasterDestination("OUTPUT", "Costmap"),
            "a GeoTIFF; its lethal sidecar and program are written beside it.",
        )
        self.addOutput(QgsProcessingOutputFile("PROGRAM_FILE", "Cost program file"))
        self.addOutput(QgsProcessingOutputNumber("MEAN_COST", "Mean cost"))

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec costmap --json``; the costmap loads named after its prompt or program."""
        layer_args = layer_source_args(self, parameters, context)
        prompt = self.optional_str(parameters, "PROMPT", context)
        text = self.optional_str(parameters, "PROGRAM_TEXT", context)
        program = self.optional_file(parameters, "PROGRAM", context)
        if sum(x is not None for x in (prompt, text, program)) != 1:
            raise QgsProcessingException("give exactly one of PROMPT, PROGRAM_TEXT or PROGRAM")
        if text is not None:
            program = temp_file("program.txt")
            program.write_text(text + "\n", encoding="utf-8")
        aliases = aliases_args(self, parameters, context)
        out = Path(self.parameterAsOutputLayer(parameters, "OUTPUT", context))
        if out.suffix.lower() not in (".tif", ".tiff"):
            raise QgsProcessingException(f"OUTPUT: the costmap is a GeoTIFF; name it .tif, not {out.name}")
        out.parent.mkdir(parents=True, exist_ok=True)
        args = [*self.arg("OUTPUT", out), "--json", *layer_args]
        args += self.arg("PROMPT", prompt, joined=True) if prompt is not None else self.arg("PROGRAM", program)
        args += aliases
        args += priors_args(self, parameters, context)
        args += override_args(self, parameters, context, feedback)
        args += self.arg("DEM", self.optional_raster_file(parameters, "DEM", context))
        doc = self.cli(args, feedback)
        for warning in doc.get("warnings") or []:
            feedback.pushWarning(str(warning))
        name = loading.costmap_name(prompt or "", str(self.optional_file(parameters, "PROGRAM", context) or ""))
        prov = Provenance(run_dir=str(out.parent), prompt=prompt or "", program=doc.get("program", ""), stage="costmap")
        loading.name_destination(context, str(out), name, loading.StyleLayer("costmap", "costmap", prov))
        return {
            "OUTPUT": str(out),
            "PROGRAM_FILE": str(doc.get("program_file", "")),
            "MEAN_COST": doc.get("mean_cost"),
        }
