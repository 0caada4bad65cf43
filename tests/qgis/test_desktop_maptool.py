"""The map tool in the real QGIS desktop (the `qgis` binary under Xvfb): never blocking the GUI,
re-planning on overrides drawn with QGIS's own Add Polygon tool, undo moving the markers.

A script given to QGIS with ``--code`` loads the plugin from a pure-Python copy of the tree and
drives it with QTest events as an analyst would: plan a route with the overseec tool; switch to
QGIS's Add Polygon (``iface.actionAddFeature()``) on the overrides layer in edit mode and digitize
a polygon across the route (the layer's default makes it lethal; its attribute form is
suppressed); drag the goal and take it back with Edit › Undo; plan in exact mode (a task in the
task manager); give the tool a freshly written 4096² costmap and click at once (the plan waits for
the load); save, stop the worker, reopen the project and plan again. Around every action a 10 ms
QTimer heartbeat (:mod:`tests.qgis.heartbeat`, pasted into the script) records the longest time
the GUI thread was blocked; the figures go into the JSON report and are printed.
"""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from .conftest import artifacts_dir
from .desktop import (
    META,
    as_rgb,
    desktop_config,
    near,
    needs_desktop,
    passable,
    print_blocks,
    roads_costmap,
    run_desktop,
    sample_costmap,
)
from .heartbeat import MAX_BLOCK_MS

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

#: Side of the big costmap (pixels): its load takes the worker a second or two.
BIG = 4096
#: Actions whose time is QGIS's own (not the plugin's): recorded, not held to the rule.
QGIS_OWN = (
    "open the saved project (QGIS reads it)",
    "save the project (QGIS writes it; the tool commits the paths layer's edits)",
)

