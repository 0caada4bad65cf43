"""Each refiner keeps its own checkpoint in the settings; the single setting of earlier versions
is migrated; the segmenter settings (--gsd, boxes+sam's) keep their types."""

from __future__ import annotations

from dataclasses import replace

import pytest
from qgis.core import QgsSettings

from overseec_qgis.settings import PREFIX, PluginSettings

pytestmark = pytest.mark.qgis


@pytest.fixture
def clean(qgis_app):
    QgsSettings().remove("overseec")
    yield QgsSettings()
    QgsSettings().remove("overseec")


def test_each_refiner_keeps_its_own_checkpoint(clean) -> None:
    assert PluginSettings.save_fields(sam_model="/models/sam-vit-b").params.sam_model == "/models/sam-vit-b"
    switched = PluginSettings.save_fields(refiner="sam2")
    assert (switched.params.refiner, switched.params.sam_model) == ("sam2", "")  # SAM's is no SAM 2 checkpoint
    PluginSettings.save_fields(sam_model="/models/sam2-tiny")
    assert PluginSettings.save_fields(refiner="sam").params.sam_model == "/models/sam-vit-b"
    assert PluginSettings.save_fields(refiner="sam2").params.sam_model == "/models/sam2-tiny"
    loaded = PluginSettings.load()
    assert loaded.sam_models == {"sam": "/models/sam-vit-b", "sam2": "/models/sam2-tiny"}
    assert loaded.params.sam_model == "/models/sam2-tiny"
    assert clean.value(PREFIX + "sam_models/sam-hq") is None and not clean.contains(PREFIX + "sam_model")


@pytest.mark.parametrize("saved_refiner, owner", [(None, "sam"), ("sam-hq", "sam-hq"), ("bogus", "sam")])
def test_the_old_single_setting_is_migrated_to_its_refiner(clean, saved_refiner, owner) -> None:
    clean.setValue(PREFIX + "sam_model", "/models/old")
    if saved_refiner is not None:
        clean.setValue(PREFIX + "refiner", saved_refiner)
    s = PluginSettings.load()
    assert s.sam_models == {owner: "/models/old"}
    assert not QgsSettings().contains(PREFIX + "sam_model")  # migrated once, then gone
    if saved_refiner != "bogus":
        assert s.params.sam_model == "/models/old"
    assert PluginSettings.load().sam_models == {owner: "/models/old"}


def test_migration_never_overwrites_a_refiners_own_checkpoint(clean) -> None:
    clean.setValue(PREFIX + "sam_models/sam", "/models/new")
    clean.setValue(PREFIX + "sam_model", "/models/old")
    assert PluginSettings.load().params.sam_model == "/models/new"


def test_segmenter_settings_round_trip_with_their_types(clean) -> None:
    s = PluginSettings.load()
    s.params = replace(s.params, gsd="0.3", box_threshold=0.25, max_boxes=5, segmenter="boxes+sam")
    s.save()
    again = PluginSettings.load()
    assert (again.params.gsd, again.params.box_threshold, again.params.max_boxes) == ("0.3", 0.25, 5)
    assert isinstance(again.params.box_threshold, float) and isinstance(again.params.max_boxes, int)
