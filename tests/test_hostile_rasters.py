"""Raster inputs are checked alike (issue 33 rule 1), one table across every command and role.

Each raster role a command reads -- a costmap to plan, corridor, export or vectorize on, a class
raster, a DEM, a lethal sidecar -- is given what that role cannot be: too many bands (a photo), the
wrong kind of numbers (a class raster as costs, costs as class ids), a raster far over the pixel
budget (a 2,000,000² VRT that costs nothing to make), and for the sidecar one on another grid.
Each case runs the real console script and must end with exit 2 and one ``overseec: error:`` line
saying what the role needs, with no traceback and no file changed or added, before any pixel
of a budget-breaking raster is read (the run is given 20 s).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.limits import max_pixels
from tests import test_hostile
from tests.test_hostile import LABELS, POINTS
from tests.test_hostile_text_inputs import _argv, _refused

scene_template = test_hostile.scene_template
scene = test_hostile.scene

COSTMAP = "{f}"
#: (role, argv with {f} where the hostile raster goes).
ROLES = {
    "plan: costmap": ("plan", COSTMAP, *POINTS, "--out", "o/p.geojson"),
    "plan --pairs: costmap": ("plan", COSTMAP, "--pairs", "pairs.csv", "--out", "o/r.gpkg"),
    "corridor: costmap": ("corridor", COSTMAP, *POINTS, "--within", "10", "--out", "o/c.tif"),
    "export nav2: costmap": ("export", "costmap", COSTMAP, "--to", "nav2", "--out", "o/map.yaml"),
    "costmap --labels": (
        "costmap",
        "--labels",
        "{f}",
        "--classes",
        "classes.json",
        "--prompt",
        "prefer roads",
        "--out",
        "o/c.tif",
    ),
    "vectorize: class raster": ("vectorize", "--labels", "{f}", "--classes", "classes.json", "--out", "o/v.gpkg"),
    "plan --dem": ("plan", "c/costmap.tif", *POINTS, "--dem", "{f}", "--out", "o/p.geojson"),
    "costmap --dem": ("costmap", *LABELS, "--prompt", "avoid steep slopes", "--dem", "{f}", "--out", "o/c.tif"),
}
#: The roles by kind: what each kind refuses.
COSTMAP_ROLES = [r for r in ROLES if r.endswith(": costmap")]
CLASS_ROLES = ["costmap --labels", "vectorize: class raster"]
DEM_ROLES = ["plan --dem", "costmap --dem"]


def _pairs(scene: Path) -> None:
    (scene / "pairs.csv").write_text(
        "start_x,start_y,goal_x,goal_y\n" + ",".join(str(v) for v in (*POINTS[1:3], *POINTS[4:6])) + "\n"
    )


@pytest.mark.parametrize("role", list(ROLES))
def test_a_raster_over_the_pixel_budget_is_refused_before_it_is_read(scene: Path, role: str) -> None:
    _pairs(scene)
    # of the role's own kind, so only its size is wrong: float costs or elevations, integer classes
    huge = "huge_labels.vrt"
    if role not in CLASS_ROLES:
        huge = "c/huge_costs.vrt"
        test_hostile._huge_vrt(scene / huge, scene / "c" / "costmap.tif", 2_000_000, "Float32")
    with rasterio.open(scene / huge) as ds:  # the premise: only its size breaks the role's rules
        assert ds.width * ds.height > max_pixels() and ds.count == 1
    _refused(scene, _argv(ROLES[role], huge), "above the pixel budget")


@pytest.mark.parametrize("role", COSTMAP_ROLES + DEM_ROLES)
def test_a_photo_is_refused_where_one_band_is_needed(scene: Path, role: str) -> None:
    _pairs(scene)
    says = "a DEM has one band" if role in DEM_ROLES else "a costmap has one"
    with rasterio.open(scene / "sample.tif") as ds:
        assert ds.count == 3  # an RGB photo
    _refused(scene, _argv(ROLES[role], "sample.tif"), says)


@pytest.mark.parametrize("role", COSTMAP_ROLES)
def test_a_class_raster_is_refused_as_a_costmap(scene: Path, role: str) -> None:
    _pairs(scene)
    with rasterio.open(scene / "class_like.tif") as ds:
        assert ds.count == 1 and ds.dtypes[0] == "uint8"  # one band, of class ids
    _refused(scene, _argv(ROLES[role], "class_like.tif"), "a costmap holds float costs")


@pytest.mark.parametrize("role", CLASS_ROLES)
def test_a_photo_or_float_costs_are_refused_as_a_class_raster(scene: Path, role: str) -> None:
    with rasterio.open(scene / "c" / "costmap.tif") as ds:
        assert ds.count == 1 and ds.dtypes[0] == "float32"  # one band, of costs
    _refused(scene, _argv(ROLES[role], "sample.tif"), "a class raster has one band")
    _refused(scene, _argv(ROLES[role], "c/costmap.tif"), "integer class ids")


@pytest.mark.parametrize("role", ["plan: costmap", "corridor: costmap", "plan --pairs: costmap"])
def test_a_lethal_sidecar_on_another_grid_is_refused(scene: Path, role: str) -> None:
    """The sidecar the costmap names is checked against the costmap's grid before planning."""
    _pairs(scene)
    src = scene / "c" / "costmap.tif"
    with rasterio.open(src) as ds:
        tags = ds.tags()
    sidecar = scene / "c" / tags["OVERSEEC_LETHAL_FILE"]
    with rasterio.open(sidecar) as ds:
        profile = ds.profile
        data = ds.read(1)
    profile.update(width=data.shape[1] // 2, height=data.shape[0] // 2)
    with rasterio.open(sidecar, "w", **profile) as ds:
        ds.write(np.ascontiguousarray(data[::2, ::2]), 1)
    with rasterio.open(sidecar) as side, rasterio.open(src) as cost:
        assert (side.width, side.height) != (cost.width, cost.height)
    _refused(scene, _argv(ROLES[role], "c/costmap.tif"), "not on the costmap's grid")
