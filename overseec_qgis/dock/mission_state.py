"""The dock's mission as the project keeps it: plain values written into the project file (under
the plugin's scope, with ``QgsProject.writeEntry``) when it is saved, read back when it is opened.

A project saved by an older plugin has none of these entries: :func:`read_mission` then returns
None and the dock keeps its earlier behaviour (only aliases, priors and the run come back).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

from qgis.core import QgsProject

from .common import PROJECT_SCOPE

#: Project entries (keys in PROJECT_SCOPE) of the mission's aliases and priors (the first
#: entries the plugin wrote; kept under these keys so older projects read as before).
PROJECT_ALIASES_KEY, PROJECT_PRIORS_KEY, PROJECT_NO_PRIORS_KEY = "aliases", "priors", "no_priors"
#: Project entries of the rest of the mission: the prompt, the entities table's cells, the
#: program as edited, the interpretation the table came from (JSON), the class raster (a layer
#: id) and its classes.json.
PROMPT_KEY, ENTITIES_KEY, PROGRAM_KEY, INTERPRETATION_KEY = "prompt", "entities", "program", "interpretation"
LABELS_KEY, CLASSES_KEY = "class_raster", "classes"
#: Project entries of the DEM (``--dem``): a layer id, or a file.
DEM_LAYER_KEY, DEM_FILE_KEY = "dem_layer", "dem_file"
#: Project entries of the input image: a layer id, or a file, and the bands.
IMAGE_LAYER_KEY, IMAGE_FILE_KEY, BANDS_KEY = "image_layer", "image_file", "bands"


@dataclass(frozen=True)
class Mission:
    """The mission fields of the dock, as plain values.

    ``rows`` are the entities table's cells as typed (name, geometry, threshold, extra prompts),
    so a half-edited table comes back as it was; ``interpretation`` is the interpreter's JSON
    document the table was filled from and ``interpreted_with`` the priors (path, off) it ran
    with, so a reopened project does not interpret again over the user's edits."""

    prompt: str = ""
    rows: tuple[tuple[str, str, str, str], ...] = ()
    program: str = ""
    aliases: str = ""
    priors: str = ""
    no_priors: bool = False
    interpretation: dict[str, Any] | None = None
    interpreted_with: tuple[str, bool] | None = None
    labels_layer: str = ""
    classes: str = ""
    #: the DEM: a layer id, or (with no layer) a file
    dem_layer: str = ""
    dem_file: str = ""
    #: whether the project held the full mission (False: a project from an older plugin)
    complete: bool = field(default=True, compare=False)


def _text(project: QgsProject, key: str) -> tuple[str, bool]:
    value, found = project.readEntry(PROJECT_SCOPE, key, "")
    return str(value), bool(found)


def _json(text: str, default: Any) -> Any:
    try:
        return json.loads(text) if text else default
    except ValueError:  # hand-edited or truncated: what cannot be read is not restored
        return default


def _rows(value: Any) -> tuple[tuple[str, str, str, str], ...]:
    if not isinstance(value, list):
        return ()
    rows = []
    for row in value:
        if isinstance(row, list) and len(row) == 4:
            rows.append((str(row[0]), str(row[1]), str(row[2]), str(row[3])))
    return tuple(rows)


def read_mission(project: QgsProject) -> Mission:
    """The mission saved in ``project`` (``complete`` False when only the older entries exist)."""
    prompt, complete = _text(project, PROMPT_KEY)
    saved = _json(_text(project, INTERPRETATION_KEY)[0], {})
    interp = saved.get("interpretation") if isinstance(saved, dict) else None
    with_priors = saved.get("priors") if isinstance(saved, dict) else None
    return Mission(
        prompt=prompt,
        rows=_rows(_json(_text(project, ENTITIES_KEY)[0], [])),
        program=_text(project, PROGRAM_KEY)[0],
        aliases=_text(project, PROJECT_ALIASES_KEY)[0],
        priors=_text(project, PROJECT_PRIORS_KEY)[0],
        no_priors=bool(project.readBoolEntry(PROJECT_SCOPE, PROJECT_NO_PRIORS_KEY, False)[0]),
        interpretation=interp if isinstance(interp, dict) else None,
        interpreted_with=(str(with_priors[0]), bool(with_priors[1]))
        if isinstance(with_priors, list) and len(with_priors) == 2
        else None,
        labels_layer=_text(project, LABELS_KEY)[0],
        classes=_text(project, CLASSES_KEY)[0],
        dem_layer=_text(project, DEM_LAYER_KEY)[0],
        dem_file=_text(project, DEM_FILE_KEY)[0],
        complete=complete,
    )


def write_mission(project: QgsProject, mission: Mission) -> None:
    """Write ``mission`` into ``project``'s entries (saved with the project file)."""
    entries: dict[str, Any] = {
        PROMPT_KEY: mission.prompt,
        ENTITIES_KEY: json.dumps([list(r) for r in mission.rows]),
        PROGRAM_KEY: mission.program,
        PROJECT_ALIASES_KEY: mission.aliases,
        PROJECT_PRIORS_KEY: mission.priors,
        PROJECT_NO_PRIORS_KEY: mission.no_priors,
        INTERPRETATION_KEY: json.dumps(
            {"interpretation": mission.interpretation, "priors": list(mission.interpreted_with)}
            if mission.interpretation is not None and mission.interpreted_with is not None
            else {}
        ),
        LABELS_KEY: mission.labels_layer,
        CLASSES_KEY: mission.classes,
        DEM_LAYER_KEY: mission.dem_layer,
        DEM_FILE_KEY: mission.dem_file,
    }
    for key, value in entries.items():
        project.writeEntry(PROJECT_SCOPE, key, value)


@dataclass(frozen=True)
class InputImage:
    """The dock's input image as the project keeps it: a layer (its id) or a file, and bands."""

    layer_id: str = ""
    file: str = ""
    bands: str = ""
    #: whether the project held these entries (False: a project from an older plugin)
    found: bool = field(default=True, compare=False)


def read_input(project: QgsProject) -> InputImage:
    """The input image saved in ``project``."""
    layer_id, found = _text(project, IMAGE_LAYER_KEY)
    return InputImage(layer_id, _text(project, IMAGE_FILE_KEY)[0], _text(project, BANDS_KEY)[0], found)


def write_input(project: QgsProject, image: InputImage) -> None:
    """Write the input image into ``project``'s entries."""
    project.writeEntry(PROJECT_SCOPE, IMAGE_LAYER_KEY, image.layer_id)
    project.writeEntry(PROJECT_SCOPE, IMAGE_FILE_KEY, image.file)
    project.writeEntry(PROJECT_SCOPE, BANDS_KEY, image.bands)
