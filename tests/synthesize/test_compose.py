"""Composition: block-wise evaluation equals whole-image evaluation exactly; layers from masks,
class rasters and vectors; the costmap, lethal sidecar and their grid, tags and nodata."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import rasterio
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rasterio.crs import CRS
from rasterio.transform import Affine, from_origin
from rasterio.windows import Window
from scipy import ndimage

from overseec_core.costlang import check_program
from overseec_core.errors import Cancelled, CostProgramError, InputError, OutputError
from overseec_core.io.grid import Grid
from overseec_core.io.write import write_array
from overseec_core.progress import NullProgress
from overseec_core.synthesize import engine as compose_module
from overseec_core.synthesize.engine import (
    MAX_WINDOW_PX,
    TAG_LETHAL,
    blocks,
    compose_array,
    compose_costmap,
    grown_block_size,
    output_paths,
    window_pixels,
)
from overseec_core.synthesize.layers import (
    ArraySource,
    CombinedSource,
    LabelSource,
    MaskDirSource,
    VectorSource,
    class_entity_name,
    load_class_entities,
)

from ..conftest import write_tif
from ..costlang.test_local_half_width import serpentine

NAMES = ("road", "grass", "building", "water")
SPATIAL_PROGRAMS = [
    'cost = normalize(distance(M["road"], 7))',
    'n = near(M["road"], 3)\ncost = where(n, 0.1, 0.9) + 0.05 * centre(M["grass"], 4)\nlethal = inside(M["water"], 1)',
    'cost = 0.5 * edge(M["road"], 6) + 0.5 * borders(M["grass"], far(M["building"], 2), 1.5)',
    'cost = normalize(distance(near(M["road"], 2), 5))',
    'a = REMOVE(M["grass"], near(M["building"], 2.5))\n'
    'cost = where(OR(M["road"], M["grass"]), sum(0.1 * P["road"], 0.6 * P["grass"] * a), 1.0)\n'
    'cost = where(near(M["building"], 4), 1.0, cost)\nlethal = M["water"]',
    'cost = 0.3 * centre(M["road"], 9) + 0.7 * normalize(distance(M["water"]))',
]


def utm_grid(width: int, height: int, px: float = 0.5, py: float = 0.5) -> Grid:
    return Grid(CRS.from_epsg(32633), Affine(px, 0, 500000.0, 0, -py, 4000000.0), width, height)


def random_layers(rng: np.random.Generator, shape, density=0.004, grow=2) -> tuple[dict, dict]:
    masks = {n: ndimage.binary_dilation(rng.random(shape) < density, iterations=grow) for n in NAMES}
    masks["road"] |= np.zeros(shape, bool)
    masks["road"][shape[0] // 2 : shape[0] // 2 + 4, :] = True  # a road leaving the image
    probs = {n: rng.random(shape).astype(np.float32) for n in NAMES}
    return masks, probs


# --------------------------------------------------------------------------------------------
# Exactness
# --------------------------------------------------------------------------------------------


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**31 - 1),
    program=st.sampled_from(SPATIAL_PROGRAMS),
    block=st.integers(16, 70),
    px=st.sampled_from([0.3, 0.5, 1.0]),
    py=st.sampled_from([0.25, 0.5, 0.7]),
    height=st.integers(20, 90),
    width=st.integers(20, 90),
)
def test_blockwise_equals_whole_image_exactly(seed, program, block, px, py, height, width):
    rng = np.random.default_rng(seed)
    masks, probs = random_layers(rng, (height, width))
    source = ArraySource(utm_grid(width, height, px, py), masks, probs)
    p = check_program(program, NAMES)
    whole_cost, whole_lethal = compose_array(p, source)
    cost, lethal = compose_array(p, source, block)
    assert np.array_equal(whole_cost, cost, equal_nan=True)
    assert np.array_equal(whole_lethal, lethal)


def test_blockwise_equals_whole_on_a_geographic_grid_with_non_square_pixels():
    grid = Grid(CRS.from_epsg(4326), Affine(2.7e-6, 0, 10.0, 0, -2.7e-6, 60.0), 83, 77)
    px, py = grid.pixel_size_m()
    assert abs(px - py) / py > 0.3  # at 60 N a degree of longitude is half as long
    masks, probs = random_layers(np.random.default_rng(3), grid.shape, density=0.01, grow=1)
    source = ArraySource(grid, masks, probs)
    for text in SPATIAL_PROGRAMS:
        p = check_program(text, NAMES)
        whole = compose_array(p, source)
        for block in (16, 31):
            part = compose_array(p, source, block)
            assert np.array_equal(whole[0], part[0], equal_nan=True) and np.array_equal(whole[1], part[1])


def test_blocks_cover_the_grid_once_with_clipped_halos():
    grid = utm_grid(50, 37)
    seen = np.zeros(grid.shape, int)
    for core, ext in blocks(grid, 16, (5, 3)):
        seen[core.toslices()] += 1
        assert ext.row_off == max(core.row_off - 5, 0) and ext.col_off == max(core.col_off - 3, 0)
        assert ext.row_off + ext.height == min(core.row_off + core.height + 5, 37)
        assert ext.col_off + ext.width == min(core.col_off + core.width + 3, 50)
    assert np.all(seen == 1)


class RecordingSource(ArraySource):
    """An ArraySource that records which layers and windows were read."""

    def __init__(self, *a, **k):
        super().__init__(*a, **k)
        object.__setattr__(self, "reads", [])

    def read(self, names, window):
        self.reads.append((tuple(names), window))
        return super().read(names, window)


def test_only_needed_layers_and_block_windows_are_read(tmp_path):
    grid = utm_grid(300, 200)
    masks, probs = random_layers(np.random.default_rng(1), grid.shape)
    source = RecordingSource(grid, masks, probs)
    p = check_program('cost = where(near(M["road"], 5), 0.1, 0.8)', NAMES)
    stats = compose_costmap(p, source, tmp_path / "costmap.tif", block_size=64)
    assert stats.halo == (11, 11)
    assert stats.blocks == len(source.reads) == 5 * 4
    for names, window in source.reads:
        assert names == ("road",)
        assert window.height <= 64 + 2 * 11 and window.width <= 64 + 2 * 11


# --------------------------------------------------------------------------------------------
# Files: masks directory, costmap, sidecar
# --------------------------------------------------------------------------------------------


def write_mask_dir(d: Path, grid: Grid, masks: dict, probs: dict | None, prefix: str = "", mask_nodata=None) -> Path:
    d.mkdir(parents=True, exist_ok=True)
    names = list(masks)
    m = np.stack([masks[n] for n in names]).astype(np.uint8)
    write_array(d / f"{prefix}masks.tif", m, grid, nodata=mask_nodata, descriptions=names)
    if probs is not None:
        p = np.stack([probs[n] for n in names]).astype(np.float32)
        write_array(d / f"{prefix}probs.tif", p, grid, descriptions=names)
    return d


def test_compose_from_a_mask_dir_writes_costmap_and_lethal_on_the_exact_grid(tmp_path):
    grid = utm_grid(140, 90, 0.5, 0.3)
    masks, probs = random_layers(np.random.default_rng(5), grid.shape)
    d = write_mask_dir(tmp_path / "run", grid, masks, probs)
    text = SPATIAL_PROGRAMS[4]
    p = check_program(text, NAMES)
    source = MaskDirSource(d)
    out = tmp_path / "out" / "costmap.tif"
    out.parent.mkdir()
    stats = compose_costmap(p, source, out, block_size=32, tags={"X": "1"})
    assert stats.lethal_path == out.with_name("lethal.tif")
    expected_cost, expected_lethal = compose_array(p, ArraySource(grid, masks, probs))
    with rasterio.open(out) as ds:
        assert (ds.count, ds.dtypes[0], ds.descriptions) == (1, "float32", ("cost",))
        assert ds.crs == grid.crs and ds.transform == grid.transform
        assert (ds.width, ds.height) == (grid.width, grid.height)
        assert np.isnan(ds.nodata)
        assert ds.tags()[TAG_LETHAL] == "lethal.tif" and ds.tags()["X"] == "1"
        cost = ds.read(1)
    with rasterio.open(stats.lethal_path) as ds:
        assert ds.dtypes[0] == "uint8" and ds.transform == grid.transform
        lethal = ds.read(1)
    assert np.array_equal(cost, expected_cost, equal_nan=True)
    assert np.array_equal(lethal, expected_lethal)
    assert set(np.unique(lethal)) <= {0, 1} and lethal.sum() == masks["water"].sum()
    assert 0.0 <= np.nanmin(cost) and np.nanmax(cost) <= 1.0
    assert stats.valid_pixels == grid.width * grid.height
    assert stats.mean_cost == pytest.approx(float(expected_cost.mean()), rel=1e-5)
    assert [p.name for p in out.parent.iterdir() if p.name.startswith(".")] == []


def test_refined_layers_are_preferred_and_integer_probabilities_are_scaled(tmp_path):
    grid = utm_grid(20, 10)
    road = np.zeros(grid.shape, bool)
    road[:, :5] = True
    d = write_mask_dir(tmp_path, grid, {"road": road}, {"road": np.full(grid.shape, 0.2)})
    write_array(d / "refined_masks.tif", road[None].astype(np.uint8), grid, descriptions=["road"])
    write_array(d / "refined_probs.tif", np.full((1, *grid.shape), 255, np.uint8), grid, descriptions=["road"])
    source = MaskDirSource(d)
    assert source.mask_path.name == "refined_masks.tif"
    cost, _ = compose_array(check_program('cost = P["road"]', ["road"]), source)
    assert np.all(cost[:, :5] == 1.0) and np.all(cost[:, 5:] == 0.0)


def test_mask_nodata_and_nan_probabilities_are_nan_cost_and_lethal(tmp_path):
    grid = utm_grid(12, 8)
    road = np.zeros(grid.shape, np.uint8)
    road[2, :] = 1
    road[0, 0] = 255  # nodata
    prob = np.full(grid.shape, 0.5, np.float32)
    prob[4, 4] = np.nan
    d = tmp_path / "run"
    d.mkdir()
    write_array(d / "masks.tif", road[None], grid, nodata=255, descriptions=["road"])
    write_array(d / "probs.tif", prob[None], grid, descriptions=["road"])
    cost, lethal = compose_array(check_program('cost = 0.2 + 0.5 * P["road"]', ["road"]), MaskDirSource(d))
    assert np.isnan(cost[0, 0]) and np.isnan(cost[4, 4])
    assert lethal[0, 0] == 1 and lethal[4, 4] == 1 and lethal.sum() == 2
    assert cost[2, 3] == pytest.approx(0.45) and cost[1, 1] == pytest.approx(0.2)


def test_mask_dir_errors_are_one_line(tmp_path):
    with pytest.raises(InputError, match="no masks.tif"):
        MaskDirSource(tmp_path)
    with pytest.raises(InputError, match="not a directory"):
        MaskDirSource(tmp_path / "nope")
    write_tif(tmp_path / "masks.tif", np.zeros((2, 4, 4), np.uint8))
    with pytest.raises(InputError, match="no description"):
        MaskDirSource(tmp_path)


def test_output_paths_and_overwrite_protection(tmp_path):
    assert [p.name for p in output_paths(tmp_path / "costmap.tif")] == [
        "costmap.tif",
        "lethal.tif",
        "costmap.program.txt",
    ]
    assert [p.name for p in output_paths(tmp_path / "v2.tif")] == ["v2.tif", "v2.lethal.tif", "v2.program.txt"]
    with pytest.raises(InputError, match=".tif"):
        output_paths(tmp_path / "costmap.png")
    grid = utm_grid(10, 10)
    d = write_mask_dir(tmp_path / "run", grid, {"road": np.ones(grid.shape, bool)}, None)
    p = check_program("cost = 0.5", ["road"])
    with pytest.raises(OutputError, match="is the input"):
        compose_costmap(p, MaskDirSource(d), d / "masks.tif")


def test_missing_entities_and_oversized_halos_are_refused(tmp_path):
    grid = utm_grid(10, 10, 0.05, 0.05)
    source = ArraySource(grid, {"road": np.ones(grid.shape, bool)})
    with pytest.raises(InputError, match="'grass'"):
        compose_costmap(check_program('cost = 1.0 * M["grass"]', ["road", "grass"]), source, tmp_path / "c.tif")
    with pytest.raises(CostProgramError, match="pixels") as info:
        compose_costmap(check_program('x = 0.5\ncost = distance(M["road"], 400)', ["road"]), source, tmp_path / "c.tif")
    assert info.value.line == 2
    assert not (tmp_path / "c.tif").exists()


def test_cancel_leaves_no_output(tmp_path):
    grid = utm_grid(64, 64)
    source = ArraySource(grid, {"road": np.ones(grid.shape, bool)})
    progress = NullProgress()
    progress.token.cancel()
    with pytest.raises(Cancelled):
        compose_costmap(
            check_program("cost = 0.5", ["road"]), source, tmp_path / "costmap.tif", block_size=16, progress=progress
        )
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------------
# Class rasters and vectors
# --------------------------------------------------------------------------------------------


def test_class_names_become_entity_names():
    assert class_entity_name("water (Hydro)") == "water"
    assert class_entity_name("Railway (Train)") == "railway"
    assert class_entity_name("  Baseball   Field ") == "baseball field"


def test_label_source_masks_classes_and_skips_background(tmp_path):
    classes = tmp_path / "classes.json"
    classes.write_text(json.dumps({"0": "unlabeled", "1": "Road", "2": "grass", "3": "Grass (mown)"}))
    labels = np.array([[0, 1, 2, 3], [1, 1, 0, 2]], np.uint8)
    write_tif(tmp_path / "gt.tif", labels, nodata=None)
    source = LabelSource(tmp_path / "gt.tif", classes)
    assert source.names == ("road", "grass")
    block = source.read(["road", "grass"], Window(0, 0, 4, 2))
    assert np.array_equal(block.masks["road"], labels == 1)
    assert np.array_equal(block.masks["grass"], (labels == 2) | (labels == 3))
    assert block.probs == {} and block.valid.all()


def test_a_class_id_that_is_the_rasters_nodata_is_reported_as_nodata_not_missing(tmp_path):
    from overseec_core.io.inputs import check_class_raster

    labels = np.array([[0, 1, 2], [2, 1, 0]], np.uint8)
    write_tif(tmp_path / "gt.tif", labels, nodata=0)
    warnings = check_class_raster(tmp_path / "gt.tif", [0, 1, 2, 3])
    assert any("class id 0 of classes.json is the raster's nodata value" in w for w in warnings)
    missing = [w for w in warnings if "do not occur" in w]
    assert len(missing) == 1 and "class id(s) 3 of" in missing[0]  # 0 is nodata, not missing
    write_tif(tmp_path / "gt2.tif", labels, nodata=None)
    assert check_class_raster(tmp_path / "gt2.tif", [0, 1, 2]) == []


@pytest.mark.parametrize(
    "content, fragment",
    [
        ("[1, 2]", "expected an object"),
        ("{}", "expected an object"),
        ('{"a": "road"}', "not an integer"),
        ('{"1": ""}', "has no name"),
        ('{"0": "background"}', "only background"),
        ("not json", r"not JSON \(Expecting value at line 1\)"),
    ],
)
def test_bad_classes_json_is_a_one_line_input_error(tmp_path, content, fragment):
    path = tmp_path / "classes.json"
    path.write_text(content)
    with pytest.raises(InputError, match=fragment):
        load_class_entities(path)


def write_vectors(path: Path, crs: str, features: list[dict], layer_schema: dict) -> Path:
    import fiona

    with fiona.open(path, "w", driver="GPKG", crs=crs, schema=layer_schema) as dst:
        for f in features:
            dst.write(f)
    return path


def test_vectors_are_reprojected_and_rasterised_per_window(tmp_path):
    from pyproj import Transformer

    grid = Grid(CRS.from_epsg(32633), from_origin(500000.0, 4000100.0, 1.0, 1.0), 100, 100)
    to_ll = Transformer.from_crs(32633, 4326, always_xy=True)
    # a horizontal line along row 50 (y = 4000049.5) from x = 500010.5 to 500089.5, in WGS 84
    a = to_ll.transform(500010.5, 4000049.5)
    b = to_ll.transform(500089.5, 4000049.5)
    path = write_vectors(
        tmp_path / "roads.gpkg",
        "EPSG:4326",
        [{"geometry": {"type": "LineString", "coordinates": [a, b]}, "properties": {}}],
        {"geometry": "LineString", "properties": {}},
    )
    source = VectorSource({"road": path}, grid)
    cost, _ = compose_array(check_program('cost = 1.0 * M["road"]', ["road"]), source, 32)
    rows, cols = np.nonzero(cost)
    assert set(rows) == {50} and cols.min() == 10 and cols.max() == 89
    wide = VectorSource({"road": path}, grid, line_width_m=6.0)
    cost, _ = compose_array(check_program('cost = 1.0 * M["road"]', ["road"]), wide, 32)
    assert set(np.nonzero(cost[:, 50])[0]) == set(range(47, 53))


def test_polygons_burn_by_pixel_centre(tmp_path):
    grid = Grid(CRS.from_epsg(32633), from_origin(500000.0, 4000010.0, 1.0, 1.0), 10, 10)
    ring = [
        (500002.0, 4000008.0),
        (500005.0, 4000008.0),
        (500005.0, 4000004.0),
        (500002.0, 4000004.0),
        (500002.0, 4000008.0),
    ]
    path = write_vectors(
        tmp_path / "b.gpkg",
        "EPSG:32633",
        [{"geometry": {"type": "Polygon", "coordinates": [ring]}, "properties": {}}],
        {"geometry": "Polygon", "properties": {}},
    )
    block = VectorSource({"building": path}, grid).read(["building"], Window(0, 0, 10, 10))
    expected = np.zeros((10, 10), bool)
    expected[2:6, 2:5] = True
    assert np.array_equal(block.masks["building"], expected)


def test_vector_errors(tmp_path):
    grid = utm_grid(10, 10)
    with pytest.raises(InputError, match="no such file"):
        VectorSource({"road": tmp_path / "none.gpkg"}, grid)
    bad = tmp_path / "bad.gpkg"
    bad.write_text("nonsense")
    with pytest.raises(InputError, match="not a readable vector layer"):
        VectorSource({"road": bad}, grid)


def test_combined_sources_union_entities_and_require_one_grid(tmp_path):
    grid = utm_grid(6, 4)
    a = np.zeros(grid.shape, bool)
    a[0] = True
    b = np.zeros(grid.shape, bool)
    b[3] = True
    s1 = ArraySource(grid, {"road": a, "grass": ~a}, {"road": np.full(grid.shape, 0.4)})
    s2 = ArraySource(grid, {"road": b, "water": b})
    combined = CombinedSource([s1, s2])
    assert combined.names == ("road", "grass", "water")
    block = combined.read(["road", "grass", "water"], Window(0, 0, 6, 4))
    assert np.array_equal(block.masks["road"], a | b)
    assert block.probs["road"][0, 0] == pytest.approx(0.4) and block.probs["road"][3, 0] == 1.0
    other = ArraySource(utm_grid(6, 5), {"x": np.zeros((5, 6), bool)})
    with pytest.raises(InputError, match="grid"):
        CombinedSource([s1, other])
    with pytest.raises(InputError, match="no entity layers"):
        CombinedSource([])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=st.deferred(lambda: _valid_programs()), seed=st.integers(0, 2**31 - 1), block=st.integers(16, 40))
def test_random_well_typed_programs_are_blockwise_exact(text, seed, block):
    rng = np.random.default_rng(seed)
    masks, probs = random_layers(rng, (45, 57))
    source = ArraySource(utm_grid(57, 45, 0.6, 0.4), masks, probs)
    p = check_program(text, NAMES)
    whole = compose_array(p, source)
    part = compose_array(p, source, block)
    assert np.array_equal(whole[0], part[0], equal_nan=True) and np.array_equal(whole[1], part[1])


def _valid_programs():
    from ..costlang.test_fuzz import valid_programs

    return valid_programs()


# --------------------------------------------------------------------------------------------
# Wide halos and cancelling inside a block (issue 13)
# --------------------------------------------------------------------------------------------


class RecordingProgress(NullProgress):
    """NullProgress that keeps its messages."""

    def __init__(self) -> None:
        super().__init__()
        self.messages: list[str] = []

    def message(self, text: str) -> None:
        self.messages.append(text)


def test_blocks_grow_to_amortise_a_wide_halo_and_the_result_is_the_same(tmp_path):
    rng = np.random.default_rng(3)
    grid = utm_grid(200, 150)
    masks, probs = random_layers(rng, grid.shape)
    source = ArraySource(grid, masks, probs)
    program = check_program('cost = 0.5 * normalize(distance(M["road"], 40)) + 0.5 * centre(M["grass"], 6)', NAMES)
    progress = RecordingProgress()
    stats = compose_costmap(program, source, tmp_path / "costmap.tif", block_size=32, progress=progress)
    assert stats.halo == (82, 82) and stats.block_size == 192 and stats.blocks == 2
    assert progress.messages == []  # 2 blocks read the image twice: nothing to say
    with rasterio.open(tmp_path / "costmap.tif") as ds:
        written = ds.read(1)
    expected, _ = compose_array(program, source)
    assert np.array_equal(written, expected)


def test_compose_says_up_front_when_the_halo_multiplies_the_pixels_read(tmp_path, monkeypatch):
    monkeypatch.setattr(compose_module, "MAX_WINDOW_PX", 0)  # blocks may not grow
    grid = utm_grid(200, 150)
    source = ArraySource(grid, {"road": np.eye(150, 200, dtype=bool)})
    progress = RecordingProgress()
    stats = compose_costmap(
        check_program('cost = normalize(distance(M["road"], 40))', ["road"]),
        source,
        tmp_path / "costmap.tif",
        block_size=32,
        progress=progress,
    )
    assert stats.block_size == 32
    assert len(progress.messages) == 1 and "40 m (81 pixels)" in progress.messages[0]


def test_grown_blocks_keep_windows_within_the_budget():
    big = utm_grid(20000, 20000, 0.075, 0.075)
    assert grown_block_size(1024, (2012, 2012), big) == 1024  # window already at the budget
    assert window_pixels(1024, (2012, 2012), big) <= MAX_WINDOW_PX
    assert grown_block_size(1024, (700, 700), big) == 2048
    assert window_pixels(2048, (700, 700), big) <= MAX_WINDOW_PX
    assert grown_block_size(1024, (2012, 2012), utm_grid(3072, 2048, 0.075, 0.075)) == 3072
    assert grown_block_size(64, (11, 11), big) == 64  # a narrow halo: as asked


def test_a_cancel_inside_a_long_block_operation_is_honoured_within_a_second(tmp_path):
    # One 1500 x 1500 block whose centre() must run hundreds of dilation steps (a long winding
    # corridor fed by a wide blob); before issue 13 a cancel waited for the block to finish.
    grid = utm_grid(1500, 1500, 0.1, 0.1)
    source = ArraySource(grid, {"road": serpentine(1500, 1500, blob=200)})
    program = check_program('cost = centre(M["road"], 150)', ["road"])
    progress = NullProgress()
    outcome: dict[str, object] = {}

    def run() -> None:
        try:
            compose_costmap(program, source, tmp_path / "costmap.tif", progress=progress)
            outcome["result"] = "finished"
        except Cancelled:
            outcome["result"] = "cancelled"
        outcome["at"] = time.monotonic()

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    time.sleep(0.5)
    assert thread.is_alive()
    cancelled_at = time.monotonic()
    progress.token.cancel()
    thread.join(timeout=10)
    assert outcome.get("result") == "cancelled"
    assert outcome["at"] - cancelled_at < 1.5
    assert list(tmp_path.iterdir()) == []
