"""Every overseec Processing algorithm through ``processing.run``, against the CLI's results.

Non-ML algorithms run in-process on the bundled sample scene (class raster + classes.json, so
no model is needed); Segment and Run start the real worker CLI with a tiny random CLIPSeg built
in a subprocess (this test process never imports torch for it).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio
from qgis.core import QgsProcessingException, QgsProcessingFeedback

from overseec_core.cli import main as cli_main

from .conftest import SAMPLE
from .processing_fixtures import *  # noqa: F403 (the fixtures: private settings, provider, project)

pytestmark = pytest.mark.qgis
#: The provider runs the worker the settings find (processing_fixtures.provider).
CONFIGURED_WORKER = True

PROMPT = json.loads((SAMPLE / "sample.json").read_text())["prompt"]
META = json.loads((SAMPLE / "sample.json").read_text())


def run(alg: str, params: dict, feedback=None) -> dict:
    import processing

    return processing.run(f"overseec:{alg}", params, feedback=feedback)


class Recording(QgsProcessingFeedback):
    def __init__(self) -> None:
        super().__init__()
        self.progress: list[float] = []
        self.infos: list[str] = []
        self.commands: list[str] = []
        self.progressChanged.connect(self.progress.append)

    def pushInfo(self, info: str) -> None:
        self.infos.append(info)
        super().pushInfo(info)

    def pushCommandInfo(self, info: str) -> None:
        self.commands.append(info)
        super().pushCommandInfo(info)


def read(path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read()


def test_interpret_writes_the_same_document_as_the_cli(provider, tmp_path: Path) -> None:
    res = run("interpret", {"PROMPT": PROMPT, "OUTPUT": str(tmp_path / "i.json")})
    doc = json.loads(Path(res["OUTPUT"]).read_text())
    assert {"road", "trail", "grass", "baseball field"} <= {e["name"] for e in doc["entities"]}
    assert "road" in res["ENTITIES"].split(",") and "cost =" in res["PROGRAM"]
    assert cli_main(["interpret", PROMPT, "--offline", "--out", str(tmp_path / "cli.json")]) == 0
    assert json.loads((tmp_path / "cli.json").read_text()) == doc


def test_costmap_matches_the_cli_pixel_for_pixel(provider, tmp_path: Path) -> None:
    fb = Recording()
    res = run(
        "costmap",
        {
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "PROMPT": PROMPT,
            "OUTPUT": str(tmp_path / "q" / "costmap.tif"),
        },
        fb,
    )
    out = Path(res["OUTPUT"])
    assert out == tmp_path / "q" / "costmap.tif" and Path(res["PROGRAM_FILE"]).is_file()
    assert 0.0 < res["MEAN_COST"] < 1.0
    assert fb.progress and max(fb.progress) == pytest.approx(100.0)
    assert (
        cli_main(
            [
                "costmap",
                "--labels",
                str(SAMPLE / "sample_labels.tif"),
                "--classes",
                str(SAMPLE / "classes.json"),
                "--prompt",
                PROMPT,
                "--out",
                str(tmp_path / "costmap.tif"),
            ]
        )
        == 0
    )
    np.testing.assert_array_equal(read(out), read(tmp_path / "costmap.tif"))
    with rasterio.open(out) as ds, rasterio.open(SAMPLE / "sample_labels.tif") as lab:
        assert ds.crs == lab.crs and ds.transform == lab.transform


def test_costmap_reports_a_bad_program_with_its_line(provider, scene, tmp_path: Path) -> None:
    with pytest.raises(QgsProcessingException, match=r"line 2.*nope"):
        run(
            "costmap",
            {
                "MASKS": str(scene.folder),
                "PROGRAM_TEXT": "a = M['road']\ncost = nope + 1",
                "OUTPUT": str(tmp_path / "bad.tif"),
            },
        )
    assert not (tmp_path / "bad.tif").exists()
    with pytest.raises(QgsProcessingException, match="MASKS"):
        run("costmap", {"PROGRAM_TEXT": "cost = 1.0", "OUTPUT": str(tmp_path / "x.tif")})


def test_costmap_prompt_entities_match_layers_with_aliases(provider, tmp_path: Path) -> None:
    base = {"LABELS": str(SAMPLE / "sample_labels.tif"), "CLASSES": str(SAMPLE / "classes.json")}
    # nothing the prompt names is on this map: an error, never a uniform costmap
    with pytest.raises(QgsProcessingException, match="matches a layer"):
        run("costmap", {**base, "PROMPT": "avoid the compound", "OUTPUT": str(tmp_path / "a.tif")})
    assert not (tmp_path / "a.tif").exists()
    fb = Recording()
    res = run(
        "costmap",
        {**base, "PROMPT": "avoid the compound", "ALIASES": "compound=building", "OUTPUT": str(tmp_path / "b.tif")},
        fb,
    )
    with rasterio.open(SAMPLE / "sample_labels.tif") as lab:
        labels = lab.read(1)
    cost = read(res["OUTPUT"])[0]
    assert cost[labels == 6].min() > 0.5 and np.all(cost[labels == 1] == 0.5)  # building, grass
    assert any("compound -> building (alias)" in m for m in fb.infos)
    with pytest.raises(QgsProcessingException, match="ALIASES"):
        run("costmap", {**base, "PROMPT": "avoid x", "ALIASES": "compound", "OUTPUT": str(tmp_path / "c.tif")})


def test_costmap_priors_of_unsaid_hazards_can_be_replaced_or_switched_off(provider, tmp_path: Path) -> None:
    """ "avoid the baseball field" says nothing of buildings: by default they take their prior
    (1.0, an obstacle: keep-out, 2, in the lethal sidecar); NO_PRIORS leaves them neutral; a
    PRIORS file replaces the table; both at once is the command's own one-line error."""
    base = {
        "LABELS": str(SAMPLE / "sample_labels.tif"),
        "CLASSES": str(SAMPLE / "classes.json"),
        "PROMPT": "avoid the baseball field",
    }
    building = read(SAMPLE / "sample_labels.tif")[0] == 6
    table = tmp_path / "priors.json"
    table.write_text('{"building": 0.9}')

    def building_cells(name: str, **params) -> tuple[set, set, list[str]]:
        """The costs and lethal-sidecar flags of the building cells, and the commands run."""
        fb = Recording()
        res = run("costmap", {**base, **params, "OUTPUT": str(tmp_path / name / "costmap.tif")}, fb)
        out = Path(res["OUTPUT"])
        cost, flags = read(out)[0], read(out.with_name("lethal.tif"))[0]
        costs = {round(float(c), 6) for c in np.unique(cost[building])}
        return costs, set(np.unique(flags[building]).tolist()), fb.commands

    cost, flags, commands = building_cells("default")
    assert cost == {1.0} and flags == {2}
    assert not any(" --priors" in c or " --no-priors" in c for c in commands)
    cost, flags, commands = building_cells("none", NO_PRIORS=True)
    assert cost == {0.5} and flags == {0}
    assert any(" --no-priors" in c for c in commands)
    cost, flags, commands = building_cells("file", PRIORS=str(table))
    assert cost == {0.9} and flags == {0}
    assert any(f" --priors={table}" in c for c in commands)
    with pytest.raises(QgsProcessingException, match="--no-priors: not allowed with argument --priors"):
        run("costmap", {**base, "PRIORS": str(table), "NO_PRIORS": True, "OUTPUT": str(tmp_path / "both.tif")})
    assert not (tmp_path / "both.tif").exists()