SCRIPT = textwrap.dedent(
    r"""
    from qgis.core import (
        QgsApplication, QgsDefaultValue, QgsEditFormConfig, QgsGeometry, QgsPointXY, QgsProject,
        QgsRectangle,
    )
    from qgis.PyQt.QtCore import QPoint, Qt
    from qgis.PyQt.QtTest import QTest
    from qgis.PyQt.QtWidgets import QAction

    SLOTS = (
        "set_costmap", "canvasPressEvent", "canvasMoveEvent", "canvasReleaseEvent", "deactivate",
        "_job_done", "_store", "_paths_layer", "_overrides_edited", "_overrides_settled", "_flush_overrides",
        "_history_moved", "_project_read", "_project_cleared", "_project_writing",
    )
    result["slot_ms"] = {}

    def timed(cls, name):
        f = getattr(cls, name)

        def wrapper(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return f(*args, **kwargs)
            finally:
                ms = 1000 * (time.perf_counter() - t0)
                result["slot_ms"][name] = round(max(result["slot_ms"].get(name, 0.0), ms), 1)

        wrapper.__name__ = name
        setattr(cls, name, wrapper)

    def main():
        def wrap_slots():
            from overseec_qgis.maptool import PlanMapTool
            for name in SLOTS:  # the time each of the tool's handlers holds the GUI thread
                timed(PlanMapTool, name)

        win, plugin = open_plugin(before=wrap_slots)
        from overseec_qgis.layers import Provenance, add_costmap, run_group
        from overseec_qgis.override_layer import open_overrides
        from overseec_qgis.planclient import close_shared_client, shared_client
        if plugin.dock is not None:
            plugin.dock.hide()
        project = QgsProject.instance()
        canvas = iface.mapCanvas()
        vp = canvas.viewport()
        tool = plugin.map_tool
        planned, failed = [], []
        tool.planned.connect(planned.append)
        tool.failed.connect(failed.append)
        result["failed"] = failed

        def screen(x, y):
            p = canvas.getCoordinateTransform().transform(QgsPointXY(x, y))
            return QPoint(round(p.x()), round(p.y()))

        def click(x, y, button=Qt.LeftButton):
            QTest.mouseClick(vp, button, Qt.NoModifier, screen(x, y))

        def route():
            (f,) = [f for f in tool.paths_layer.getFeatures() if f["path_id"] == tool.path_key]
            return f

        def replanned(n):
            return lambda: len(planned) > n and not tool.busy()

        prov = Provenance(run_dir=CFG["run_dir"], prompt=CFG["prompt"], stage="costmap")
        costmap = add_costmap(CFG["costmap"], run_group("overseec costmap: sample"), prov)
        canvas.setDestinationCrs(costmap.crs())
        canvas.setExtent(costmap.extent())
        pump(0.5)
        measure("give the tool a costmap (load starts)", lambda: tool.set_costmap(costmap), lambda: True)
        plugin.activate_map_tool(True)
        overrides = open_overrides(CFG["run_dir"], run_group("overseec overrides: sample"))
        lethal = overrides.fields().indexOf("lethal")
        overrides.setDefaultValueDefinition(lethal, QgsDefaultValue("1"))  # drawn polygons are lethal
        form = overrides.editFormConfig()
        form.setSuppress(QgsEditFormConfig.SuppressOn)
        overrides.setEditFormConfig(form)
        tool.set_overrides_layer(overrides)
        pump(0.5)

        (sx, sy), (gx, gy) = CFG["start"], CFG["goal"]
        measure("click the start", lambda: click(sx, sy), lambda: True)
        n = len(planned)
        measure("click the goal: plan (fast)", lambda: click(gx, gy), replanned(n))
        before = route()
        line = before.geometry()
        mid = line.interpolate(line.length() / 2).asPoint()
        h = CFG["wall_half_m"]
        corners = [(mid.x() - h, mid.y() - h), (mid.x() + h, mid.y() - h), (mid.x() + h, mid.y() + h),
                   (mid.x() - h, mid.y() + h)]
        wall = QgsGeometry.fromRect(QgsRectangle(mid.x() - h, mid.y() - h, mid.x() + h, mid.y() + h))
        result["route_crossed_wall_before"] = line.intersects(wall)
        result["cost_before"] = before["total_cost"]

        # QGIS's own Add Polygon tool on the overrides layer in edit mode
        iface.setActiveLayer(overrides)
        overrides.startEditing()
        iface.actionAddFeature().trigger()
        active = canvas.mapTool()
        result["add_polygon_active"] = active is not tool and active.action() is iface.actionAddFeature()
        result["markers_after_switch"] = len(tool.markers)
        n = len(planned)

        def digitize():
            for x, y in corners:
                click(x, y)
                pump(0.05)
            click(*corners[0], button=Qt.RightButton)  # finishes the polygon

        measure("draw a polygon with QGIS's Add Polygon: re-plan", digitize, replanned(n))
        pump(1.0)  # one re-plan for the whole polygon, none later
        result["replans_for_polygon"] = len(planned) - n
        result["override_features"] = [[f["lethal"], f.geometry().asWkt(2)] for f in overrides.getFeatures()]
        after = route()
        result["route_crosses_wall_after"] = after.geometry().intersects(wall)
        result["same_feature"] = after["path_id"] == before["path_id"]
        result["cost_after"] = after["total_cost"]
        iface.messageBar().clearWidgets()
        canvas.refresh()
        pump(1.0)
        canvas.grab().toImage().save(os.path.join(CFG["out_dir"], "override_replanned.png"))
        win.grab().toImage().save(os.path.join(CFG["out_dir"], "maptool_overrides.png"))
        result["markers"] = [
            {"xy": [m.pos().x(), m.pos().y()], "fill": list(m.fillColor().getRgb()[:3])} for m in tool.markers
        ]
        n = len(planned)
        measure("save the override edits: re-plan", lambda: overrides.commitChanges(), replanned(n))

        # back to the overseec tool: drag the goal, then Edit > Undo puts the marker back
        plugin.activate_map_tool(True)
        top = win.windowHandle()
        a, b = screen(gx, gy), screen(*CFG["drag_to"])
        n = len(planned)

        def drag():
            QTest.mousePress(top, Qt.LeftButton, Qt.NoModifier, vp.mapTo(win, a))
            for t in [i / 10 for i in range(1, 11)]:
                p = QPoint(round(a.x() + t * (b.x() - a.x())), round(a.y() + t * (b.y() - a.y())))
                QTest.mouseMove(top, vp.mapTo(win, p))
                pump(0.03)
            QTest.mouseRelease(top, Qt.LeftButton, Qt.NoModifier, vp.mapTo(win, b))

        measure("drag the goal (live preview, then plan)", drag, replanned(n))
        goal_marker = lambda: [tool.markers[-1].pos().x(), tool.markers[-1].pos().y()]  # noqa: E731
        result["goal_marker_dragged"] = goal_marker()
        result["paths_layer_current"] = iface.activeLayer() is tool.paths_layer
        undo = win.findChild(QAction, "mActionUndo")
        measure("Edit > Undo (the marker moves back)", undo.trigger, lambda: True)
        result["goal_marker_undone"] = goal_marker()
        result["goal_screen"] = [a.x(), a.y()]
        redo = win.findChild(QAction, "mActionRedo")
        measure("Edit > Redo", redo.trigger, lambda: True)
        result["goal_marker_redone"] = goal_marker()

        # exact mode: a task in QGIS's task manager
        tool.mode = "exact"
        seen = []

        def exact_done():
            manager = QgsApplication.taskManager()
            seen.extend(d for d in (t.description() for t in manager.activeTasks()) if d.startswith("overseec: plan"))
            return len(planned) > n and not tool.busy()

        measure("click the start (exact)", lambda: click(sx, sy), lambda: True)
        n = len(planned)
        measure("click the goal: plan (exact, a task)", lambda: click(gx, gy), exact_done)
        result["exact_mode"] = route()["mode"]
        result["exact_tasks"] = sorted(set(seen))
        tool.mode = "fast"

        # a costmap written moments ago, given to the tool, clicked at once: the plan waits
        big = add_costmap(CFG["big_costmap"], run_group("overseec costmap: big"),
                          Provenance(run_dir=CFG["big_dir"], prompt="big", stage="costmap"))
        canvas.setExtent(big.extent())
        pump(0.3)
        tool.cancel()
        (bx0, by0), (bx1, by1) = CFG["big_start"], CFG["big_goal"]
        n = len(planned)
        queued = []

        def big_clicks():
            tool.set_costmap(big)
            click(bx0, by0)
            click(bx1, by1)
            queued.append(tool.loading)

        measure(f"give a {CFG['big']}² costmap and click at once: plan after the load", big_clicks, replanned(n))
        result["big_queued"] = queued
        result["big_planned"] = route()["total_cost"] > 0

        # save, stop the worker, reopen: the costmap loads at once, the first plan never blocks
        project.removeMapLayer(big.id())
        canvas.setExtent(costmap.extent())
        pump(0.3)
        written = []
        measure(QGIS_OWN[1], lambda: written.append(project.write(CFG["project"])), lambda: True)
        result["project_written"] = written == [True]
        old_pid = shared_client().pid
        close_shared_client()
        iface.newProject(False)
        pump(0.5)
        measure(QGIS_OWN[0], lambda: iface.addProject(CFG["project"]), lambda: True)
        result["reopened_costmap"] = tool.costmap_path()
        plugin.activate_map_tool(True)
        measure("reopened: click the start", lambda: click(sx, sy), lambda: True)
        n = len(planned)
        reopened_queued = []

        def goal():
            click(gx, gy)
            reopened_queued.append(tool.loading)

        measure("reopened: click the goal: plan (first plan after opening)", goal, replanned(n))
        result["reopened_queued"] = reopened_queued
        reopened_overrides = tool.overrides_layer
        result["reopened_overrides"] = reopened_overrides.source() if reopened_overrides is not None else None
        result["reopened_route_crosses_wall"] = route().geometry().intersects(wall)
        result["reopened_planned"] = len(planned) - n
        result["worker_restarted"] = shared_client().pid not in (None, old_pid)
        plugin.unload()

    start(main, 150000)
    """
)


