"""What the worker's commands print back: the ``--json`` document after the progress events,
read into the plugin's values (an interpretation, a costmap summary, an image's description)."""

from __future__ import annotations

import json
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from overseec_core.errors import InputError

from ..worker import run_worker


def run_json(argv: Sequence[str], env: Mapping[str, str], timeout_s: float) -> dict[str, Any]:
    """Run a short worker command here (not in a task) and return its ``--json`` document;
    InputError with the CLI's one-line reason when it fails or takes over ``timeout_s``."""
    printed: list[str] = []
    deadline = time.monotonic() + timeout_s
    res = run_worker(
        argv,
        on_event=lambda e: printed.append(e.text) if e.kind == "text" else None,
        is_cancelled=lambda: time.monotonic() > deadline,
        env=env,
    )
    if not res.ok:
        raise InputError(f"`overseec {argv[2]}` took over {timeout_s:g} s" if res.cancelled else res.summary())
    doc = result_document(printed)
    if not doc:
        raise InputError(f"`overseec {argv[2]} --json` printed no document ({argv[0]})")
    return doc


def result_document(lines: Sequence[str]) -> dict[str, Any]:
    """The ``--json`` document a CLI command prints after its progress events: one line (as the
    CLI prints it under --json-progress), or indented, ``{`` on a line of its own (older CLIs);
    {} when there is none."""
    for i, line in enumerate(lines):
        text = line.strip()
        if not text.startswith("{"):
            continue
        try:
            doc = json.loads("\n".join(lines[i:]) if text == "{" else text)
        except ValueError:
            return {}
        return doc if isinstance(doc, dict) else {}
    return {}


def describe_info(info: Mapping[str, Any]) -> str:
    """The core's info as a few lines for the dock (the same facts `overseec info` prints)."""
    px, py = info["pixel_size_m"]
    return "\n".join(
        [
            f"{info['width']} x {info['height']} px, {info['count']} band(s) {', '.join(info['dtypes'])}",
            f"CRS {info['crs']}{' (assumed)' if info.get('crs_assumed') else ''}, pixel {px:.3g} x {py:.3g} m",
            f"read as: {info['read_plan']['description']}",
            f"nodata: {'NaN' if info.get('nodata_is_nan') else info.get('nodata')}, "
            f"alpha band: {info.get('alpha_band') or 'none'}",
        ]
    )


def interpretation_from_json(doc: Mapping[str, Any]):
    """The Interpretation of an ``overseec interpret --json`` document (the schema's fields)."""
    from overseec_core.schema import Cue, Entity, Interpretation, Preference

    if not isinstance(doc.get("entities"), list):
        raise InputError("the interpreter returned no entities")
    return Interpretation(
        prompt=str(doc.get("prompt", "")),
        entities=tuple(Entity.from_json(e) for e in doc["entities"]),
        preferences=tuple(Preference.from_json(p) for p in doc.get("preferences") or ()),
        hierarchy=tuple((str(c), str(p)) for c, p in doc.get("hierarchy") or ()),
        cues=tuple(Cue(**c) for c in doc.get("cues") or ()),
        program=str(doc.get("program", "")),
        unparsed=tuple(doc.get("unparsed") or ()),
        source=str(doc.get("source", "offline")),
        notes=tuple(doc.get("notes") or ()),
    )


@dataclass(frozen=True)
class CostmapSummary:
    """What the dock shows of an ``overseec costmap --json`` document."""

    costmap: Path
    lethal: Path
    program_file: Path
    program: str
    entities: tuple[str, ...]
    notes: tuple[str, ...]
    warnings: tuple[str, ...]
    mean_cost: float | None

    @staticmethod
    def from_json(doc: Mapping[str, Any]) -> CostmapSummary:
        try:
            return CostmapSummary(
                costmap=Path(doc["costmap"]),
                lethal=Path(doc["lethal"]),
                program_file=Path(doc["program_file"]),
                program=str(doc["program"]),
                entities=tuple(doc.get("entities") or ()),
                notes=tuple(doc.get("notes") or ()),
                warnings=tuple(doc.get("warnings") or ()),
                mean_cost=doc.get("mean_cost"),
            )
        except (KeyError, TypeError) as exc:
            raise InputError(f"`overseec costmap --json` printed no usable document (missing {exc})") from None