def test_interpret_run_and_compare_take_priors_too(provider, tmp_path: Path) -> None:
    """PRIORS / NO_PRIORS reach `overseec interpret`, `run` and `compare` as they reach costmap."""
    table = tmp_path / "priors.json"
    table.write_text('{"building": 0.9}')
    prompt = "avoid the baseball field"

    def priors_of(doc: dict) -> dict:
        return {p["entity"]: p["weight"] for p in doc["preferences"] if p.get("prior")}

    res = run("interpret", {"PROMPT": prompt, "OUTPUT": str(tmp_path / "builtin.json")})
    assert priors_of(json.loads(Path(res["OUTPUT"]).read_text()))["building"] == 1.0
    res = run("interpret", {"PROMPT": prompt, "PRIORS": str(table), "OUTPUT": str(tmp_path / "file.json")})
    assert priors_of(json.loads(Path(res["OUTPUT"]).read_text())) == {"building": 0.9}
    res = run("interpret", {"PROMPT": prompt, "NO_PRIORS": True, "OUTPUT": str(tmp_path / "none.json")})
    assert priors_of(json.loads(Path(res["OUTPUT"]).read_text())) == {}

    labels = {"LABELS": str(SAMPLE / "sample_labels.tif"), "CLASSES": str(SAMPLE / "classes.json")}
    res = run(
        "run",
        {
            "INPUT": str(SAMPLE / "sample.tif"),
            "PROMPT": prompt,
            **labels,
            "NO_PRIORS": True,
            "EVALUATE": False,
            "OUTPUT_DIR": str(tmp_path / "run"),
        },
    )
    building = read(SAMPLE / "sample_labels.tif")[0] == 6
    assert np.all(read(res["COSTMAP"])[0][building] == 0.5)

    (sx, sy), (gx, gy) = META["start"], META["goal"]
    fb = Recording()
    res = run(
        "compare",
        {
            **labels,
            "PROMPTS": f"{prompt}\nprefer the roads",
            "PRIORS": str(table),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "MODE": 0,
            "OUTPUT_DIR": str(tmp_path / "compare"),
        },
        fb,
    )
    assert any(f" --priors={table}" in c for c in fb.commands)
    cost = read(tmp_path / "compare" / "prompt_1" / "costmap.tif")[0]
    assert np.allclose(cost[building], 0.9)


def test_costmap_chains_from_a_segment_folder(provider, scene, tmp_path: Path) -> None:
    program = "cost = where(M['road'], 0.1, 0.6)\nlethal = M['water']\n"
    res = run("costmap", {"MASKS": str(scene.folder), "PROGRAM_TEXT": program, "OUTPUT": str(tmp_path / "cm.tif")})
    cost = read(res["OUTPUT"])[0]
    masks = read(scene.masks)
    assert np.allclose(cost[masks[0] == 1], 0.1) and np.allclose(cost[(masks[0] == 0) & (masks[2] == 0)], 0.6)


@pytest.fixture(scope="module")
def sample_costmap(provider, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("sample") / "costmap.tif"
    run(
        "costmap",
        {
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "PROMPT": PROMPT,
            "OUTPUT": str(out),
        },
    )
    return out


def _wgs84(x: float, y: float) -> tuple[float, float]:
    from pyproj import Transformer

    return Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True).transform(x, y)


def test_plan_matches_the_cli_and_takes_points_in_any_crs(provider, sample_costmap, tmp_path: Path) -> None:
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    res = run(
        "plan",
        {
            "COSTMAP": str(sample_costmap),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "MODE": 1,
            "OUTPUT": str(tmp_path / "q" / "path.geojson"),
        },
    )
    doc = json.loads(Path(res["OUTPUT"]).read_text())
    props = doc["features"][0]["properties"]
    assert props["total_cost"] == pytest.approx(res["COST"]) and props["length_m"] == pytest.approx(res["LENGTH_M"])
    assert (
        cli_main(
            [
                "plan",
                str(sample_costmap),
                "--start",
                str(sx),
                str(sy),
                "--goal",
                str(gx),
                str(gy),
                "--mode",
                "exact",
                "--out",
                str(tmp_path / "cli.geojson"),
            ]
        )
        == 0
    )
    cli = json.loads((tmp_path / "cli.geojson").read_text())
    assert cli["features"][0]["geometry"] == doc["features"][0]["geometry"]
    # the same points given in WGS 84: Processing reprojects them to the costmap's CRS
    (slon, slat), (glon, glat) = _wgs84(sx, sy), _wgs84(gx, gy)
    res84 = run(
        "plan",
        {
            "COSTMAP": str(sample_costmap),
            "START": f"{slon!r},{slat!r} [EPSG:4326]",
            "GOAL": f"{glon!r},{glat!r} [EPSG:4326]",
            "MODE": 1,
            "OUTPUT": str(tmp_path / "p84.geojson"),
        },
    )
    assert res84["COST"] == pytest.approx(res["COST"], rel=1e-9)


def test_plan_passes_the_generated_planner_parameters_to_the_cli(provider, sample_costmap, tmp_path: Path) -> None:
    """BASE_COST_PER_M and LETHAL_THRESHOLD (generated from `overseec plan`'s declarations) reach
    the CLI: the route is the CLI's own with the same flags, and not the default's."""
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    points = {"COSTMAP": str(sample_costmap), "START": f"{sx},{sy} [EPSG:32633]", "GOAL": f"{gx},{gy} [EPSG:32633]"}
    plain = run("plan", {**points, "MODE": 1, "OUTPUT": str(tmp_path / "plain.geojson")})
    tuned = {"MODE": 1, "BASE_COST_PER_M": 2.0, "LETHAL_THRESHOLD": 0.9}
    res = run("plan", {**points, **tuned, "OUTPUT": str(tmp_path / "tuned.geojson")})
    argv = ["plan", str(sample_costmap), "--start", str(sx), str(sy), "--goal", str(gx), str(gy), "--mode", "exact"]
    argv += ["--base-cost-per-m", "2", "--lethal-threshold", "0.9", "--out", str(tmp_path / "cli.geojson")]
    assert cli_main(argv) == 0
    cli = json.loads((tmp_path / "cli.geojson").read_text())["features"][0]
    assert res["COST"] == pytest.approx(cli["properties"]["total_cost"], rel=1e-9)
    assert res["COST"] > plain["COST"] + 1.0  # two cost units a metre more than the default's 0.01