@pytest.fixture(scope="module")
def desktop_run(tmp_path_factory) -> dict:
    """One QGIS desktop session driving the map tool and QGIS's own digitizing; its report."""
    from overseec_core.plan import load_costmap

    tmp = tmp_path_factory.mktemp("desktop_maptool")
    run_dir = tmp / "run"
    costmap = sample_costmap(run_dir)
    grid = load_costmap(costmap)
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    drag_to = passable(grid.cost, grid, gx - 0.15 * (gy - sy), gy + 0.15 * (gx - sx))
    big, big_start, big_goal = roads_costmap(tmp / "big", BIG, (300.5, 400.5), (BIG - 500.5, BIG - 300.5))
    config = desktop_config(
        tmp,
        costmap,
        start=[sx, sy],
        goal=[gx, gy],
        drag_to=drag_to,
        wall_half_m=12.0,
        big=BIG,
        big_dir=str(big.parent),
        big_costmap=str(big),
        big_start=big_start,
        big_goal=big_goal,
        project=str(tmp / "project.qgz"),
    )
    script = f"QGIS_OWN = {QGIS_OWN!r}\n" + SCRIPT
    keep = {name: name for name in ("maptool_overrides.png", "override_replanned.png")}
    result = run_desktop(tmp, "drive_map_tool.py", script, config, timeout=300, keep=keep)
    out = Path(config["out_dir"])
    figures = {"blocks": result["blocks"], "gaps": result["gaps"], "handlers": result["slot_ms"]}
    (artifacts_dir() / "maptool_blocks.json").write_text(json.dumps(figures, indent=1))
    print_blocks(result)
    print("longest time in one of the tool's handlers (ms):", json.dumps(result["slot_ms"]))
    return {"result": result, "out": out, "config": config}


