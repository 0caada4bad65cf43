"""The plugin's value types: run parameters, the interpreter's LLM, the priors a prompt is read with.

:mod:`.jobs` turns them into worker argv, :mod:`.settings` stores them in QgsSettings; both import
them from here, so neither imports the other. Frozen dataclasses over the core's light modules
(``overseec_core.defaults``: standard library only), so the plugin can load this before it knows
whether rasterio is importable.
"""

from __future__ import annotations

from dataclasses import dataclass

from overseec_core import defaults
from overseec_core.locate.refiners import DEFAULT_REFINER, refiner_names
from overseec_core.locate.segmenters import DEFAULT_SEGMENTER, segmenter_names

#: The planner mode the plugin starts with (dock runs and the map tool): interactive, so fast.
PLAN_MODE = defaults.INTERACTIVE_PLAN_MODE
#: The planner modes as the plugin's menus list them: the interactive default first (Processing's
#: saved models and ``qgis_process`` calls hold the index, so the order stays).
PLAN_MODES = (PLAN_MODE, *(m for m in defaults.PLAN_MODES if m != PLAN_MODE))
#: The planner steps the plugin starts with (8 neighbours) and offers (the core's: 8, 16).
PLAN_STEPS = defaults.PLAN_NEIGHBOURS
#: The coarse segmenters (the core's registry, standard library only), default first.
SEGMENTERS = segmenter_names()
#: The refiners of the masks (the core's table, light), default first.
REFINERS = refiner_names()


@dataclass(frozen=True)
class LlmSettings:
    """Where the interpreter's LLM is; an empty endpoint means the offline interpreter."""

    endpoint: str = ""
    model: str = ""
    api_key: str = ""

    @property
    def offline(self) -> bool:
        """True when there is no endpoint: the offline interpreter reads the prompt."""
        return not self.endpoint


@dataclass(frozen=True)
class Priors:
    """The priors a prompt is read with: what the hazards it leaves unsaid cost
    (``overseec_core.interpret.priors``). The built-in table by default; ``path``: a JSON file
    replacing it (``--priors FILE``); ``off``: none (``--no-priors``)."""

    path: str = ""
    off: bool = False

    def cli(self) -> list[str]:
        """``--priors=FILE`` and/or ``--no-priors``; both when both are set, so that the
        command's own one-line error says they contradict each other."""
        return ([f"--priors={self.path}"] if self.path else []) + (["--no-priors"] if self.off else [])

    def table(self):
        """The core's PriorTable for these priors (InputError, one line, for a bad file)."""
        from overseec_core.interpret.priors import resolve_priors  # reads JSON: only when asked

        return resolve_priors(self.path or None, enabled=not self.off)


#: The offline interpreter (no LLM) and the built-in priors: the defaults of the jobs' functions.
OFFLINE = LlmSettings()
BUILT_IN_PRIORS = Priors()


@dataclass(frozen=True)
class Params:
    """Run parameters shared by the dock and the Processing algorithms (CLI option names).

    Defaults are the core's (``overseec_core.defaults``, which SegmentOptions, RefineOptions and
    the CLI use); empty model ids mean the CLI's default models. ``segmenter`` is a name of the
    core's segmenter registry, ``refiner`` of its refiners' table (``sam_model``: that refiner's
    checkpoint, "" = its default). ``clipseg_model`` is CLIPSeg's model (``--clipseg-model``) and
    ``model`` the model of any other segmenter (``--model``; "" = that segmenter's default), so
    switching segmenters in the dock never hands one backend another's model. ``gsd`` ("": native),
    ``box_threshold`` and ``max_boxes`` (0: the backend's defaults) are typed so QgsSettings keeps
    them. One default differs on purpose:
    ``plan_mode`` is :data:`PLAN_MODE` ("fast"), not the CLI's "exact", because in QGIS a path is
    re-planned on every click and drag of the map tool and has to come back at once; "exact" is
    one choice away in the dock and the Processing algorithms.
    """

    tile_size: int = defaults.TILE_SIZE
    overlap: int = defaults.overlap_for(defaults.TILE_SIZE)
    tau_linear: float = defaults.THRESHOLDS["linear"]
    tau_areal: float = defaults.THRESHOLDS["areal"]
    refine: bool = defaults.REFINE
    device: str = defaults.DEVICE
    segmenter: str = DEFAULT_SEGMENTER
    model: str = ""
    clipseg_model: str = ""
    sam_model: str = ""
    refiner: str = DEFAULT_REFINER
    plan_mode: str = PLAN_MODE
    #: ``--neighbours``: the route's steps, 8 or 16 with knight moves (map tool, pairs, Run all)
    plan_neighbours: int = PLAN_STEPS[0]
    #: ``--gsd``: processing resolution, metres per pixel as typed or "auto"; "" = the image's own
    gsd: str = ""
    #: ``--box-threshold`` of boxes+sam; 0 = the detector's default (OWLv2 0.1, Grounding DINO 0.3)
    box_threshold: float = 0.0
    #: ``--max-boxes`` of boxes+sam; 0 = its default (16)
    max_boxes: int = 0