def test_plan_through_via_points_from_a_layer(provider, scene, tmp_path: Path) -> None:
    from qgis.core import QgsFeature, QgsGeometry, QgsPointXY, QgsVectorLayer

    vias = QgsVectorLayer("Point?crs=EPSG:32633", "vias", "memory")
    f = QgsFeature()
    f.setGeometry(QgsGeometry.fromPointXY(QgsPointXY(*scene.world(2, 30))))
    vias.dataProvider().addFeatures([f])
    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(44, 60)
    res = run(
        "plan",
        {
            "COSTMAP": str(scene.costmap),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "VIAS": vias,
            "MODE": 1,
            "OUTPUT": str(tmp_path / "via.geojson"),
        },
    )
    direct = run(
        "plan",
        {
            "COSTMAP": str(scene.costmap),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "MODE": 1,
            "OUTPUT": str(tmp_path / "direct.geojson"),
        },
    )
    assert res["COST"] > direct["COST"]  # the detour through (2, 30) costs more
    props = json.loads(Path(res["OUTPUT"]).read_text())["features"][0]["properties"]
    assert len(props["waypoints"]) == 3


def _override_layer(scene, rows: range, cols: range, **fields):
    """A memory polygon layer over the given pixel rows/cols of the scene, with override fields."""
    from qgis.core import QgsFeature, QgsField, QgsGeometry, QgsPointXY, QgsVectorLayer
    from qgis.PyQt.QtCore import QVariant

    layer = QgsVectorLayer("Polygon?crs=EPSG:32633", "overrides", "memory")
    layer.dataProvider().addAttributes(
        [QgsField("cost", QVariant.Double), QgsField("lethal", QVariant.Int), QgsField("prefer", QVariant.Int)]
    )
    layer.updateFields()
    (x0, y0), (x1, y1) = scene.world(rows.start, cols.start), scene.world(rows.stop, cols.stop)
    f = QgsFeature(layer.fields())
    ring = [QgsPointXY(x0, y0), QgsPointXY(x1, y0), QgsPointXY(x1, y1), QgsPointXY(x0, y1)]
    f.setGeometry(QgsGeometry.fromPolygonXY([ring]))
    for name, value in fields.items():
        f[name] = value
    layer.dataProvider().addFeatures([f])
    return layer


def test_plan_and_costmap_take_override_polygons_from_a_layer(provider, scene, tmp_path: Path) -> None:
    """A preferred corridor drawn on the map (a memory layer, as an analyst draws it) pulls the
    route onto it, in Plan (costmap file untouched) exactly as in Costmap then Plan."""
    program = 'cost = where(M["road"], 0.05, 0.5)\nlethal = M["water"]'
    base = run(
        "costmap",
        {"MASKS": str(scene.folder), "PROGRAM_TEXT": program, "OUTPUT": str(tmp_path / "base" / "costmap.tif")},
    )["OUTPUT"]
    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(44, 60)
    points = {"START": f"{sx},{sy} [EPSG:32633]", "GOAL": f"{gx},{gy} [EPSG:32633]", "MODE": 1}
    before = Path(base).read_bytes()
    plain = run("plan", {"COSTMAP": base, **points, "OUTPUT": str(tmp_path / "a.geojson")})
    corridor = _override_layer(scene, range(42, 46), range(0, 64), prefer=1)
    moved = run("plan", {"COSTMAP": base, **points, "OVERRIDES": [corridor], "OUTPUT": str(tmp_path / "b.geojson")})
    assert Path(base).read_bytes() == before
    props = json.loads(Path(moved["OUTPUT"]).read_text())["features"][0]["properties"]
    assert props["overrides_applied"] is True and moved["COST"] < 0.5 * plain["COST"]
    edited = run(
        "costmap",
        {
            "MASKS": str(scene.folder),
            "PROGRAM_TEXT": program,
            "OVERRIDES": [corridor],
            "OUTPUT": str(tmp_path / "edited" / "costmap.tif"),
        },
    )
    again = run("plan", {"COSTMAP": edited["OUTPUT"], **points, "OUTPUT": str(tmp_path / "d.geojson")})
    assert again["COST"] == pytest.approx(moved["COST"], rel=1e-9)


def test_plan_onto_lethal_water_is_a_one_line_error(provider, scene, tmp_path: Path) -> None:
    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(25, 30)
    with pytest.raises(QgsProcessingException, match="goal.*lethal"):
        run(
            "plan",
            {
                "COSTMAP": str(scene.costmap),
                "START": f"{sx},{sy} [EPSG:32633]",
                "GOAL": f"{gx},{gy} [EPSG:32633]",
                "OUTPUT": str(tmp_path / "x.geojson"),
            },
        )


def test_plan_on_a_costmap_without_a_crs_says_so_not_blaming_the_point(provider, scene, tmp_path: Path) -> None:
    bare = tmp_path / "no_crs.tif"
    with rasterio.open(scene.costmap) as src:
        profile = {**src.profile, "crs": None}
        with rasterio.open(bare, "w", **profile) as dst:
            dst.write(src.read())
    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(3, 60)
    with pytest.raises(QgsProcessingException, match="no_crs.tif has no CRS") as err:
        run(
            "plan",
            {"COSTMAP": str(bare), "START": f"{sx},{sy}", "GOAL": f"{gx},{gy}", "OUTPUT": str(tmp_path / "p.geojson")},
        )
    assert "not a CRS" not in str(err.value) and not (tmp_path / "p.geojson").exists()


