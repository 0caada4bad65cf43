"""The dock's Routes box in the real QGIS desktop (the `qgis` binary under Xvfb).

A ``--code`` script loads the plugin from a pure-Python copy of the tree, gives the map tool the
sample's costmap, clicks the start and the goal on the canvas (QTest), then clicks the dock's
Corridor button and, with a generated line layer of pairs chosen, Plan pairs -- each with the
real worker, while a 10 ms heartbeat (:mod:`tests.qgis.heartbeat`, pasted into the script)
records the longest time the GUI thread was blocked. The canvas is grabbed with the corridor
drawn: the corridor's cells are coloured where the route runs.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from .desktop import META, as_rgb, desktop_config, needs_desktop, print_blocks, run_desktop, sample_costmap
from .heartbeat import MAX_BLOCK_MS

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

SCRIPT = textwrap.dedent(
    r"""
    from qgis.core import QgsFeature, QgsGeometry, QgsPointXY, QgsProject, QgsVectorLayer
    from qgis.PyQt.QtCore import QPoint, Qt
    from qgis.PyQt.QtTest import QTest

    def main():
        win, plugin = open_plugin()
        from overseec_qgis.layers import Provenance, add_costmap, run_group
        dock = plugin.dock
        dock.environment.checked_once = True  # no environment check competing for the job slot
        dock.show()
        dock.raise_()
        done = []
        dock.task_done.connect(lambda stage, ok: done.append((stage, ok)))
        canvas = iface.mapCanvas()
        vp = canvas.viewport()
        tool = plugin.map_tool
        planned = []
        tool.planned.connect(planned.append)

        def click(x, y):
            p = canvas.getCoordinateTransform().transform(QgsPointXY(x, y))
            QTest.mouseClick(vp, Qt.LeftButton, Qt.NoModifier, QPoint(round(p.x()), round(p.y())))

        prov = Provenance(run_dir=CFG["run_dir"], prompt=CFG["prompt"], stage="costmap")
        costmap = add_costmap(CFG["costmap"], run_group("overseec costmap: sample"), prov)
        canvas.setDestinationCrs(costmap.crs())
        canvas.setExtent(costmap.extent())
        pump(0.5)
        tool.set_costmap(costmap)
        plugin.activate_map_tool(True)
        pump(0.5)
        bar = iface.messageBar()
        bar.clearWidgets()
        titles = lambda: [(i.title(), int(i.level())) for i in bar.items()]  # noqa: E731
        QTest.mouseClick(dock.routes.corridor_button, Qt.LeftButton)  # no route yet: a red bar
        pump(0.2)
        result["bar_before_route"] = titles()
        (sx, sy), (gx, gy) = CFG["start"], CFG["goal"]
        click(sx, sy)
        measure("click the goal: plan", lambda: click(gx, gy), lambda: bool(planned) and not tool.busy(), timeout=90)

        n = len(done)
        measure("Corridor (click, worker, two rasters loaded)",
                lambda: QTest.mouseClick(dock.routes.corridor_button, Qt.LeftButton), lambda: len(done) > n, timeout=90)
        result["corridor"] = done[-1]
        pump(0.2)
        result["bar_after_corridor"] = titles()
        root = QgsProject.instance().layerTreeRoot()
        result["legend"] = [c.name() for c in root.children()]
        from overseec_qgis.legend import find_routes_group
        find_routes_group().setItemVisibilityChecked(False)  # the corridor itself, not the route over it
        pump(1.0)
        canvas.refreshAllLayers()
        wait_for(lambda: not canvas.isDrawing(), 30)
        pump(0.5)
        canvas.grab().save(os.path.join(CFG["out_dir"], "corridor.png"))
        find_routes_group().setItemVisibilityChecked(True)
        result["route"] = [[p.x(), p.y()] for p in next(tool.paths_layer.getFeatures()).geometry().asPolyline()]
        result["route_screen"] = [
            [canvas.getCoordinateTransform().transform(QgsPointXY(x, y)).x(),
             canvas.getCoordinateTransform().transform(QgsPointXY(x, y)).y()] for x, y in result["route"]
        ]

        lines = QgsVectorLayer(f"LineString?crs={costmap.crs().authid()}", "pairs", "memory")
        for (ax, ay), (bx, by) in CFG["pairs"]:
            f = QgsFeature(lines.fields())
            f.setGeometry(QgsGeometry.fromPolylineXY([QgsPointXY(ax, ay), QgsPointXY(bx, by)]))
            lines.dataProvider().addFeature(f)
        QgsProject.instance().addMapLayer(lines)
        dock.routes.pairs_combo.setLayer(lines)
        n = len(done)
        measure("Plan pairs (click, pairs written in the task, worker, routes loaded)",
                lambda: QTest.mouseClick(dock.routes.pairs_button, Qt.LeftButton), lambda: len(done) > n, timeout=90)
        result["pairs"] = done[-1]
        routes = [lyr for lyr in QgsProject.instance().mapLayers().values() if lyr.name().startswith("routes — ")]
        result["routes"] = [lyr.featureCount() for lyr in routes]
        plugin.unload()

    run(main)
    """
)


@pytest.fixture(scope="module")
def desktop_run(tmp_path_factory) -> dict:
    """One QGIS desktop session: a route, its corridor and three pairs planned from the dock."""
    tmp = tmp_path_factory.mktemp("desktop_routes")
    run_dir = tmp / "run"
    costmap = sample_costmap(run_dir)
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    config = desktop_config(
        tmp,
        costmap,
        start=[sx, sy],
        goal=[gx, gy],
        pairs=[[[sx, sy], [gx, gy]], [[gx, gy], [sx, sy]], [[sx, gy], [gx, sy]]],
    )
    keep = {"corridor.png": "dock_corridor.png"}
    result = run_desktop(tmp, "drive_routes.py", SCRIPT, config, timeout=300, check_exit=False, keep=keep)
    out = Path(config["out_dir"])
    print_blocks(result)
    return {"result": result, "out": out, "config": config}


@needs_desktop
def test_corridor_and_pairs_from_the_dock_never_block_the_gui_thread(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["corridor"] == ["corridor", True] and r["pairs"] == ["pairs", True]
    assert r["routes"] == [3]
    assert r["legend"][0] == "overseec routes & overrides"
    assert r["legend"][1].startswith("overseec corridor:")
    slow = {name: ms for name, ms in r["blocks"].items() if ms > MAX_BLOCK_MS}
    assert not slow, slow


@needs_desktop
def test_the_corridor_is_drawn_along_the_route(desktop_run) -> None:
    rgb = as_rgb(desktop_run["out"] / "corridor.png").astype(int)
    # with the routes group hidden, the route's own cells show the ratio's colour at 1.0 (green,
    # #1a9850 at 85 % over the mask's blue): green well above red and blue
    points = desktop_run["result"]["route_screen"]
    samples = points[len(points) // 4 : 3 * len(points) // 4 : 5]
    greenish = 0
    for x, y in samples:
        r0, c0 = max(0, round(y) - 3), max(0, round(x) - 3)  # the corridor is a few screen pixels wide
        near_route = rgb[r0 : round(y) + 4, c0 : round(x) + 4].reshape(-1, 3)
        greenish += int(any(g > r + 40 and g > b + 20 for r, g, b in near_route))
    assert greenish >= 0.8 * len(samples), (greenish, len(samples))
    assert np.asarray(rgb).std() > 5  # something is drawn at all


@needs_desktop
def test_a_corridor_error_goes_when_the_corridor_succeeds(desktop_run) -> None:
    """Corridor before any route leaves a red bar that stays (the analyst may be away); once the
    corridor of a route succeeds, that bar is gone, not left contradicting the drawn corridor
    (issue 32 item 7)."""
    critical = 2  # Qgis.Critical
    result = desktop_run["result"]
    assert ["overseec corridor", critical] in result["bar_before_route"]
    assert result["corridor"] == ["corridor", True]
    assert ["overseec corridor", critical] not in result["bar_after_corridor"], result["bar_after_corridor"]
