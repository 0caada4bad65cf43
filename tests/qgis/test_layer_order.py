"""Routes and overrides above every costmap, names by prompt, saving loaded paths.

The dock's own methods add the costmaps (``RunsSection._add_costmap``) and the plugin's map tool
plans through a real planner worker; the project is written and read back with QGIS's own
``QgsProject.write``/``read``, as a user saves and reopens it.
"""

from __future__ import annotations

import json
import shutil
import uuid
from pathlib import Path

import pytest
from qgis.core import QgsLayerTreeGroup, QgsPointXY, QgsProject

from overseec_qgis import layers, override_layer
from overseec_qgis.jobs import CostmapSummary
from overseec_qgis.legend import (
    PROP_ROUTES_GROUP,
    ROUTES_GROUP,
    RoutesKeeper,
    find_routes_group,
    layer_name,
    tidy_routes,
    unique_name,
)
from overseec_qgis.savedpaths import paths_layers

from .conftest import make_scene, wait_until

pytestmark = pytest.mark.qgis


def summary(folder: Path, costmap: Path) -> CostmapSummary:
    """What `overseec costmap --json` reports for a costmap the test wrote itself."""
    return CostmapSummary(
        costmap=costmap,
        lethal=costmap.with_name("lethal.tif"),
        program_file=costmap.with_suffix(".program.txt"),
        program='cost = where(M["road"], 0.05, 0.5)',
        entities=("road", "grass", "water"),
        notes=(),
        warnings=(),
        mean_cost=0.5,
    )


def plan_between(tool, scene, a, b) -> None:
    """Plan a route on the tool's costmap between two pixels (as two clicks do). The tool's points
    are in the canvas CRS, which an earlier test may have left as another: make it the costmap's."""
    tool.canvas.setDestinationCrs(tool.costmap_layer.crs())
    tool.points = [QgsPointXY(*scene.world(*a)), QgsPointXY(*scene.world(*b))]
    tool.complete, tool.path_key = True, uuid.uuid4().hex
    assert tool.replan(block=True) is not None


def drawn_order(project) -> list[str]:
    """Roles of the visible layers in drawing order, top first."""
    root = project.layerTreeRoot()
    return [
        lyr.customProperty("overseec/role", "")
        for lyr in root.layerOrder()
        if root.findLayer(lyr.id()) is not None and root.findLayer(lyr.id()).isVisible()
    ]


@pytest.fixture
def two_costmaps(plugin, tmp_path):
    """A costmap planned on, then a second costmap of the same prompt added by the dock."""
    project = QgsProject.instance()
    runs, tool = plugin.dock.runs, plugin.map_tool
    first = make_scene(tmp_path / "run")
    runs._add_costmap(first.folder, summary(first.folder, first.costmap), "prefer the road")
    plan_between(tool, first, (44, 2), (3, 60))
    second = make_scene(tmp_path / "run2")
    runs._add_costmap(second.folder, summary(second.folder, second.costmap), "prefer the road")
    assert tool.wait()  # the route carried onto the second costmap is planned off the GUI thread
    yield project, runs, tool, first, second
    tool.cancel()


def test_a_new_costmap_goes_below_the_routes_which_stay_visible(two_costmaps) -> None:
    project, _runs, tool, _first, _second = two_costmaps
    root = project.layerTreeRoot()
    group = root.children()[0]
    assert isinstance(group, QgsLayerTreeGroup) and group.customProperty(PROP_ROUTES_GROUP)
    assert group.name() == ROUTES_GROUP
    # the route planned on the first costmap and the same route re-planned on the second
    roles = drawn_order(project)
    assert roles[:2] == ["path", "path"], roles
    assert set(roles[2:]) == {"costmap", "lethal"}
    paths = paths_layers(project)
    assert len(paths) == 2 and all(lyr.featureCount() == 1 for lyr in paths)
    assert all(group.findLayer(lyr.id()) is not None for lyr in paths)
    # the costmap group sits right below the routes
    assert root.children()[1].name().startswith("overseec costmap: run2/")


def test_costmaps_and_masks_added_with_no_route_to_replan_go_below_it(plugin, tmp_path) -> None:
    """No re-plan moves anything here: the new groups themselves go below the routes group."""
    project = QgsProject.instance()
    runs, tool = plugin.dock.runs, plugin.map_tool
    scene = make_scene(tmp_path / "run")
    runs._add_costmap(scene.folder, summary(scene.folder, scene.costmap), "prefer the road")
    plan_between(tool, scene, (44, 2), (3, 60))
    tool.cancel()  # the route stays in its layer; nothing to carry to the next costmap
    other = make_scene(tmp_path / "run2")
    runs._add_costmap(other.folder, summary(other.folder, other.costmap), "avoid the road")
    runs._add_outputs(other.folder, "segment", ("mask",))
    roles = drawn_order(project)
    assert roles[0] == "path" and roles.count("path") == 1 and {"costmap", "mask"} <= set(roles[1:]), roles
    assert len(project.layerTreeRoot().children()) == 4  # routes, segment, costmap 2, costmap 1


