"""The sample scene is reproducible and its truth is consistent with its pixels."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import rasterio

from overseec_core import sample
from overseec_core.io.read import read_grid


def test_same_seed_same_pixels_and_the_bundled_copy_matches(tmp_path: Path) -> None:
    bundled = sample.bundled_sample()
    assert bundled is not None, "resources/sample is missing: run overseec sample --out resources/sample"
    fresh = sample.generate(tmp_path / "s")
    for a, b in ((fresh.image, bundled.image), (fresh.labels, bundled.labels)):
        with rasterio.open(a) as x, rasterio.open(b) as y:
            np.testing.assert_array_equal(x.read(), y.read())
            assert x.crs == y.crs and x.transform == y.transform
    assert json.loads(fresh.meta.read_text()) == json.loads(bundled.meta.read_text())


def test_every_class_is_present_and_colours_follow_labels(tmp_path: Path) -> None:
    scene = sample.generate(tmp_path / "small", size=256, seed=3)
    with rasterio.open(scene.labels) as ds:
        labels = ds.read(1)
    with rasterio.open(scene.image) as ds:
        rgb = ds.read().astype(float)
    classes = {int(k): v for k, v in json.loads(scene.classes.read_text()).items()}
    assert set(np.unique(labels)) == set(classes)
    water, grass = labels == 5, labels == 1
    assert rgb[2][water].mean() > rgb[1][water].mean()  # water is blue
    assert rgb[1][grass].mean() > rgb[0][grass].mean()  # grass is green
    assert read_grid(scene.image).same_as(read_grid(scene.labels))
    meta = json.loads(scene.meta.read_text())
    assert meta["crs"] == "EPSG:32633" and len(meta["start"]) == 2
