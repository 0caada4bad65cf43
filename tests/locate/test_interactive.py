"""Click to fix a mask (locate/interactive.py) with a tiny random-weight SAM.

The answers are checked against the library's own pipeline (SamProcessor on the view's pixels and
prompts, a plain SamModel forward with the encoder inside, post_process_masks); the encoder runs
once per view; apply changes only the entity's band inside the view, in every file of the pair,
atomically, with a manifest record; and `overseec costmap --masks` sees the edit.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.windows import Window

pytest.importorskip("torch")

import torch

from overseec_core.cli import main
from overseec_core.errors import InputError, ModelError
from overseec_core.io.grid import Grid
from overseec_core.io.write import write_array
from overseec_core.locate.interactive import (
    MANIFEST_SECTION,
    FixSession,
    Prompt,
    combine,
    mask_outline,
    mask_polygons,
    view_window,
)

from .conftest import write_geotiff

ENTITIES = ("road", "water")
#: The view: image columns 40..136, rows 30..110 (SAM's 128 px input sees it upscaled to 128 x 107).
COLS, ROWS = (40, 136), (30, 110)
PROGRAM = 'cost = where(M["water"], 1.0, 0.2)\nlethal = M["water"]\n'


def pixel_xy(transform, col: float, row: float) -> tuple[float, float]:
    """Map coordinates of an image pixel's centre."""
    x, y = transform * (col + 0.5, row + 0.5)
    return float(x), float(y)


def write_segment_dir(folder: Path, image: Path, refined: bool = False) -> Path:
    """masks.tif/probs.tif (or the refined pair and gated.tif) on the image's grid: a road band
    along rows 60..70, water in the lower right; the image's nodata corner is mask nodata."""
    with rasterio.open(image) as ds:
        grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
        alpha = ds.read(4)
    folder.mkdir(parents=True, exist_ok=True)
    road = np.zeros(grid.shape, bool)
    road[60:70, :] = True
    water = np.zeros(grid.shape, bool)
    water[100:, 120:] = True
    masks = np.stack([road, water]).astype(np.uint8)
    masks[:, alpha == 0] = 255
    probs = np.where(masks == 1, 0.9, 0.2).astype(np.float32)
    probs[:, alpha == 0] = np.nan
    names = ("refined_masks.tif", "refined_probs.tif") if refined else ("masks.tif", "probs.tif")
    write_array(folder / names[0], masks, grid, nodata=255, descriptions=ENTITIES)
    write_array(folder / names[1], probs, grid, nodata=float("nan"), descriptions=ENTITIES)
    if refined:
        gated = np.where(masks == 1, probs, 0.0).astype(np.float32)
        write_array(folder / "gated.tif", gated, grid, nodata=float("nan"), descriptions=ENTITIES)
    return folder


@pytest.fixture
def scene(tmp_path: Path):
    image = write_geotiff(tmp_path / "image.tif", 200, 150, nodata_box=(30, 45, 40, 60))
    folder = write_segment_dir(tmp_path / "seg", image)
    with rasterio.open(image) as ds:
        transform = ds.transform
    (x0, y1), (x1, y0) = transform * (COLS[0], ROWS[0]), transform * (COLS[1], ROWS[1])
    return image, folder, transform, (x0, y0, x1, y1)


@pytest.fixture
def session(scene, tiny_sam) -> FixSession:
    image, folder, _t, bounds = scene
    return FixSession(image, folder, bounds, model=str(tiny_sam), device="cpu")