def test_same_prompt_gives_distinct_costmap_and_path_names(two_costmaps) -> None:
    project = two_costmaps[0]
    costmaps = [lyr.name() for lyr in project.mapLayers().values() if lyr.customProperty("overseec/role") == "costmap"]
    assert sorted(costmaps) == ["costmap — prefer the road", "costmap — prefer the road (2)"]
    paths = sorted(lyr.name() for lyr in paths_layers(project))
    assert paths == ["path — prefer the road", "path — prefer the road (2)"]
    names = [lyr.name() for lyr in project.mapLayers().values()]
    assert len(names) == len(set(names))


def test_reopening_restores_the_routes_on_top_and_visible(two_costmaps, tmp_path) -> None:
    project, _runs, tool, _first, _second = two_costmaps
    root = project.layerTreeRoot()
    # a project saved with the routes buried (an older plugin, or a legend rearranged by hand)
    routes = find_routes_group(project)
    root.insertChildNode(len(root.children()), routes.clone())
    root.removeChildNode(routes)
    assert drawn_order(project)[0] != "path"
    tool.commit_paths()
    keeper = RoutesKeeper(project)
    try:
        file = tmp_path / "project.qgz"
        assert project.write(str(file))
        project.clear()
        assert project.read(str(file))
        assert drawn_order(project)[:2] == ["path", "path"]
        group = root.children()[0]
        assert group.customProperty(PROP_ROUTES_GROUP) and group.isVisible()
        for lyr in paths_layers(project):
            node = root.findLayer(lyr.id())
            assert node.isVisible() and lyr.isValid() and lyr.featureCount() == 1
            assert lyr.renderer().type() == "singleSymbol" and lyr.opacity() == 1.0
            assert not lyr.hasScaleBasedVisibility()
    finally:
        keeper.close()


def test_save_paths_writes_the_loaded_path_layers_without_the_map_tool(two_costmaps, tmp_path) -> None:
    """After reopening, the map tool knows no paths layer and no costmap; Save planned paths
    writes the loaded layer and never asks the planner worker (which can block for seconds)."""
    project, runs, tool, first, _second = two_costmaps
    tool.commit_paths()
    file = tmp_path / "project.qgz"
    assert project.write(str(file))
    project.clear()
    assert project.read(str(file))

    # the tool's paths layer and costmap went with the closed project (their objects are deleted)
    def no_worker():
        raise AssertionError("save_paths asked the planner worker")

    tool.session = no_worker
    saved = runs.save_paths()
    assert saved is not None and saved.parent in (first.folder, _second.folder)
    wait_until(lambda: getattr(runs, "save_task", None) is None, 30, "the save task")
    doc = json.loads(saved.read_text())
    (feature,) = doc["features"]
    assert set(feature["properties"]) == {"total_cost", "length_m", "mode", "vias"}
    lon, lat = feature["geometry"]["coordinates"][0]
    assert 15.0 < lon < 16.0 and 47.0 < lat < 47.2  # WGS 84 (RFC 7946), not UTM
    assert feature["properties"]["total_cost"] > 0
    (layer,) = [lyr for lyr in project.mapLayers().values() if lyr.source().split("|")[0] == str(saved)]
    assert layer.name().startswith("saved paths — prefer the road")
    assert find_routes_group(project).findLayer(layer.id()) is not None


def test_save_paths_without_any_route_says_so(plugin, qgis_iface) -> None:
    assert plugin.dock.runs.save_paths() is None
    assert "no planned paths" in plugin.dock.runs.status_label.text()


def test_names_are_shortened_prompts_made_unique(qgis_new_project, scene) -> None:
    project = QgsProject.instance()
    long = "prefer the paved roads and the gravel tracks, keep well away from the river banks"
    name = layer_name("costmap", long)
    assert name.startswith("costmap — prefer the paved") and name.endswith("…") and len(name) <= 60
    assert layer_name("costmap", "", "costmap-2") == "costmap-2"
    a = layers.add_costmap(scene.costmap, None, name=layer_name("costmap", "x", project=project))
    assert a.name() == "costmap — x"
    assert layer_name("costmap", "x", project=project) == "costmap — x (2)"
    assert unique_name("costmap — x", project, exclude=a) == "costmap — x"