def test_evaluate_writes_metrics_like_the_cli(provider, sample_costmap, tmp_path: Path) -> None:
    ranks = ",".join(f"{k}={v}" for k, v in META["ranks"].items())
    res = run(
        "evaluate",
        {
            "COSTMAP": str(sample_costmap),
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "RANKS": ranks,
            "PAIRS": 3,
            "SEED": 1,
            "MODE": 1,
            "REFERENCE": str(SAMPLE / "reference_route.geojson"),
            "PLOTS": False,
            "OUTPUT_DIR": str(tmp_path / "q"),
        },
    )
    metrics = json.loads(Path(res["METRICS"]).read_text())
    assert metrics["sampling"]["drawn"] == 3 and Path(res["REPORT"]).is_file()
    assert res["MEAN_HAUSDORFF"] is not None and res["MEAN_HAUSDORFF"] >= 0
    # the paper's figure (mean point distance) never exceeds the per-path maximum's
    assert 0 <= res["HAUSDORFF_PAPER"] <= res["MEAN_HAUSDORFF"]
    assert res["HAUSDORFF_PAPER"] == metrics["hausdorff"]["mean_paper_normalised"]
    assert metrics["sampling"]["draw"] == "passable"
    assert (
        cli_main(
            [
                "eval",
                "--costmap",
                str(sample_costmap),
                "--labels",
                str(SAMPLE / "sample_labels.tif"),
                "--classes",
                str(SAMPLE / "classes.json"),
                "--ranks",
                ranks,
                "--pairs",
                "3",
                "--seed",
                "1",
                "--mode",
                "exact",
                "--reference",
                str(SAMPLE / "reference_route.geojson"),
                "--no-plots",
                "--out",
                str(tmp_path / "c"),
            ]
        )
        == 0
    )
    cli = json.loads((tmp_path / "c" / "metrics.json").read_text())
    assert cli["paths"] == metrics["paths"] and cli["hausdorff"] == metrics["hausdorff"]


def test_run_with_a_class_raster_goes_through_the_worker_without_models(provider, tmp_path: Path) -> None:
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    fb = Recording()
    res = run(
        "run",
        {
            "INPUT": str(SAMPLE / "sample.tif"),
            "PROMPT": PROMPT,
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "EVALUATE": False,
            "OUTPUT_DIR": str(tmp_path / "run"),
        },
        fb,
    )
    out = tmp_path / "run"
    assert res["COSTMAP"] == str(out / "costmap.tif") and res["PATH"] == str(out / "path.geojson")
    assert res["MASKS"] is None  # the class raster stood in for segmentation
    manifest = json.loads(Path(res["MANIFEST"]).read_text())
    assert {"interpret", "costmap"} <= set(manifest["stages"]) and "segment" not in manifest["stages"]
    props = json.loads((out / "path.geojson").read_text())["features"][0]["properties"]
    assert props["total_cost"] > 0 and props["mode"] == "exact"
    assert fb.progress and max(fb.progress) == pytest.approx(100.0)
    assert any("/overseec" in c and " run " in c for c in fb.commands)


# --------------------------------------------------------------------------------------------
# Worker algorithms: the real `overseec` CLI in a subprocess, with a tiny random CLIPSeg
# --------------------------------------------------------------------------------------------


@pytest.mark.models
def test_segment_runs_the_worker_and_outputs_named_bands(provider, scene, tiny_clipseg, tmp_path: Path) -> None:
    fb = Recording()
    res = run(
        "segment",
        {
            "INPUT": str(scene.image),
            "ENTITIES": "road:linear, grass, water",
            "SEGMENTER": 0,  # clipseg, the registry's first (and default)
            "MODEL": str(tiny_clipseg),
            "REFINE": False,
            "TILE_SIZE": 64,
            "OVERLAP": 8,
            "DEVICE": 1,
            "OUTPUT_DIR": str(tmp_path / "seg"),
        },
        fb,
    )
    assert Path(res["MASKS"]) == tmp_path / "seg" / "masks.tif"
    with rasterio.open(res["PROBS"]) as ds, rasterio.open(scene.image) as img:
        assert ds.descriptions == ("road", "grass", "water")
        assert ds.crs == img.crs and ds.transform == img.transform
        probs = ds.read()
    assert np.isfinite(probs).all() and (probs >= 0).all() and (probs <= 1).all()
    masks = read(res["MASKS"])
    # thresholds: linear 0.4, areal 0.8 (the form's defaults, written into entities.json)
    np.testing.assert_array_equal(masks[0], (probs[0] >= 0.4).astype(np.uint8))
    np.testing.assert_array_equal(masks[1], (probs[1] >= 0.8).astype(np.uint8))
    doc = json.loads((tmp_path / "seg" / "entities.json").read_text())
    assert [(e["name"], e["geometry"], e["threshold"]) for e in doc["entities"]] == [
        ("road", "linear", 0.4),
        ("grass", "areal", 0.8),
        ("water", "areal", 0.8),
    ]
    assert fb.progress and max(fb.progress) == pytest.approx(100.0)
    # the worker's manifest names the segmenter and the model it ran
    manifest = json.loads((tmp_path / "seg" / "manifest.json").read_text())
    assert manifest["segmenter"] == "clipseg"
    assert manifest["models"]["clipseg"]["path"] == str(tiny_clipseg)


def test_segment_passes_the_chosen_segmenter_and_model_to_the_worker(provider, scene, tmp_path: Path) -> None:
    """SEGMENTER and MODEL reach `overseec segment` as --segmenter/--model: the worker's own
    one-line error names that segmenter's model (or says the backend is not in this version)."""
    from overseec_qgis.processing.parameters import SEGMENTERS

    fb = Recording()
    missing = str(tmp_path / "no-such-model")
    with pytest.raises(QgsProcessingException) as err:
        run(
            "segment",
            {
                "INPUT": str(scene.image),
                "ENTITIES": "road:linear",
                "SEGMENTER": SEGMENTERS.index("semantic"),
                "MODEL": missing,
                "REFINE": False,
                "OUTPUT_DIR": str(tmp_path / "seg"),
            },
            fb,
        )
    message = str(err.value)
    # the worker took both flags (an older one reads --model as an abbreviated --model-size) ...
    assert "unrecognized arguments" not in message and "--model-size" not in message
    assert "segmenter 'semantic' is not installed in this version" in message or missing in message  # ... and used them
    assert any("--segmenter semantic --model " + missing in c for c in fb.commands)


@pytest.mark.models
def test_cancelling_a_worker_algorithm_stops_it_and_leaves_no_outputs(provider, tiny_clipseg, tmp_path: Path) -> None:
    fb = Recording()
    seen = []

    def on_progress(value: float) -> None:
        seen.append(value)
        fb.cancel()  # the first progress report from the worker

    fb.progressChanged.connect(on_progress)
    with pytest.raises(QgsProcessingException, match="cancelled"):
        run(
            "segment",
            {
                "INPUT": str(SAMPLE / "sample.tif"),
                "ENTITIES": "road:linear, grass",
                "CLIPSEG_MODEL": str(tiny_clipseg),
                "REFINE": False,
                "TILE_SIZE": 64,
                "OVERLAP": 0,
                "DEVICE": 1,
                "OUTPUT_DIR": str(tmp_path / "seg"),
            },
            fb,
        )
    assert seen
    out = tmp_path / "seg"
    assert not (out / "probs.tif").exists() and not (out / "masks.tif").exists()
    assert not [p for p in out.iterdir() if p.suffix == ".tif" or ".partial" in p.name]


