"""The map tool in the real QGIS desktop (the `qgis` binary under Xvfb), planning through the worker.

The plugin runs from a pure-Python copy of the tree (no compiled kernel anywhere QGIS's Python can
import it), so every plan goes to the overseec environment's planner worker. A script given to
QGIS with ``--code`` loads the sample scene's costmap, turns the map tool on and drives it with
QTest mouse events on the canvas: click the start, Shift+click two vias, click the goal, drag a via.
It then grabs the canvas (with and without the markers and the paths layer), saves the project
and writes what it saw to a JSON file. The test checks pixels -- markers in their colours and the
path's blue on top of the opaque costmap -- and reopens the saved project to find the same paths.
The main window's grab is kept as the map tool's screenshot ($OVERSEEC_ARTIFACTS/maptool.png;
docs/img/ keeps a copy).
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from .conftest import SAMPLE
from .desktop import (
    META,
    as_rgb,
    desktop_config,
    near,
    needs_desktop,
    passable,
    run_desktop,
    sample_costmap,
)

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

SCRIPT = textwrap.dedent(
    r"""
    import importlib.util
    from qgis.core import QgsProject, QgsRasterLayer, QgsPointXY
    from qgis.PyQt.QtCore import QPoint, Qt
    from qgis.PyQt.QtTest import QTest
    from qgis.PyQt.QtWidgets import QAction

    def main():
        import overseec_core
        result["core_file"] = overseec_core.__file__
        result["kernel_importable"] = importlib.util.find_spec("overseec_core.plan._kernel") is not None
        win, plugin = open_plugin()
        from overseec_qgis.layers import Provenance, add_costmap, run_group
        from overseec_qgis.planclient import shared_client
        if plugin.dock is not None:  # the screenshot shows the map and the legend
            plugin.dock.hide()
        pump(0.3)
        project = QgsProject.instance()
        image = QgsRasterLayer(CFG["image"], "sample image")
        project.addMapLayer(image)
        prov = Provenance(run_dir=CFG["run_dir"], prompt=CFG["prompt"], stage="costmap")
        costmap = add_costmap(CFG["costmap"], run_group("overseec costmap: sample"), prov)
        # the legend selection is the image, below the costmap: new layers would go there
        iface.layerTreeView().setCurrentLayer(image)
        canvas = iface.mapCanvas()
        canvas.setDestinationCrs(costmap.crs())
        canvas.setExtent(costmap.extent())
        tool = plugin.map_tool
        tool.set_costmap(costmap)
        plugin.plan_action.trigger()
        result["tool_active"] = canvas.mapTool() is tool
        rendered(canvas)
        result["canvas_size"] = [canvas.width(), canvas.height()]
        planned, failed = [], []
        tool.planned.connect(planned.append)
        tool.failed.connect(failed.append)

        def screen(x, y):
            p = canvas.getCoordinateTransform().transform(QgsPointXY(x, y))
            return QPoint(round(p.x()), round(p.y()))

        vp = canvas.viewport()
        extent = canvas.extent().toString(3)
        (sx, sy), (gx, gy) = CFG["start"], CFG["goal"]
        QTest.mouseClick(vp, Qt.LeftButton, Qt.NoModifier, screen(sx, sy))
        pump(0.1)
        for x, y in CFG["vias"]:
            QTest.mouseClick(vp, Qt.LeftButton, Qt.ShiftModifier, screen(x, y))
            pump(0.1)
        result["extent_unchanged_by_shift_clicks"] = canvas.extent().toString(3) == extent
        QTest.mouseClick(vp, Qt.LeftButton, Qt.NoModifier, screen(gx, gy))
        tool.wait()  # the worker plans in the background
        result["planned_after_goal"] = len(planned)
        # drag the second via with the button held (QTest's window events carry the buttons)
        top = win.windowHandle()
        a, b = screen(*CFG["vias"][1]), screen(*CFG["drag_to"])
        QTest.mousePress(top, Qt.LeftButton, Qt.NoModifier, vp.mapTo(win, a))
        for t in (0.2, 0.4, 0.6, 0.8, 1.0):
            p = QPoint(round(a.x() + t * (b.x() - a.x())), round(a.y() + t * (b.y() - a.y())))
            QTest.mouseMove(top, vp.mapTo(win, p))
            pump(0.03)
        QTest.mouseRelease(top, Qt.LeftButton, Qt.NoModifier, vp.mapTo(win, b))
        tool.wait()
        result["planned"] = len(planned)
        result["failed"] = failed
        result["replan_ms"] = planned[-1].ms if planned else None
        result["worker_pid"] = shared_client().pid
        deadline = time.monotonic() + 60  # the dock's first-use environment check reports in the bar
        environment = getattr(plugin.dock, "environment", None)
        while getattr(environment, "task", None) is not None and time.monotonic() < deadline:
            pump(0.1)
        iface.messageBar().clearWidgets()
        rendered(canvas)
        out = CFG["out_dir"]
        canvas.grab().toImage().save(os.path.join(out, "canvas.png"))
        win.grab().toImage().save(os.path.join(out, "maptool.png"))
        result["markers"] = [
            {"xy": [m.pos().x(), m.pos().y()], "fill": list(m.fillColor().getRgb()[:3])} for m in tool.markers
        ]
        layer = tool.paths_layer
        root = project.layerTreeRoot()
        result["paths_source"] = layer.source()
        first = root.children()[0]  # the routes group, above every costmap
        result["paths_first_in_legend"] = first.findLayer(layer.id()) is not None
        result["paths_first_drawn"] = root.layerOrder()[0] is layer
        vertices = [p for f in layer.getFeatures() for p in f.geometry().asPolyline()]
        result["path_screen"] = [[screen(p.x(), p.y()).x(), screen(p.x(), p.y()).y()] for p in vertices]
        result["undo_steps"] = layer.undoStack().count()
        # Edit › Undo (what Ctrl+Z triggers) takes back the drag's re-plan, Redo restores it
        result["paths_layer_current"] = iface.activeLayer() is layer
        wkt = lambda: [f.geometry().asWkt(3) for f in layer.getFeatures()]  # noqa: E731
        dragged = wkt()
        iface.mainWindow().findChild(QAction, "mActionUndo").trigger()
        pump(0.1)
        result["undo_changed_path"] = wkt() != dragged and len(wkt()) == 1
        iface.mainWindow().findChild(QAction, "mActionRedo").trigger()
        pump(0.1)
        result["redo_restored_path"] = wkt() == dragged
        # the same view without the markers and the paths layer
        for m in tool.markers:
            m.hide()
        root.findLayer(layer.id()).setItemVisibilityChecked(False)
        rendered(canvas)
        canvas.grab().toImage().save(os.path.join(out, "canvas_without.png"))
        root.findLayer(layer.id()).setItemVisibilityChecked(True)
        for m in tool.markers:
            m.show()
        result["project_written"] = project.write(CFG["project"])
        result["modified_after_write"] = layer.isModified()
        result["features"] = [[f["total_cost"], f["vias"], f.geometry().asWkt(3)] for f in layer.getFeatures()]
        plugin.unload()
        pid = result["worker_pid"]
        alive = True
        for _ in range(50):
            try:
                os.kill(pid, 0)
            except OSError:
                alive = False
                break
            time.sleep(0.1)
        result["worker_alive_after_unload"] = alive
        result["kernel_loaded"] = "overseec_core.plan._kernel" in sys.modules

    start(main, 240000)
    """
)


@pytest.fixture(scope="module")
def desktop_run(tmp_path_factory) -> dict:
    """One QGIS desktop session driving the map tool; its JSON report and file paths."""
    from overseec_core.plan import load_costmap

    tmp = tmp_path_factory.mktemp("desktop")
    run_dir = tmp / "run"
    costmap = sample_costmap(run_dir)
    grid = load_costmap(costmap)
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    dx, dy = gx - sx, gy - sy
    vias = [passable(grid.cost, grid, sx + dx / 3 + 0.25 * dy, sy + dy / 3 - 0.25 * dx)]
    vias.append(passable(grid.cost, grid, sx + 2 * dx / 3 - 0.2 * dy, sy + 2 * dy / 3 + 0.2 * dx))
    drag_to = passable(grid.cost, grid, vias[1][0] - 0.15 * dy, vias[1][1] + 0.15 * dx)
    config = desktop_config(
        tmp,
        costmap,
        image=str(SAMPLE / "sample.tif"),
        start=[sx, sy],
        vias=vias,
        goal=[gx, gy],
        drag_to=drag_to,
        project=str(tmp / "project.qgz"),
    )
    result = run_desktop(tmp, "drive_map_tool.py", SCRIPT, config, timeout=400, keep={"maptool.png": "maptool.png"})
    out = Path(config["out_dir"])
    return {"result": result, "out": out, "config": config, "run_dir": run_dir}


@needs_desktop
def test_the_plugin_plans_through_the_worker_without_a_kernel(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["core_file"].startswith(desktop_run["config"]["plugin_dir"])
    assert r["kernel_importable"] is False and r["kernel_loaded"] is False
    assert r["tool_active"] and r["failed"] == []
    assert r["planned_after_goal"] == 1 and r["planned"] == 2  # the goal, then the drag
    assert r["worker_pid"] and r["worker_alive_after_unload"] is False


@needs_desktop
def test_clicks_shift_clicks_and_a_drag_give_one_path_with_two_vias(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["extent_unchanged_by_shift_clicks"]  # Shift+click added vias, no zoom rectangle
    ((cost, vias, wkt),) = r["features"]
    assert vias == 2 and cost > 0 and wkt.startswith("LineString")
    assert r["undo_steps"] == 2  # the plan and the drag's re-plan, each one undoable command
    assert r["paths_layer_current"] and r["undo_changed_path"] and r["redo_restored_path"]
    assert r["paths_source"].split("|")[0] == str(desktop_run["run_dir"] / "paths.gpkg")
    assert r["paths_first_in_legend"] and r["paths_first_drawn"]


@needs_desktop
def test_markers_and_path_are_drawn_on_top_of_the_costmap(desktop_run) -> None:
    from overseec_qgis.maptool import GOAL_COLOUR, START_COLOUR, VIA_COLOUR

    r, out = desktop_run["result"], desktop_run["out"]
    shown, hidden = as_rgb(out / "canvas.png"), as_rgb(out / "canvas_without.png")
    assert shown.shape[0] > 400 and shown.shape[1] > 600
    fills = [m["fill"] for m in r["markers"]]
    expected = [START_COLOUR, VIA_COLOUR, VIA_COLOUR, GOAL_COLOUR]
    assert fills == [list(c.getRgb()[:3]) for c in expected]
    for marker in r["markers"]:
        x, y = (round(v) for v in marker["xy"])
        assert near(shown[y, x], marker["fill"]), (marker, shown[y, x])
        assert not near(hidden[y, x], marker["fill"], 25), "that colour was there without the marker"
    # the path's blue core along its segments (away from the markers), absent without the layer
    marks = np.array([m["xy"] for m in r["markers"]])
    pts = np.array(r["path_screen"], float)
    mids = (pts[:-1] + pts[1:]) / 2
    mids = mids[np.min(np.linalg.norm(mids[:, None] - marks[None], axis=-1), axis=1) > 15]
    assert len(mids) > 20
    blue = (0, 80, 255)

    def bluish(img, x, y) -> bool:
        patch = img[max(0, y - 1) : y + 2, max(0, x - 1) : x + 2].reshape(-1, 3)
        return any(near(p, blue, 60) for p in patch)

    on = np.mean([bluish(shown, round(x), round(y)) for x, y in mids])
    off = np.mean([bluish(hidden, round(x), round(y)) for x, y in mids])
    assert on > 0.9 and off < 0.05, (on, off)


@needs_desktop
def test_the_saved_project_reopens_with_the_same_paths(desktop_run) -> None:
    from qgis.core import QgsProject

    r = desktop_run["result"]
    assert r["project_written"] and r["modified_after_write"] is False
    project = QgsProject()
    assert project.read(desktop_run["config"]["project"])
    (layer,) = [lyr for lyr in project.mapLayers().values() if lyr.source() == r["paths_source"]]
    got = [[f["total_cost"], f["vias"], f.geometry().asWkt(3)] for f in layer.getFeatures()]
    assert got == r["features"]
    assert project.layerTreeRoot().children()[0].findLayer(layer.id()) is not None  # still on top
    project.clear()
