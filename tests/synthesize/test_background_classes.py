"""Which classes.json classes are background: every real scene's, and the edge cases.

The real scenes name class 0 "unlabeled", "background/unlabeled" or "background/unlabeled
(non-road)"; none of them may become an entity (a costmap rule "avoid background" would otherwise
silently read the unlabeled ground), and every other class must stay one.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from overseec_core.errors import InputError
from overseec_core.io.read import read_classes_json
from overseec_core.synthesize.layers import class_entity_name, is_background_class, load_class_entities
from tests.conftest import SCENES

SCENE_CLASSES = sorted(SCENES.glob("*/classes.json")) if SCENES.is_dir() else []


@pytest.mark.skipif(not SCENE_CLASSES, reason=f"real scenes not found at {SCENES}")
@pytest.mark.parametrize("classes", SCENE_CLASSES, ids=lambda p: p.parent.name)
def test_real_scene_background_is_no_entity_and_every_other_class_is_kept(classes: Path) -> None:
    labels = read_classes_json(classes)
    entities = load_class_entities(classes)
    assert 0 not in entities, f"class 0 {labels[0]!r} became entity {entities.get(0)!r}"
    assert not any("background" in n or "unlabeled" in n for n in entities.values())
    assert set(entities) == set(labels) - {0}
    assert entities == {cid: class_entity_name(labels[cid]) for cid in labels if cid != 0}


def test_the_real_scenes_are_all_checked() -> None:
    if not SCENE_CLASSES:
        pytest.skip(f"real scenes not found at {SCENES}")
    assert len(SCENE_CLASSES) >= 8


@pytest.mark.parametrize(
    "label",
    [
        "unlabeled",
        "Unlabelled",
        "background",
        "background/unlabeled",
        "background/unlabeled (non-road)",
        "Background / Unlabeled",
        "unlabeled (non-road)",
        "Clutter/background",
        "nodata",
        "no data",
        "void",
        "ignore",
        "unclassified",
        " background ",
    ],
)
def test_background_spellings(label: str) -> None:
    assert is_background_class(label)


@pytest.mark.parametrize(
    "label",
    [
        "building",
        "background road",  # a road in the background is still a road: whole aliases only
        "unlabeled building",
        "road (background)",  # parentheses are notes, never the class
        "paved road (buffered centerline)",
        "water (Hydro)",
        "tree crown (bounding box)",
        "voids in canopy",
        "low vegetation/grass",
    ],
)
def test_classes_that_name_a_thing_stay_entities(label: str) -> None:
    assert not is_background_class(label)


def test_load_class_entities_names_and_skips(tmp_path: Path) -> None:
    path = tmp_path / "classes.json"
    path.write_text(
        json.dumps(
            {
                "0": "background/unlabeled (non-road)",
                "1": "paved road (buffered centerline)",
                "2": "background road",
                "3": "Clutter/background",
            }
        )
    )
    assert load_class_entities(path) == {1: "paved road", 2: "background road"}


def test_only_background_spellings_is_a_one_line_error(tmp_path: Path) -> None:
    path = tmp_path / "classes.json"
    path.write_text(json.dumps({"0": "background/unlabeled", "255": "nodata (fill)"}))
    with pytest.raises(InputError, match="only background classes") as info:
        load_class_entities(path)
    assert "\n" not in str(info.value)