def read_all(path: Path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read()


# -- parity with the library ----------------------------------------------------------------------


def library_probability(tiny_sam: Path, rgb: np.ndarray, points, labels, box) -> tuple[np.ndarray, float]:
    """The library's own pipeline on the view: SamProcessor (resize, normalise, pad, prompt
    scaling), SamModel's full forward (encoder included), post_process_masks -> probabilities."""
    from transformers import SamModel, SamProcessor

    proc = SamProcessor.from_pretrained(tiny_sam)
    model = SamModel.from_pretrained(tiny_sam).eval()
    kwargs = {}
    if points:
        kwargs.update(input_points=[[list(map(float, p)) for p in points]], input_labels=[list(labels)])
    if box is not None:
        kwargs["input_boxes"] = [[list(map(float, box))]]
    enc = proc(images=rgb, return_tensors="pt", **kwargs)
    multimask = box is None and len(points) == 1
    with torch.no_grad():
        out = model(
            pixel_values=enc["pixel_values"],
            input_points=enc.get("input_points"),
            input_labels=enc.get("input_labels"),
            input_boxes=enc.get("input_boxes"),
            multimask_output=multimask,
        )
    best = int(torch.argmax(out.iou_scores[0, 0]))
    logits = proc.post_process_masks(
        [out.pred_masks[0, :, best : best + 1]], enc["original_sizes"], enc["reshaped_input_sizes"], binarize=False
    )[0][0, 0]
    return torch.sigmoid(logits).numpy(), float(out.iou_scores[0, 0, best])


PROMPTS = {
    # (view col, view row) pixel indices of points, labels, and a box as pixel edges (c0, r0, c1, r1)
    "one include point": ([(30, 35)], [1], None),
    "include and exclude": ([(30, 35), (70, 20), (10, 60)], [1, 0, 1], None),
    "box": ([], [], (20, 25, 60, 50)),
    "box and points": ([(40, 40), (22, 27)], [1, 0], (20, 25, 60, 50)),
}


@pytest.mark.parametrize("name", list(PROMPTS))
def test_answers_equal_the_library_pipeline(session, scene, tiny_sam, name) -> None:
    image, _f, transform, _b = scene
    points, labels, box = PROMPTS[name]
    c0, r0 = COLS[0], ROWS[0]
    prompt = Prompt(
        points=tuple(pixel_xy(transform, c0 + c, r0 + r) for c, r in points),
        labels=tuple(labels),
        box=None if box is None else (*transform * (c0 + box[0], r0 + box[3]), *transform * (c0 + box[2], r0 + box[1])),
    )
    answer = session.prompt("road", prompt)
    with rasterio.open(image) as ds:
        win = Window(c0, r0, COLS[1] - c0, ROWS[1] - r0)
        rgb = np.moveaxis(ds.read((1, 2, 3), window=win), 0, -1)
        valid = ds.read(4, window=win) > 0
    rgb[~valid] = 0  # RasterSource zeroes pixels without data, the library sees the same image
    # SAM takes pixel indices: a point at a pixel's centre is that index; box corners (edges) - 0.5
    lib_box = None if box is None else [v - 0.5 for v in box]
    expected, score = library_probability(tiny_sam, rgb, points, labels, lib_box)
    assert answer.probability.shape == expected.shape == (80, 96)
    np.testing.assert_allclose(answer.probability, expected, atol=2e-5)
    assert answer.score == pytest.approx(score, abs=1e-5)
    assert 0 < answer.candidate.sum() < answer.candidate.size or name == "box"  # a mask that varies
    assert not answer.candidate[~session.valid].any()  # no mask where the image has no data


# -- one embedding per view --------------------------------------------------------------------------


def test_the_encoder_runs_once_per_view(scene, tiny_sam) -> None:
    image, folder, transform, bounds = scene
    calls = []
    first = FixSession(image, folder, bounds, model=str(tiny_sam), device="cpu")
    hook = first.bundle.model.vision_encoder.register_forward_hook(lambda *_: calls.append(1))
    try:
        for k in range(5):
            first.prompt("road", Prompt((pixel_xy(transform, 50 + 5 * k, 40 + 3 * k),), (1,)))
        first.prompt("water", Prompt(box=(*transform * (60, 100), *transform * (130, 40))), "replace")
        assert calls == [] and first.encoder_calls == 1 and first.embed_ms > 0
        second = FixSession(image, folder, (bounds[0] + 10, bounds[1], bounds[2], bounds[3]), str(tiny_sam), "cpu")
        assert calls == [1] and second.encoder_calls == 1
        assert second.bundle is first.bundle  # the model itself is loaded once per process
    finally:
        hook.remove()


# -- editing and applying ------------------------------------------------------------------------------


def test_combine_modes_only_touch_editable_pixels() -> None:
    existing = np.array([[1, 1, 0, 0]], bool)
    candidate = np.array([[1, 0, 1, 0]], bool)
    editable = np.array([[1, 1, 1, 0]], bool)
    assert combine(existing, candidate, editable, "add").tolist() == [[1, 1, 1, 0]]
    assert combine(existing, candidate, editable, "remove").tolist() == [[0, 1, 0, 0]]
    assert combine(existing, candidate, editable, "replace").tolist() == [[1, 0, 1, 0]]
    assert combine(existing, ~candidate, np.zeros_like(editable), "replace").tolist() == existing.tolist()
    with pytest.raises(InputError, match="unknown mode"):
        combine(existing, candidate, editable, "xor")


def test_apply_writes_only_the_entitys_band_inside_the_view(session, scene) -> None:
    _image, folder, transform, _b = scene
    before = {n: read_all(folder / n) for n in ("masks.tif", "probs.tif")}
    prompt = Prompt(box=(*transform * (COLS[0] + 5, ROWS[0] + 70), *transform * (COLS[0] + 80, ROWS[0] + 5)))
    answer = session.prompt("road", prompt, "replace")
    assert answer.added.any() and answer.removed.any()
    record = session.apply("road", prompt, "replace")
    after = {n: read_all(folder / n) for n in ("masks.tif", "probs.tif")}
    inside = (slice(ROWS[0], ROWS[1]), slice(COLS[0], COLS[1]))
    for name in before:
        changed = before[name] != after[name]
        changed &= ~(np.isnan(before[name]) & np.isnan(after[name])) if name == "probs.tif" else changed
        assert not changed[1].any()  # water untouched
        outside = changed[0].copy()
        outside[inside] = False
        assert not outside.any()  # nothing outside the view
    road = after["masks.tif"][0][inside]
    nodata = before["masks.tif"][0][inside] == 255
    assert (road[nodata] == 255).all()  # the image's nodata stays the mask's nodata
    assert np.array_equal(road[~nodata] == 1, answer.mask[~nodata])
    probs = after["probs.tif"][0][inside]
    assert np.allclose(probs[answer.added], answer.probability[answer.added])
    assert (probs[answer.removed] == 0).all() and (probs[answer.added] >= 0.5).all()
    edits = json.loads((folder / "manifest.json").read_text())[MANIFEST_SECTION]
    assert edits == {record.pop("edit"): record}
    assert record["pixels_added"] == answer.added.sum() and record["files"] == ["masks.tif", "probs.tif"]
    assert record["view"]["window"] == [COLS[0], ROWS[0], 96, 80] and record["prompt"]["box"] is not None
    assert sorted(p.name for p in folder.iterdir()) == ["manifest.json", "masks.tif", "probs.tif"]
    # the session reads the new file: the same prompt again changes nothing
    again = session.prompt("road", prompt, "replace")
    assert not again.added.any() and not again.removed.any()


def test_apply_to_refined_masks_keeps_mask_equal_to_probs_over_half(scene, tiny_sam, tmp_path) -> None:
    image, _f, transform, bounds = scene
    folder = write_segment_dir(tmp_path / "refined", image, refined=True)
    session = FixSession(image, folder, bounds, model=str(tiny_sam), device="cpu")
    prompt = Prompt((pixel_xy(transform, 70, 50), pixel_xy(transform, 100, 65)), (1, 0))
    record = session.apply("road", prompt, "add")
    assert record["files"] == ["refined_masks.tif", "refined_probs.tif", "gated.tif"]
    masks, probs, gated = (read_all(folder / n)[0] for n in record["files"])
    data = masks != 255
    assert np.array_equal(masks[data] == 1, probs[data] >= 0.5)
    assert np.allclose(gated[data], np.where(masks[data] == 1, probs[data], 0.0))


def test_a_failed_apply_leaves_every_file_as_it_was(session, scene, monkeypatch) -> None:
    import overseec_core.locate.interactive as interactive

    _image, folder, transform, _b = scene
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    real = interactive.write_window

    def failing(path, *args):
        if path.name == "probs.tif":  # the mask was already replaced: the transaction undoes it
            raise interactive.OutputError(f"cannot update {path}: disk full")
        return real(path, *args)

    monkeypatch.setattr(interactive, "write_window", failing)
    with pytest.raises(interactive.OutputError, match="disk full"):
        session.apply("road", Prompt((pixel_xy(transform, 70, 50),), (1,)), "replace")
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


def test_the_costmap_rebuilt_from_the_folder_sees_the_edit(session, scene, tmp_path, capsys) -> None:
    _image, folder, transform, _b = scene
    program = tmp_path / "p.txt"
    program.write_text(PROGRAM)

    def costmap(name: str) -> np.ndarray:
        out = tmp_path / name
        assert main(["-q", "costmap", "--masks", str(folder), "--program", str(program), "--out", str(out)]) == 0
        return read_all(out)[0]

    before = costmap("before.tif")
    prompt = Prompt(box=(*transform * (COLS[0] + 10, ROWS[0] + 60), *transform * (COLS[0] + 60, ROWS[0] + 10)))
    answer = session.prompt("water", prompt, "add")
    assert answer.added.any()
    session.apply("water", prompt, "add")
    after = costmap("after.tif")
    inside = (slice(ROWS[0], ROWS[1]), slice(COLS[0], COLS[1]))
    expected = before.copy()
    expected[inside][answer.added] = 1.0
    np.testing.assert_array_equal(np.nan_to_num(after, nan=-1), np.nan_to_num(expected, nan=-1))


# -- polygons, views and errors ---------------------------------------------------------------------


def test_polygons_outline_the_mask_in_map_coordinates(session) -> None:
    mask = np.zeros((80, 96), bool)
    mask[10:20, 5:25] = True
    mask[40:42, 50:51] = True
    polys, truncated = mask_polygons(mask, session.view.transform)
    assert not truncated and len(polys) == 2
    t = session.view.transform
    outer = np.array(polys[0][0])
    assert outer[:, 0].min() == pytest.approx((t * (5, 0))[0]) and outer[:, 0].max() == pytest.approx((t * (25, 0))[0])
    assert mask_polygons(mask, t, max_vertices=6)[1] is True


def test_a_speckled_mask_is_outlined_at_a_coarser_scale_within_the_budget(session) -> None:
    t = session.view.transform
    smooth = np.zeros((80, 96), bool)
    smooth[10:60, 20:70] = True
    polys, _truncated, scale = mask_outline(smooth, t, max_edges=500)
    assert scale == 1 and polys == mask_polygons(smooth, t)[0]
    speckled = np.random.default_rng(0).random((80, 96)) < 0.5
    polys, truncated, scale = mask_outline(speckled, t, max_edges=500)
    assert scale > 1 and not truncated
    edges = sum(len(ring) - 1 for p in polys for ring in p)
    assert edges <= 500  # each vertex of a pixel outline ends one edge
    cells = sum(abs(_shoelace(p[0])) - sum(abs(_shoelace(r)) for r in p[1:]) for p in polys) / abs(t.a * t.e)
    assert cells % (scale * scale) == 0  # whole cells of scale x scale image pixels


def _shoelace(ring) -> float:
    xy = np.asarray(ring)
    return 0.5 * float(np.dot(xy[:-1, 0], xy[1:, 1]) - np.dot(xy[1:, 0], xy[:-1, 1]))


def test_views_and_prompts_refuse_what_they_cannot_do(scene, session, tiny_sam) -> None:
    image, folder, transform, bounds = scene
    with rasterio.open(image) as ds:
        grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
    assert view_window(grid, bounds) == Window(COLS[0], ROWS[0], 96, 80)
    far = (bounds[0] + 1e5, bounds[1], bounds[2] + 1e5, bounds[3])
    with pytest.raises(InputError, match="does not overlap"):
        view_window(grid, far)
    # finite bounds far past any map: clipped to the image first, no overflow (issue 33 rule 4)
    assert view_window(grid, (-1e308, -1e308, 1e308, 1e308), max_px=10_000) == Window(0, 0, grid.width, grid.height)
    with pytest.raises(InputError, match="zoom in to at most 64 px"):
        view_window(grid, bounds, max_px=64)
    with pytest.raises(InputError, match="no entity 'tree'.*road, water"):
        session.prompt("tree", Prompt((pixel_xy(transform, 50, 40),), (1,)))
    with pytest.raises(InputError, match="outside the view"):
        session.prompt("road", Prompt((pixel_xy(transform, 5, 5),), (1,)))
    with pytest.raises(InputError, match="at least one point or a box"):
        session.prompt("road", Prompt())
    with pytest.raises(InputError, match="unknown mode"):
        session.prompt("road", Prompt((pixel_xy(transform, 50, 40),), (1,)), "xor")
    with pytest.raises(ModelError, match="no-such-sam"):
        FixSession(image, folder, bounds, model=str(folder / "no-such-sam"), device="cpu")
