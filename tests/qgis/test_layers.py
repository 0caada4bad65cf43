"""Run outputs as layers: groups, styles, band-per-entity layers, provenance."""

from __future__ import annotations

import json

import pytest
from qgis.core import QgsLayerMetadata, QgsProject, QgsRasterLayer

from overseec_qgis.layers import (
    ENTITY_COLOURS,
    Provenance,
    add_costmap,
    add_run_outputs,
    resources_dir,
    style_path,
)

from .conftest import SAMPLE

pytestmark = pytest.mark.qgis


def test_shipped_styles_load() -> None:
    for name in ("costmap", "probability", "mask", "path"):
        assert style_path(name).is_file(), name
    assert (resources_dir() / "icons" / "overseec.svg").is_file()


def test_costmap_layer_has_the_0_to_1_ramp_legend_and_provenance(scene, qgis_new_project) -> None:
    prov = Provenance(
        run_dir=str(scene.folder),
        prompt="prefer the road",
        program="cost = 1.0",
        entities=("road", "grass"),
        stage="costmap",
    )
    layer = add_costmap(scene.costmap, None, prov)
    assert QgsProject.instance().mapLayer(layer.id()) is layer
    assert layer.crs().authid() == "EPSG:32633"
    r = layer.renderer()
    assert r.type() == "singlebandpseudocolor"
    assert (r.classificationMin(), r.classificationMax()) == (0.0, 1.0)
    items = r.shader().rasterShaderFunction().colorRampItemList()
    assert items[0].value == 0.0 and items[-1].value == 1.0
    assert items[0].color.name() != items[-1].color.name()
    legend = [text for text, _colour in r.legendSymbologyItems()]
    assert any("preferred" in t for t in legend) and any("avoid" in t for t in legend)
    md: QgsLayerMetadata = layer.metadata()
    assert "prefer the road" in md.abstract() and "cost = 1.0" in md.abstract()
    assert "overseec" in md.keywords() and md.keywords()["entities"] == ["road", "grass"]
    assert layer.customProperty("overseec/role") == "costmap"
    assert layer.customProperty("overseec/run_dir") == str(scene.folder)


def test_run_group_has_one_layer_per_entity_and_band(scene, qgis_new_project) -> None:
    (scene.folder / "manifest.json").write_text(
        json.dumps(
            {
                "entities": [{"name": n} for n in ("road", "grass", "water")],
                "cost_program": {"text": "cost = where(M['road'], 0.1, 0.5)"},
                "interpretation": {"prompt": "prefer the road, avoid water"},
            }
        )
    )
    group, layers = add_run_outputs(scene.folder, "overseec run: test")
    root = QgsProject.instance().layerTreeRoot()
    assert root.children()[0] is group and group.name() == "overseec run: test"
    names = [layer.name() for layer in layers]
    assert names == [
        "costmap",
        "road mask",
        "grass mask",
        "water mask",
        "road probability",
        "grass probability",
        "water probability",
    ]
    by_name = {layer.name(): layer for layer in layers}
    for i, entity in enumerate(("road", "grass", "water")):
        mask = by_name[f"{entity} mask"]
        prob = by_name[f"{entity} probability"]
        assert isinstance(mask, QgsRasterLayer) and mask.crs().authid() == "EPSG:32633"
        assert mask.renderer().type() == "paletted" and mask.renderer().band() == i + 1
        colours = {c.value: c.color for c in mask.renderer().classes()}
        assert colours[1].name() == ENTITY_COLOURS[i] and colours[0].alpha() == 0
        assert prob.renderer().type() == "singlebandpseudocolor" and prob.renderer().band() == i + 1
        assert prob.customProperty("overseec/entity") == entity
        # probabilities start hidden, masks and costmap visible
        assert not group.findLayer(prob.id()).isVisible()
        assert group.findLayer(mask.id()).isVisible()
    cm = by_name["costmap"]
    assert "prefer the road, avoid water" in cm.metadata().abstract()
    assert "cost = where" in cm.metadata().abstract()
    # layers point at the run directory's files, so a saved project reopens with them
    assert all(layer.source().startswith(str(scene.folder)) for layer in layers)


def test_project_round_trip_keeps_layers_and_provenance(scene, qgis_new_project, tmp_path) -> None:
    add_run_outputs(scene.folder, "overseec run: saved")
    project_file = tmp_path / "p.qgz"
    assert QgsProject.instance().write(str(project_file))
    QgsProject.instance().clear()
    assert QgsProject.instance().read(str(project_file))
    layers = QgsProject.instance().mapLayersByName("costmap")
    assert len(layers) == 1 and layers[0].isValid()
    assert layers[0].renderer().type() == "singlebandpseudocolor"
    assert layers[0].customProperty("overseec/role") == "costmap"
    assert QgsProject.instance().layerTreeRoot().findGroup("overseec run: saved") is not None


def test_a_runs_path_goes_into_the_routes_group_above_its_costmap(scene, qgis_new_project) -> None:
    """A run folder with a path: the path in the routes group at the top, the rest in the run's group."""
    import shutil

    from overseec_qgis.legend import PROP_ROUTES_GROUP, find_routes_group

    shutil.copy(SAMPLE / "reference_route.geojson", scene.folder / "path.geojson")
    group, layers = add_run_outputs(scene.folder, "overseec run: with a path")
    root = QgsProject.instance().layerTreeRoot()
    routes = find_routes_group()
    assert routes is not None and root.children()[0] is routes and routes.customProperty(PROP_ROUTES_GROUP)
    assert root.children()[1] is group
    (path,) = [node.layer() for node in routes.findLayers()]
    assert path.customProperty("overseec/role") == "path" and path in layers
    assert root.layerOrder()[0] is path


def test_layer_names_cut_long_prompts_at_a_word_with_an_ellipsis() -> None:
    """A prompt up to the limit is the name as written (whitespace folded); a longer one is cut at
    the last whole word that fits, with an ellipsis, and never exceeds the limit."""
    from overseec_qgis.legend import NAME_PROMPT_CHARS, short_text

    exact = "x" * (NAME_PROMPT_CHARS - 5) + " abcd"  # exactly the limit
    assert len(exact) == NAME_PROMPT_CHARS and short_text(exact) == exact
    assert short_text("prefer  the\troads\n") == "prefer the roads"
    long = "prefer the roads and trails, grass is fine, avoid the baseball field at all costs"
    cut = short_text(long)
    assert cut == "prefer the roads and trails, grass is fine…"
    assert len(cut) <= NAME_PROMPT_CHARS and long.startswith(cut.removesuffix("…"))
    assert short_text("a" * 60) == "a" * (NAME_PROMPT_CHARS - 1) + "…"  # no word to cut at
    assert short_text(long, limit=10) == "prefer…"