def test_segment_without_a_worker_says_what_to_run(provider, scene, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr("overseec_qgis.jobs.find_worker_for", lambda settings: None)
    with pytest.raises(QgsProcessingException, match="worker.*not found.*OVERSEEC_VENV"):
        run("segment", {"INPUT": str(scene.image), "ENTITIES": "road", "OUTPUT_DIR": str(tmp_path / "s")})


def test_segment_checks_its_entities_before_starting_a_worker(provider, scene, tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text('{"entities": [{"geometry": "linear"}]}')
    with pytest.raises(QgsProcessingException, match="entity 1 has no"):
        run("segment", {"INPUT": str(scene.image), "INTERPRETATION": str(bad), "OUTPUT_DIR": str(tmp_path / "s")})
    with pytest.raises(QgsProcessingException, match="either INTERPRETATION"):
        run("segment", {"INPUT": str(scene.image), "OUTPUT_DIR": str(tmp_path / "s")})
    with pytest.raises(QgsProcessingException, match="geometry must be linear or areal"):
        run("segment", {"INPUT": str(scene.image), "ENTITIES": "road:wiggly", "OUTPUT_DIR": str(tmp_path / "s")})


def test_algorithms_chain_in_a_graphical_model(provider, tmp_path: Path) -> None:
    """Costmap -> Plan as a Modeler model: the costmap output feeds the planner's input."""
    from qgis.core import QgsProcessingModelAlgorithm, QgsProcessingModelChildAlgorithm, QgsProcessingModelOutput
    from qgis.core import QgsProcessingModelChildParameterSource as Source

    (sx, sy), (gx, gy) = META["start"], META["goal"]
    model = QgsProcessingModelAlgorithm("costmap then plan", "overseec")
    cost = QgsProcessingModelChildAlgorithm("overseec:costmap")
    cost.setChildId("costmap")
    for name, value in (
        ("LABELS", str(SAMPLE / "sample_labels.tif")),
        ("CLASSES", str(SAMPLE / "classes.json")),
        ("PROMPT", PROMPT),
    ):
        cost.addParameterSources(name, [Source.fromStaticValue(value)])
    cost.addParameterSources("OUTPUT", [Source.fromStaticValue(str(tmp_path / "m" / "costmap.tif"))])
    model.addChildAlgorithm(cost)
    plan = QgsProcessingModelChildAlgorithm("overseec:plan")
    plan.setChildId("plan")
    plan.addParameterSources("COSTMAP", [Source.fromChildOutput("costmap", "OUTPUT")])
    plan.addParameterSources("START", [Source.fromStaticValue(f"{sx},{sy} [EPSG:32633]")])
    plan.addParameterSources("GOAL", [Source.fromStaticValue(f"{gx},{gy} [EPSG:32633]")])
    plan.addParameterSources("MODE", [Source.fromStaticValue(1)])
    out = QgsProcessingModelOutput("path", "path")
    out.setChildId("plan")
    out.setChildOutputName("OUTPUT")
    plan.setModelOutputs({"path": out})
    plan.setDependencies([])
    model.addChildAlgorithm(plan)
    model.updateDestinationParameters()
    import processing

    res = processing.run(model, {"plan:path": str(tmp_path / "m" / "path.geojson")})
    path = Path(res["plan:path"])
    assert path.is_file() and (tmp_path / "m" / "costmap.tif").is_file()
    props = json.loads(path.read_text())["features"][0]["properties"]
    assert props["costmap"] == str(tmp_path / "m" / "costmap.tif") and props["total_cost"] > 0


def test_export_costmap_and_path_for_other_planners(provider, sample_costmap, tmp_path: Path) -> None:
    """Nav2 map, costmap_2d GeoTIFF and the path as GPX/CSV, read back by their readers."""
    import fiona
    import yaml

    (sx, sy), (gx, gy) = META["start"], META["goal"]
    path = run(
        "plan",
        {
            "COSTMAP": str(sample_costmap),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "MODE": 1,
            "OUTPUT": str(tmp_path / "path.geojson"),
        },
    )["OUTPUT"]
    nav2 = run(
        "exportcostmap", {"COSTMAP": str(sample_costmap), "FORMAT": 0, "OUTPUT": str(tmp_path / "nav2" / "map.yaml")}
    )
    doc = yaml.safe_load(Path(nav2["OUTPUT"]).read_text())
    with rasterio.open(sample_costmap) as ds:
        assert doc["resolution"] == pytest.approx(abs(ds.transform.a))
        shape = ds.shape
    pgm = (Path(nav2["OUTPUT"]).parent / doc["image"]).read_bytes()
    assert pgm.startswith(b"P5") and f"{shape[1]} {shape[0]}".encode() in pgm[:64]
    c2d = run("exportcostmap", {"COSTMAP": str(sample_costmap), "FORMAT": 1, "OUTPUT": str(tmp_path / "c2d.tif")})
    with rasterio.open(c2d["OUTPUT"]) as ds, rasterio.open(sample_costmap) as src:
        values, cost = ds.read(1), src.read(1)
        assert ds.dtypes[0] == "uint8" and ds.transform == src.transform
    ok = np.isfinite(cost)
    assert np.array_equal(values[ok & (values < 253)], np.floor(252 * cost[ok & (values < 253)] + 0.5).astype(np.uint8))
    gpx = run("exportpath", {"PATH": path, "FORMAT": 0, "OUTPUT": str(tmp_path / "path.gpx")})
    with fiona.open(gpx["OUTPUT"], layer="tracks") as src:
        (track,) = list(src)
    line = json.loads(Path(path).read_text())["features"][0]["geometry"]["coordinates"]
    assert track["geometry"]["coordinates"][0][0] == pytest.approx(tuple(line[0]), abs=1e-7)
    csv = run("exportpath", {"PATH": path, "FORMAT": 2, "OUTPUT": str(tmp_path / "path.csv")})
    rows = Path(csv["OUTPUT"]).read_text().splitlines()
    assert rows[0].startswith("path,index,x,y,length_m") and len(rows) == len(line) + 1


def test_export_path_takes_the_map_tools_route_layer_and_its_selection(provider, tmp_path: Path) -> None:
    """A route table of the map tool's paths.gpkg (any CRS, one table of several), as the layer
    QGIS has open and as its source string, all routes or the selected one: GPX tracks."""
    import fiona
    from qgis.core import (
        QgsCoordinateReferenceSystem,
        QgsFeature,
        QgsGeometry,
        QgsPointXY,
        QgsProcessingFeatureSourceDefinition,
        QgsProject,
        QgsVectorLayer,
    )

    from overseec_qgis.layers import create_paths_table

    gpkg = tmp_path / "paths.gpkg"
    crs = QgsCoordinateReferenceSystem("EPSG:32633")
    context = QgsProject.instance().transformContext()
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    for table in ("paths_other", "paths_costmap"):
        assert create_paths_table(gpkg, table, crs, context) == ""
    layer = QgsVectorLayer(f"{gpkg}|layername=paths_costmap", "path — prefer the roads", "ogr")
    assert layer.isValid()
    for k in range(2):
        f = QgsFeature(layer.fields())
        mid = QgsPointXY((sx + gx) / 2 + 5 * k, (sy + gy) / 2)
        f.setGeometry(QgsGeometry.fromPolylineXY([QgsPointXY(sx, sy), mid, QgsPointXY(gx, gy)]))
        f.setAttribute("total_cost", 10.0 + k)
        f.setAttribute("mode", "exact")
        f.setAttribute("waypoints", QgsGeometry.fromMultiPointXY([QgsPointXY(sx, sy), QgsPointXY(gx, gy)]).asWkt())
        assert layer.dataProvider().addFeatures([f])[0]
    QgsProject.instance().addMapLayer(layer)
    try:
        for source in (layer, layer.source()):
            out = run("exportpath", {"PATH": source, "FORMAT": 0, "OUTPUT": str(tmp_path / "all.gpx")})["OUTPUT"]
            with fiona.open(out, layer="tracks") as src:
                descs = [t["properties"]["desc"] for t in src]
            assert len(descs) == 2 and descs[0].startswith("cost 10; ")
        layer.selectByIds([f.id() for f in layer.getFeatures() if f["total_cost"] == 11.0])
        picked = QgsProcessingFeatureSourceDefinition(layer.id(), selectedFeaturesOnly=True)
        out = run("exportpath", {"PATH": picked, "FORMAT": 0, "OUTPUT": str(tmp_path / "one.gpx")})["OUTPUT"]
        with fiona.open(out, layer="tracks") as src:
            (track,) = list(src)
        assert track["properties"]["desc"].startswith("cost 11; ")
        with fiona.open(out, layer="waypoints") as src:
            names = [w["properties"]["name"] for w in src]
        assert names == ["start", "goal"]
    finally:
        QgsProject.instance().removeMapLayer(layer.id())


def test_compare_prompts_side_by_side(provider, tmp_path: Path) -> None:
    """Two prompts on the sample labels: two routes, a difference raster, figure and table."""
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    res = run(
        "compare",
        {
            "PROMPTS": "prefer roads\nprefer grass, avoid roads",
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "MODE": 1,
            "OUTPUT_DIR": str(tmp_path / "cmp"),
        },
    )
    out = Path(res["OUTPUT_DIR"])
    assert (out / "prompt_1" / "path.geojson").is_file() and (out / "prompt_2" / "path.geojson").is_file()
    assert res["MAX_HAUSDORFF_M"] > 10  # the two prompts route differently
    with (
        rasterio.open(res["DIFFERENCE"]) as ds,
        rasterio.open(out / "prompt_1" / "costmap.tif") as a,
        rasterio.open(out / "prompt_2" / "costmap.tif") as b,
    ):
        assert np.allclose(ds.read(1), b.read(1) - a.read(1), equal_nan=True)
    header = Path(res["TABLE"]).read_text().splitlines()[0]
    assert "length_m" in header and Path(res["FIGURE"]).stat().st_size > 10_000


def test_plan_smooths_the_route_on_request(provider, sample_costmap, tmp_path: Path) -> None:
    """SMOOTH straightens the staircase within the tolerance and keeps the grid route's figures."""
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    points = {
        "COSTMAP": str(sample_costmap),
        "START": f"{sx},{sy} [EPSG:32633]",
        "GOAL": f"{gx},{gy} [EPSG:32633]",
        "MODE": 1,
    }
    grid = run("plan", {**points, "OUTPUT": str(tmp_path / "grid.geojson")})
    smooth = run(
        "plan", {**points, "SMOOTH": True, "SMOOTH_TOLERANCE": 0.01, "OUTPUT": str(tmp_path / "smooth.geojson")}
    )
    props = json.loads(Path(smooth["OUTPUT"]).read_text())["features"][0]["properties"]
    assert props["n_vertices"] < props["grid_route"]["n_vertices"]
    assert smooth["COST"] <= 1.01 * props["grid_route"]["cost_integral"] + 1e-9
    assert smooth["LENGTH_M"] < grid["LENGTH_M"]


# --------------------------------------------------------------------------------------------
# As users run them: default temporary outputs loaded, named, styled and grouped
# --------------------------------------------------------------------------------------------


def run_and_load(alg: str, params: dict, feedback=None) -> dict:
    """``processing.runAndLoadResults``: what the toolbox does with "Open output file" ticked."""
    import processing

    return processing.runAndLoadResults(f"overseec:{alg}", params, feedback=feedback)


def loaded(project, name_prefix: str):
    found = [lay for lay in project.mapLayers().values() if lay.name().startswith(name_prefix)]
    assert len(found) == 1, f"{name_prefix!r} among {[lay.name() for lay in project.mapLayers().values()]}"
    return found[0]


def styled_like(layer, style: str) -> bool:
    """The layer's renderer is the one resources/styles/<style>.qml gives a fresh layer."""
    from overseec_qgis.layers import apply_style

    ref = layer.clone()
    apply_style(ref, style)
    if layer.type() == layer.VectorLayer:
        return layer.renderer().dump() == ref.renderer().dump()
    a, b = layer.renderer(), ref.renderer()
    return type(a) is type(b) and a.shader().rasterShaderFunction().colorRampItemList() == (
        b.shader().rasterShaderFunction().colorRampItemList()
    )


def test_toolbox_shows_one_overseec_level_with_help(provider) -> None:
    """overseec > Pipeline/Evaluate/Export > algorithm; every algorithm links its README entry
    and says which inputs it needs; Build costmap lists what it needs first, options under Advanced."""
    from qgis.core import QgsProcessingParameterDefinition

    groups = {alg.group() for alg in provider.algorithms()}
    assert groups == {"Pipeline", "Evaluate", "Export"} and provider.name() not in groups
    from overseec_qgis.processing.base import OverseecAlgorithm

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    for alg in provider.algorithms():
        assert f'<a id="processing-{alg.name()}"></a>' in readme
        if not isinstance(alg, OverseecAlgorithm):
            continue  # extractimagery: its own module and help
        assert alg.helpUrl().endswith(f"README.md#processing-{alg.name()}")
        assert "Needs" in alg.shortHelpString()
    costmap = provider.algorithm("costmap")
    required_first = [p.name() for p in costmap.parameterDefinitions() if not p.flags() & p.FlagAdvanced]
    assert required_first == ["MASKS", "LABELS", "CLASSES", "PROMPT", "PROGRAM_TEXT", "PROGRAM", "OUTPUT"]
    assert all(
        costmap.parameterDefinition(n).flags() & QgsProcessingParameterDefinition.FlagAdvanced
        for n in ("ALIASES", "OVERRIDES")
    )
    help_text = costmap.shortHelpString()
    assert "MASKS, or LABELS + CLASSES" in help_text and "exactly one of PROMPT" in help_text
    assert "Entity layers: class raster (integer ids): a classified raster" in help_text


def test_each_declared_flag_is_a_parameter_and_an_option_of_the_command(provider) -> None:
    """FLAGS name the algorithm's own parameters and options its `overseec` command declares (read
    back from the CLI's parser); a boolean whose switch is given when off feeds a switch; an enum
    offers exactly the CLI's choices (in Processing's order) and defaults to a value it offers."""
    from qgis.core import QgsProcessingParameterBoolean, QgsProcessingParameterEnum

    from overseec_core.commands.spec import command_spec
    from overseec_qgis.processing.base import OverseecAlgorithm

    checked = 0
    for alg in provider.algorithms():
        if not isinstance(alg, OverseecAlgorithm):
            continue  # extractimagery runs in-process, no command
        spec = command_spec(alg.COMMAND)
        assert alg.INVERTED <= alg.FLAGS.keys() and alg.OWN_DEFAULTS.keys() <= alg.FLAGS.keys()
        for name, flag in alg.FLAGS.items():
            definition = alg.parameterDefinition(name)
            assert definition is not None, f"{alg.name()}: FLAGS names no parameter {name}"
            option = spec.option(flag)  # KeyError naming the command when it has no such flag
            if name in alg.INVERTED:
                assert isinstance(definition, QgsProcessingParameterBoolean) and not option.takes_value
            if isinstance(definition, QgsProcessingParameterEnum) and option.choices is not None:
                assert sorted(definition.options()) == sorted(option.choices), f"{alg.name()}: {name}"
            checked += 1
    assert checked > 60


def test_costmap_and_plan_temporary_outputs_load_named_and_styled(provider, project, scene) -> None:
    program = 'cost = where(M["road"], 0.05, 0.5)\nlethal = M["water"]'
    cost = run_and_load("costmap", {"MASKS": str(scene.folder), "PROGRAM_TEXT": program, "OUTPUT": "TEMPORARY_OUTPUT"})
    assert cost["OUTPUT"].endswith(".tif") and Path(cost["OUTPUT"]).is_file()
    layer = loaded(project, "costmap — ")
    assert layer.isValid() and layer.source() == cost["OUTPUT"] and styled_like(layer, "costmap")
    assert layer.customProperty("overseec/role") == "costmap"

    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(2, 60)
    fb = Recording()
    res = run_and_load(
        "plan",
        {
            "COSTMAP": cost["OUTPUT"],
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "OUTPUT": "TEMPORARY_OUTPUT",
        },
        fb,
    )
    assert res["OUTPUT"].endswith(".gpkg")  # the default vector format, and it is a GeoPackage
    path = loaded(project, "path — ")
    assert path.isValid() and path.featureCount() == 1 and path.geometryType() == 1  # a line
    assert path.crs().authid() == "EPSG:32633"  # the costmap's CRS, not WGS 84
    assert path.name() == f"path — cost {res['COST']:.4g}, {res['LENGTH_M']:.0f} m"
    assert styled_like(path, "path")
    feature = next(path.getFeatures())
    assert feature["total_cost"] == pytest.approx(res["COST"])
    assert fb.progress and max(fb.progress) == pytest.approx(100.0)
    geojson = json.loads(Path(res["GEOJSON"]).read_text())  # Export path's input
    assert geojson["features"][0]["properties"]["total_cost"] == pytest.approx(res["COST"])


@pytest.mark.parametrize("suffix", [".geojson", ".shp"])
def test_plan_writes_the_format_the_destination_asks_for(provider, project, scene, tmp_path, suffix) -> None:
    from qgis.core import QgsVectorLayer

    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(2, 60)
    out = tmp_path / f"route{suffix}"
    res = run_and_load(
        "plan",
        {
            "COSTMAP": str(scene.costmap),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "OUTPUT": str(out),
        },
    )
    assert res["OUTPUT"] == str(out)
    layer = QgsVectorLayer(str(out), "check", "ogr")
    assert layer.isValid() and layer.featureCount() == 1
    assert loaded(project, "path — ").source().split("|")[0] == str(out)


def test_run_loads_its_layers_into_one_group(provider, project) -> None:
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    res = run_and_load(
        "run",
        {
            "INPUT": str(SAMPLE / "sample.tif"),
            "PROMPT": PROMPT,
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{gx},{gy} [EPSG:32633]",
            "EVALUATE": False,
            "OUTPUT_DIR": "TEMPORARY_OUTPUT",
        },
    )
    root = project.layerTreeRoot()
    (group,) = [g for g in root.findGroups() if g.name().startswith("overseec run — Prefer the roads")]
    (costmap,) = [node.layer() for node in group.findLayers()]
    assert costmap.name().startswith("costmap — Prefer")
    routes = root.children()[0]  # the run's path: in the routes group, above every costmap
    (path,) = [node.layer() for node in routes.findLayers()]
    assert routes.customProperty("overseec/routes_group") and path.name().startswith("path — cost ")
    assert not [n for n in root.children() if n.nodeType() == n.NodeLayer]  # nothing left outside
    assert path.source().split("|")[0] == res["PATH"] and costmap.source() == res["COSTMAP"]
    assert styled_like(path, "path") and styled_like(costmap, "costmap")


def test_run_masks_arrive_as_one_layer_per_entity_in_the_group(provider, project, scene) -> None:
    """The masks/probabilities post-processor on a real run folder, through QGIS's own loader
    (what Segment and Run do with their folder): one styled layer per entity, probabilities
    hidden, costmap and masks in one group."""
    from processing.gui.Postprocessing import handleAlgorithmResults
    from qgis.core import QgsProcessingContext, QgsProcessingFeedback

    from overseec_qgis.processing.loading import load_run_layers

    context = QgsProcessingContext()
    context.setProject(project)
    load_run_layers(context, scene.folder, "prefer the road")
    assert handleAlgorithmResults(provider.algorithm("run"), context, QgsProcessingFeedback())
    (group,) = project.layerTreeRoot().findGroups()
    assert group.name() == "overseec run — prefer the road"
    nodes = group.findLayers()
    assert [n.layer().name() for n in nodes] == [
        "costmap — prefer the road",
        "road mask",
        "grass mask",
        "water mask",
        "road probability",
        "grass probability",
        "water probability",
    ]
    assert [n.isVisible() for n in nodes] == [True] * 4 + [False] * 3
    assert len(project.mapLayers()) == 7  # the multi-band layers Processing loaded were replaced


def test_plan_cancel_stops_the_worker_and_writes_nothing(provider, sample_costmap, tmp_path: Path) -> None:
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    fb = Recording()
    fb.cancel()
    with pytest.raises(QgsProcessingException, match="cancelled"):
        run(
            "plan",
            {
                "COSTMAP": str(sample_costmap),
                "START": f"{sx},{sy} [EPSG:32633]",
                "GOAL": f"{gx},{gy} [EPSG:32633]",
                "OUTPUT": str(tmp_path / "p.gpkg"),
            },
            fb,
        )
    assert not list(tmp_path.iterdir())


def test_a_prompt_matching_no_layer_fails_in_run_too(provider, tmp_path: Path) -> None:
    with pytest.raises(QgsProcessingException, match=r"compound.*matches a layer") as info:
        run(
            "run",
            {
                "INPUT": str(SAMPLE / "sample.tif"),
                "PROMPT": "avoid the compound",
                "LABELS": str(SAMPLE / "sample_labels.tif"),
                "CLASSES": str(SAMPLE / "classes.json"),
                "OUTPUT_DIR": str(tmp_path / "r"),
            },
        )
    assert "\n" not in str(info.value)
    assert not list((tmp_path / "r").glob("costmap*.tif"))


def test_costmap_needs_exactly_one_kind_of_preferences(provider, scene, tmp_path: Path) -> None:
    with pytest.raises(QgsProcessingException, match="exactly one of PROMPT, PROGRAM_TEXT or PROGRAM"):
        run("costmap", {"MASKS": str(scene.folder), "OUTPUT": str(tmp_path / "c.tif")})
    with pytest.raises(QgsProcessingException, match="exactly one of"):
        run(
            "costmap",
            {
                "MASKS": str(scene.folder),
                "PROMPT": "prefer roads",
                "PROGRAM_TEXT": "cost = 0.5",
                "OUTPUT": str(tmp_path / "c.tif"),
            },
        )
    assert not (tmp_path / "c.tif").exists()


KERNEL_FREE_SCRIPT = r"""
import json, os, sys, tempfile
from pathlib import Path
os.environ["QT_QPA_PLATFORM"] = "offscreen"
from qgis.core import QgsApplication
app = QgsApplication([], False)
app.initQgis()
from qgis.PyQt.QtCore import QCoreApplication
QCoreApplication.setOrganizationName(f"overseec-processing-tests-{os.getpid()}")  # settings of its own
sys.path.append(os.path.join(QgsApplication.pkgDataPath(), "python", "plugins"))
from processing.core.Processing import Processing
Processing.initialize()
import processing
from overseec_qgis import classFactory
plugin = classFactory(None)
plugin.initProcessing()
sample = Path(sys.argv[1])
meta = json.loads((sample / "sample.json").read_text())
(sx, sy), (gx, gy) = meta["start"], meta["goal"]
points = {"START": f"{sx},{sy} [EPSG:32633]", "GOAL": f"{gx},{gy} [EPSG:32633]"}
layers = {"LABELS": str(sample / "sample_labels.tif"), "CLASSES": str(sample / "classes.json")}
out = Path(tempfile.mkdtemp())
processing.run("overseec:interpret", {"PROMPT": meta["prompt"], "OUTPUT": "TEMPORARY_OUTPUT"})
cm = processing.run("overseec:costmap", {**layers, "PROMPT": meta["prompt"], "OUTPUT": "TEMPORARY_OUTPUT"})["OUTPUT"]
plan = processing.run("overseec:plan", {"COSTMAP": cm, **points, "OUTPUT": "TEMPORARY_OUTPUT"})
processing.run("overseec:run", {"INPUT": str(sample / "sample.tif"), "PROMPT": meta["prompt"], **layers, **points,
               "EVALUATE": False, "OUTPUT_DIR": "TEMPORARY_OUTPUT"})
processing.run("overseec:evaluate", {"COSTMAP": cm, **layers, "RANKS": "road=1,grass=2", "PAIRS": 2,
               "PLOTS": False, "OUTPUT_DIR": "TEMPORARY_OUTPUT"})
processing.run("overseec:compare", {**layers, "PROMPTS": "prefer roads\nprefer grass", **points,
               "OUTPUT_DIR": "TEMPORARY_OUTPUT"})
processing.run("overseec:exportcostmap", {"COSTMAP": cm, "FORMAT": 1, "OUTPUT": "TEMPORARY_OUTPUT"})
processing.run("overseec:exportpath", {"PATH": plan["GEOJSON"], "FORMAT": 2, "OUTPUT": "TEMPORARY_OUTPUT"})
plugin.unload()
from qgis.core import QgsSettings
Path(QgsSettings().fileName()).unlink(missing_ok=True)
heavy = ("overseec_core.plan", "overseec_core.pipeline", "torch", "matplotlib")
print(json.dumps(sorted(m for m in sys.modules if m.startswith(heavy))))
"""


@pytest.mark.slow
def test_processing_needs_no_planner_kernel_in_the_qgis_process() -> None:
    """Every non-ML algorithm, run with temporary outputs in a fresh process standing in for
    QGIS, imports neither the planner (its compiled kernel) nor the pipeline, torch or matplotlib:
    the work is the worker's, as in the pure-Python plugin zip."""
    import subprocess
    import sys

    from .conftest import REPO

    done = subprocess.run(
        [sys.executable, "-c", KERNEL_FREE_SCRIPT, str(SAMPLE)], capture_output=True, text=True, cwd=REPO, timeout=600
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []


def test_every_algorithm_is_found_by_the_words_of_its_task() -> None:
    """The Processing toolbox's search matches tags: each algorithm has "overseec" and words of
    what it does, so "route", "nav2" or "costmap" find it (issue 32 item 8)."""
    from overseec_qgis.processing.provider import OverseecProvider

    provider = OverseecProvider()
    provider.loadAlgorithms()
    algorithms = provider.algorithms()
    assert len(algorithms) >= 12
    for alg in algorithms:
        tags = alg.tags()
        assert "overseec" in tags or alg.name() == "extractimagery", alg.name()
        assert len(tags) >= 4, (alg.name(), tags)
    finds = {word: {a.name() for a in algorithms if word in a.tags()} for word in ("route", "costmap", "export")}
    assert {"plan", "run"} <= finds["route"] and "costmap" in finds["costmap"]
    assert {"exportcostmap", "exportpath"} <= finds["export"]
    plan = next(a for a in algorithms if a.name() == "plan")
    assert "temporary output is deleted" in plan.shortHelpString()