@needs_desktop
def test_no_map_tool_action_blocks_the_gui_thread(desktop_run) -> None:
    blocks = desktop_run["result"]["blocks"]
    assert len(blocks) >= 12
    slow = {action: ms for action, ms in blocks.items() if action not in QGIS_OWN and ms > MAX_BLOCK_MS}
    assert not slow, f"the GUI thread was blocked longer than {MAX_BLOCK_MS:g} ms: {slow}"


@needs_desktop
def test_a_polygon_drawn_with_qgis_add_polygon_replans_the_route_around_it(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["failed"] == []
    assert r["add_polygon_active"] and r["markers_after_switch"] == 2  # the route survived the switch
    ((lethal, wkt),) = r["override_features"]
    assert lethal == 1 and wkt.startswith("Polygon")
    assert r["route_crossed_wall_before"] and not r["route_crosses_wall_after"]
    assert r["same_feature"] and r["cost_after"] > r["cost_before"]
    assert r["replans_for_polygon"] == 1  # one re-plan for the whole digitizing


@needs_desktop
def test_the_markers_are_drawn_after_the_tool_switch(desktop_run) -> None:
    from overseec_qgis.maptool import GOAL_COLOUR, START_COLOUR

    r, out = desktop_run["result"], desktop_run["out"]
    shown = as_rgb(out / "override_replanned.png")
    assert [m["fill"] for m in r["markers"]] == [list(c.getRgb()[:3]) for c in (START_COLOUR, GOAL_COLOUR)]
    for marker in r["markers"]:
        x, y = (round(v) for v in marker["xy"])
        assert near(shown[y, x], marker["fill"]), (marker, shown[y, x])


@needs_desktop
def test_undo_moves_the_marker_back_and_redo_again(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["paths_layer_current"]

    def dist(a, b) -> float:
        return float(np.hypot(a[0] - b[0], a[1] - b[1]))

    assert dist(r["goal_marker_dragged"], r["goal_screen"]) > 20
    assert dist(r["goal_marker_undone"], r["goal_screen"]) <= 2
    assert dist(r["goal_marker_redone"], r["goal_marker_dragged"]) <= 2


@needs_desktop
def test_exact_plans_run_as_tasks_and_big_costmaps_load_in_the_background(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["exact_mode"] == "exact" and r["exact_tasks"] == ["overseec: planning a route (exact)"]
    assert r["big_queued"] == [True] and r["big_planned"]


@needs_desktop
def test_the_reopened_project_plans_at_the_first_click(desktop_run) -> None:
    r = desktop_run["result"]
    assert r["project_written"] and r["reopened_costmap"] == desktop_run["config"]["costmap"]
    assert r["reopened_planned"] == 1 and r["worker_restarted"]
    # the overrides layer beside the costmap applies again: the new route keeps out of the polygon
    assert r["reopened_overrides"].split("|")[0] == str(Path(desktop_run["config"]["run_dir"]) / "overrides.gpkg")
    assert r["reopened_route_crosses_wall"] is False
