"""``overseec:vectorize`` through ``processing.run``: the worker CLI's GeoPackage, byte for byte what
`overseec vectorize` writes, loaded as one styled polygon layer per entity."""

from __future__ import annotations

import json
from pathlib import Path

import fiona
import pytest
from qgis.core import QgsProcessingException

from overseec_core.cli import main as cli_main

from .conftest import ENTITIES, SAMPLE
from .processing_fixtures import *  # noqa: F403 (the fixtures: private settings, provider, project)

pytestmark = pytest.mark.qgis


def features(path: Path) -> dict[str, list[tuple]]:
    """Each layer's (pixels, area_m2, mean_prob, WKB) in file order."""
    out = {}
    for name in fiona.listlayers(path):
        with fiona.open(path, layer=name) as src:
            out[name] = [
                (f["properties"]["pixels"], f["properties"]["area_m2"], f["properties"]["mean_prob"], f["geometry"])
                for f in src
            ]
    return out


def test_vectorize_writes_what_the_cli_writes(provider, scene, tmp_path: Path) -> None:
    import processing

    res = processing.run(
        "overseec:vectorize", {"MASKS": str(scene.folder), "SIMPLIFY": 0.5, "OUTPUT": str(tmp_path / "alg.gpkg")}
    )
    assert res["OUTPUT"] == str(tmp_path / "alg.gpkg")
    cli_out = tmp_path / "cli.gpkg"
    assert cli_main(["-q", "vectorize", str(scene.folder), "--simplify", "0.5", "--out", str(cli_out)]) == 0
    got, expected = features(Path(res["OUTPUT"])), features(cli_out)
    assert list(got) == list(ENTITIES) and got == expected
    assert res["POLYGONS"] == sum(len(v) for v in got.values())
    water = got["water"]
    assert len(water) == 1 and water[0][0] == 16 * 20 and water[0][1] == pytest.approx(16 * 20 * 0.25)
    assert water[0][2] == pytest.approx(0.9)


def test_a_class_raster_and_a_non_gpkg_name(provider, tmp_path: Path) -> None:
    import processing

    res = processing.run(
        "overseec:vectorize",
        {
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "OUTPUT": str(tmp_path / "classes.shp"),  # the suffix follows the format
        },
    )
    assert res["OUTPUT"] == str(tmp_path / "classes.gpkg")
    classes = json.loads((SAMPLE / "classes.json").read_text())
    layers = features(Path(res["OUTPUT"]))
    assert layers and set(layers) <= {str(v).lower() for v in classes.values()}
    assert all(f[2] == 1.0 for fs in layers.values() for f in fs)


def test_the_source_must_be_one_of_the_two(provider, scene, tmp_path: Path) -> None:
    import processing

    with pytest.raises(QgsProcessingException, match="not both"):
        processing.run(
            "overseec:vectorize",
            {"MASKS": str(scene.folder), "LABELS": str(SAMPLE / "sample_labels.tif"), "OUTPUT": str(tmp_path / "x")},
        )
    with pytest.raises(QgsProcessingException, match="go together"):
        processing.run(
            "overseec:vectorize", {"LABELS": str(SAMPLE / "sample_labels.tif"), "OUTPUT": str(tmp_path / "x")}
        )


def test_a_worker_error_is_its_one_line(provider, tmp_path: Path) -> None:
    import processing

    (tmp_path / "empty").mkdir()
    with pytest.raises(QgsProcessingException, match="run `overseec segment` first"):
        processing.run("overseec:vectorize", {"MASKS": str(tmp_path / "empty"), "OUTPUT": str(tmp_path / "v.gpkg")})
    assert not (tmp_path / "v.gpkg").exists()


def test_the_polygons_load_as_one_styled_layer_per_entity(provider, project, scene) -> None:
    """runAndLoadResults (the toolbox with "Open output file"): the GeoPackage Processing loaded is
    replaced by one layer per entity in a group, filled in the entity's mask colour."""
    import processing
    from qgis.PyQt.QtGui import QColor

    from overseec_qgis.layers import ENTITY_COLOURS

    res = processing.runAndLoadResults("overseec:vectorize", {"MASKS": str(scene.folder), "OUTPUT": "TEMPORARY_OUTPUT"})
    assert res["OUTPUT"].endswith(".gpkg")
    (group,) = project.layerTreeRoot().findGroups()
    assert group.name().startswith("overseec polygons — ")
    loaded = [node.layer() for node in group.findLayers()]
    assert [layer.name() for layer in loaded] == [f"{e} polygons" for e in ENTITIES]
    assert len(project.mapLayers()) == len(ENTITIES)  # the layer Processing loaded is gone
    for i, layer in enumerate(loaded):
        assert layer.isValid() and layer.geometryType() == 2  # polygons
        assert layer.customProperty("overseec/role") == "polygons"
        assert layer.customProperty("overseec/entity") == ENTITIES[i]
        fill = layer.renderer().symbol().symbolLayer(0)
        assert fill.strokeColor().name() == QColor(ENTITY_COLOURS[i]).name()
        assert fill.color().name() == QColor(ENTITY_COLOURS[i]).name() and 0 < fill.color().alpha() < 255
        assert layer.fields().names()[-3:] == ["area_m2", "mean_prob", "pixels"]