def write_route(path: Path) -> Path:
    """A one-line route GeoJSON, as `overseec plan` writes it (WGS 84)."""
    feature = {
        "type": "Feature",
        "properties": {"total_cost": 1.0},
        "geometry": {"type": "LineString", "coordinates": [[14.5, 47.0], [14.6, 47.1]]},
    }
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [feature]}))
    return path


def test_overrides_go_into_the_routes_group_even_with_a_group_given(qgis_new_project, scene) -> None:
    project = QgsProject.instance()
    costmap = layers.add_costmap(scene.costmap, layers.run_group("overseec costmap: a"))
    overrides = override_layer.open_overrides(scene.folder, layers.run_group("overseec overrides: run"))
    root = project.layerTreeRoot()
    assert [lyr.id() for lyr in root.layerOrder()] == [overrides.id(), costmap.id()]
    assert find_routes_group(project).findLayer(overrides.id()) is not None


def test_tidy_moves_stray_paths_into_the_group_at_the_top(qgis_new_project, scene, tmp_path) -> None:
    """A project saved before the routes group existed: its path layer lies below a costmap."""
    project = QgsProject.instance()
    shutil.copy(scene.costmap, tmp_path / "c.tif")
    path = tmp_path / "p.geojson"
    write_route(path)
    route = layers.add_path(path)
    project.layerTreeRoot().removeChildNode(find_routes_group(project))  # as an old project had it
    project.layerTreeRoot().addLayer(route)
    layers.add_costmap(tmp_path / "c.tif", None)
    assert drawn_order(project) == ["costmap", "path"]
    tidy_routes(project)
    assert drawn_order(project) == ["path", "costmap"]


def test_a_layer_added_while_a_route_is_selected_goes_below_the_routes(qgis_new_project, scene, tmp_path) -> None:
    """Layer › Add Raster Layer with a route layer selected: QGIS's insertion point is inside the
    routes group (QgsLayerTreeRegistryBridge follows the selection), so the new raster would
    land in the group above the route and cover it; the keeper moves it right below the group."""
    project = QgsProject.instance()
    keeper = RoutesKeeper(project)
    try:
        costmap = layers.add_costmap(scene.costmap, None)
        overrides = override_layer.open_overrides(scene.folder)
        group = find_routes_group(project)
        bridge = project.layerTreeRegistryBridge()
        bridge.setLayerInsertionPoint(bridge.InsertionPoint(group, 0))  # what selecting a route does
        shutil.copy(scene.costmap, tmp_path / "photo.tif")
        from qgis.core import QgsRasterLayer

        photo = QgsRasterLayer(str(tmp_path / "photo.tif"), "photo")
        project.addMapLayer(photo)  # as QGIS's Add Raster Layer does: into the legend at the insertion point
        order = [lyr.id() for lyr in project.layerTreeRoot().layerOrder()]
        assert order == [overrides.id(), photo.id(), costmap.id()]
        assert group.findLayer(photo.id()) is None and find_routes_group(project).findLayer(photo.id()) is None
        assert project.layerTreeRoot().findLayer(photo.id()).parent() is project.layerTreeRoot()
    finally:
        keeper.close()
        bridge = project.layerTreeRegistryBridge()  # the group goes with the project: point at the root
        bridge.setLayerInsertionPoint(bridge.InsertionPoint(project.layerTreeRoot(), 0))


def test_each_route_of_a_comparison_has_its_own_colour_and_a_telling_name(qgis_new_project, scene, tmp_path) -> None:
    """Two prompts with the same opening: the second route's name says where they differ (not
    " (2)"), the full prompt is in the abstract, and the two lines are drawn in two colours."""
    project = QgsProject.instance()
    a = "Prefer the roads and trails, grass is fine, keep well away from the baseball field"
    b = "Prefer the roads and trails, grass is fine, keep well away from the water"
    made = []
    for i, prompt in enumerate((a, b)):
        path = tmp_path / f"p{i}.geojson"
        write_route(path)
        prov = layers.Provenance(prompt=prompt, stage="plan")
        made.append(layers.add_path(path, prov=prov, name=layer_name("path", prompt, project=project)))
    first, second = made
    assert first.name().startswith("path — Prefer the roads and trails")
    assert "(2)" not in second.name() and "water" in second.name(), second.name()
    assert b in second.metadata().abstract()
    colours = {layers._route_colour_of(lyr) for lyr in made}
    assert len(colours) == 2 and layers.ROUTE_COLOURS[0] in colours
