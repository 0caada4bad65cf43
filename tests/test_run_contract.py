"""One owner per fact the core and the plugin share: run-folder names, defaults, entity parsing."""

from __future__ import annotations

from pathlib import Path

import pytest

from overseec_core import defaults, runfiles
from overseec_core.commands.segment import load_entities_json as cli_load
from overseec_core.commands.segment import parse_entity as cli_parse
from overseec_core.errors import InputError
from overseec_core.interpret.entity_input import load_entities_json, parse_entity, parse_entity_list
from overseec_core.locate.entities import DEFAULT_THRESHOLDS
from overseec_core.locate.refine import RefineOptions
from overseec_core.locate.segment import SegmentOptions
from overseec_core.pipeline import PipelineOptions
from overseec_core.plan.stage import PlanOptions
from overseec_qgis import jobs, params


def test_first_existing_prefers_refined_files(tmp_path: Path) -> None:
    assert runfiles.first_existing(tmp_path, "mask") is None
    (tmp_path / runfiles.MASKS).write_bytes(b"")
    assert runfiles.first_existing(tmp_path, "mask") == tmp_path / runfiles.MASKS
    (tmp_path / runfiles.REFINED_MASKS).write_bytes(b"")
    assert runfiles.first_existing(tmp_path, "mask") == tmp_path / runfiles.REFINED_MASKS
    with pytest.raises(KeyError):
        runfiles.first_existing(tmp_path, "no such role")


def test_plugin_params_default_to_the_core_options() -> None:
    p, seg, ref = params.Params(), SegmentOptions(), RefineOptions()
    assert (p.tile_size, p.overlap, p.device) == (seg.tile_size, seg.resolved_overlap(), seg.device)
    assert p.device == ref.device
    assert (p.tau_linear, p.tau_areal) == (DEFAULT_THRESHOLDS["linear"], DEFAULT_THRESHOLDS["areal"])
    assert p.refine is (PipelineOptions(image=Path("x"), prompt="", out_dir=Path("o")).refine is not None)
    # batch planning is exact everywhere; the plugin's interactive default is the one named exception
    assert PlanOptions(costmap=Path("c.tif"), points=((0, 0), (1, 1)), out=Path("p.geojson")).mode == defaults.PLAN_MODE
    assert PipelineOptions(image=Path("x"), prompt="", out_dir=Path("o")).plan_mode == defaults.PLAN_MODE
    assert p.plan_mode == params.PLAN_MODE == defaults.INTERACTIVE_PLAN_MODE != defaults.PLAN_MODE


@pytest.mark.parametrize(
    ("text", "geometry"),
    [
        ("road", "linear"),
        ("dirt road", "linear"),
        ("trails", "linear"),
        ("tree", "areal"),
        ("baseball field", "areal"),
        ("something unknown", "areal"),
        ("road:areal", "areal"),
        ("grass:linear", "linear"),
        (" Water : AREAL ", "areal"),
    ],
)
def test_cli_and_plugin_parse_an_entity_alike(text: str, geometry: str) -> None:
    assert cli_parse is parse_entity and cli_load is load_entities_json
    assert parse_entity(text).geometry == geometry
    (row,) = jobs.parse_entities(text)
    assert (row["name"], row["geometry"]) == (parse_entity(text).name, geometry)


def test_entity_list_and_json_share_the_rule(tmp_path: Path) -> None:
    assert [(e.name, e.geometry) for e in parse_entity_list("road, grass, river:linear,")] == [
        ("road", "linear"),
        ("grass", "areal"),
        ("river", "linear"),
    ]
    spec = tmp_path / "entities.json"
    spec.write_text('[{"name": "road"}, {"name": "road", "geometry": "areal"}, {"name": "tree"}]')
    assert [e.geometry for e in load_entities_json(spec)] == ["linear", "areal", "areal"]
    for bad, message in (
        ("road:lineal", "geometry must be linear or areal"),
        (":linear", "empty entity name"),
        (" , ", "no entities given"),
    ):
        with pytest.raises(InputError, match=message):
            parse_entity_list(bad)
