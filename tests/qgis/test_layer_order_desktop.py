"""Routes stay on top in the real QGIS desktop (the `qgis` binary under Xvfb).

A script given to QGIS with ``--code`` adds the sample costmap through the dock, plans a route
with the map tool (planner worker), then adds a second costmap through the dock -- the way a
re-prompt or a new run does -- and grabs the canvas: the route's blue must still be drawn over the
new costmap. It saves the project, reopens it with QGIS's own File › Open (``iface.addProject``)
and grabs again: the route is still on top and visible. Save planned paths then runs on the
reopened project, whose map tool knows no paths layer. A 10 ms QTimer heartbeat records the
longest gap on the GUI thread while each dock action runs. The reopened canvas is kept as
``docs/img/routes_on_top.png`` ($OVERSEEC_ARTIFACTS/routes_on_top.png).
"""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import numpy as np
import pytest

from .conftest import SAMPLE
from .desktop import META, as_rgb, desktop_config, near, needs_desktop, run_desktop, sample_costmap

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

SCRIPT = textwrap.dedent(
    r"""
    import uuid
    from pathlib import Path
    from qgis.core import QgsProject, QgsRasterLayer, QgsPointXY

    result["blocks_ms"] = {}

    def timed(name, action, settle=0.3):
        # the longest heartbeat gap (as measured) while an action runs on the GUI thread
        beat = Heartbeat().start()
        QTimer.singleShot(0, action)
        pump(settle)
        beat.stop()
        result["blocks_ms"][name] = round(beat.longest_ms, 1)

    def summary(costmap):
        from overseec_qgis.jobs import CostmapSummary
        return CostmapSummary(costmap=Path(costmap), lethal=Path(costmap).with_name("lethal.tif"),
            program_file=Path(costmap).with_suffix(".program.txt"), program="cost = 0.5",
            entities=("road",), notes=(), warnings=(), mean_cost=0.5)

    def main():
        win, plugin = open_plugin()
        from overseec_qgis.legend import RoutesKeeper
        from overseec_qgis.savedpaths import paths_layers
        keeper = RoutesKeeper()  # what the plugin holds for its session
        if plugin.dock is not None:
            plugin.dock.hide()
        project = QgsProject.instance()
        image = QgsRasterLayer(CFG["image"], "sample image")
        project.addMapLayer(image)
        runs, tool, canvas = plugin.dock.runs, plugin.map_tool, iface.mapCanvas()
        add = lambda folder, cm, prompt: runs._add_costmap(Path(folder), summary(cm), prompt)  # noqa: E731
        timed("add costmap", lambda: add(CFG["run_dir"], CFG["costmap"], CFG["prompt"]))
        costmap = tool.costmap_layer
        iface.layerTreeView().setCurrentLayer(image)  # new layers would land below the costmaps
        canvas.setDestinationCrs(costmap.crs())
        canvas.setExtent(costmap.extent())
        tool.points = [QgsPointXY(*CFG["start"]), QgsPointXY(*CFG["goal"])]
        tool.complete, tool.path_key = True, uuid.uuid4().hex
        planned = tool.replan(block=True)
        result["planned"] = planned is not None
        tool.cancel()  # nothing to carry: the next costmap only lands on the map
        timed("add a second costmap", lambda: add(CFG["run2_dir"], CFG["costmap2"], "avoid everything"))
        layer = paths_layers(project)[0]
        root = project.layerTreeRoot()
        result["order"] = [l.customProperty("overseec/role", "") for l in root.layerOrder()]
        result["path_screen"] = []
        for f in layer.getFeatures():
            for p in f.geometry().asPolyline():
                s = canvas.getCoordinateTransform().transform(p)
                result["path_screen"].append([s.x(), s.y()])
        iface.messageBar().clearWidgets()
        out = CFG["out_dir"]
        result["step"] = 'rendered(canvas)\n        canva'
        rendered(canvas)
        canvas.grab().toImage().save(os.path.join(out, "after_costmap.png"))
        root.findLayer(layer.id()).setItemVisibilityChecked(False)
        rendered(canvas)
        canvas.grab().toImage().save(os.path.join(out, "without_route.png"))
        root.findLayer(layer.id()).setItemVisibilityChecked(True)
        extent = canvas.extent()
        result["step"] = 'result["written"] = project.wr'
        result["written"] = project.write(CFG["project"])
        project.clear()
        pump(0.3)
        result["step"] = 'iface.addProject(CFG["project"'
        iface.addProject(CFG["project"])  # File > Open
        pump(0.5)
        canvas.setExtent(extent)
        rendered(canvas)
        result["step"] = 'win.grab().toImage().save(os.p'
        win.grab().toImage().save(os.path.join(out, "reopened_window.png"))
        canvas.grab().toImage().save(os.path.join(out, "reopened.png"))
        root = QgsProject.instance().layerTreeRoot()
        result["order_reopened"] = [l.customProperty("overseec/role", "") for l in root.layerOrder()]
        reopened = paths_layers(QgsProject.instance())
        result["reopened_paths"] = [[l.name(), l.featureCount(), root.findLayer(l.id()).isVisible()] for l in reopened]
        saved = []
        result["step"] = 'timed("save planned pat'
        def save():
            t = time.perf_counter()
            saved.append(runs.save_paths())
            result["save_call_ms"] = round(1000 * (time.perf_counter() - t), 1)

        timed("save planned paths", save)
        deadline = time.monotonic() + 30
        while getattr(runs, "save_task", None) is not None and time.monotonic() < deadline:
            pump(0.05)
        result["saved"] = str(saved[0]) if saved and saved[0] else None
        names = [lyr.name() for lyr in QgsProject.instance().mapLayers().values()]
        result["saved_layer"] = [n for n in names if n.startswith("saved paths")]
        result["status"] = runs.status_label.text()
        keeper.close()
        result["step"] = "unload"
        plugin.unload()
        result["step"] = "unloaded"

    def timed_out():
        result.setdefault("error", "timed out after step " + result.get("step", "?"))
        from qgis.PyQt.QtWidgets import QApplication
        shown = [w for w in QApplication.topLevelWidgets() if w.isVisible()]
        result["windows"] = [[type(w).__name__, w.windowTitle()] for w in shown]  # a dialog waiting?
        QApplication.primaryScreen().grabWindow(0).save(os.path.join(CFG["out_dir"], "timed_out.png"))
        finish(3)

    start(main, 100000, timed_out)
    """
)


@pytest.fixture(scope="module")
def desktop(tmp_path_factory) -> dict:
    """One QGIS desktop session; its JSON report and screenshots."""
    tmp = tmp_path_factory.mktemp("routes")
    run_dir, run2 = tmp / "run", tmp / "run2"
    costmap = sample_costmap(run_dir)
    shutil.copytree(run_dir, run2)
    config = desktop_config(
        tmp,
        costmap,
        run2_dir=str(run2),
        image=str(SAMPLE / "sample.tif"),
        costmap2=str(run2 / "costmap.tif"),
        start=META["start"],
        goal=META["goal"],
        project=str(tmp / "project.qgz"),
    )
    keep = {"reopened_window.png": "routes_on_top.png"}
    result = run_desktop(tmp, "routes_on_top.py", SCRIPT, config, timeout=300, check_exit=False, keep=keep)
    out = Path(config["out_dir"])
    return {"result": result, "out": out, "config": config}


def route_share(img: np.ndarray, pts: np.ndarray) -> float:
    """Share of the route's segment midpoints with the path style's blue core within a pixel."""
    mids = (pts[:-1] + pts[1:]) / 2
    blue = (0, 80, 255)

    def bluish(x, y) -> bool:
        patch = img[max(0, y - 1) : y + 2, max(0, x - 1) : x + 2].reshape(-1, 3)
        return any(near(p, blue, 60) for p in patch)

    return float(np.mean([bluish(round(x), round(y)) for x, y in mids]))


@needs_desktop
def test_a_new_costmap_leaves_the_route_drawn_on_top(desktop) -> None:
    r, out = desktop["result"], desktop["out"]
    assert r["planned"]
    assert r["order"][0] == "path" and r["order"].count("path") == 1, r["order"]
    pts = np.array(r["path_screen"], float)
    assert len(pts) > 5
    shown, hidden = as_rgb(out / "after_costmap.png"), as_rgb(out / "without_route.png")
    assert route_share(shown, pts) > 0.9 and route_share(hidden, pts) < 0.05


@needs_desktop
def test_the_reopened_project_draws_the_route_on_top(desktop) -> None:
    r, out = desktop["result"], desktop["out"]
    assert r["written"] and r["order_reopened"][0] == "path", r["order_reopened"]
    ((_name, count, visible),) = r["reopened_paths"]
    assert count == 1 and visible
    pts = np.array(r["path_screen"], float)
    assert route_share(as_rgb(out / "reopened.png"), pts) > 0.9


@needs_desktop
def test_save_planned_paths_works_on_the_reopened_project(desktop) -> None:
    r = desktop["result"]
    assert r["saved"] and Path(r["saved"]).is_file(), r["status"]
    assert Path(r["saved"]).parent == Path(desktop["config"]["run_dir"])
    assert r["saved_layer"] == ["saved paths — " + r["reopened_paths"][0][0].removeprefix("path — ")], r["status"]


@needs_desktop
def test_the_dock_actions_never_block_the_gui_for_100_ms(desktop) -> None:
    blocks = desktop["result"]["blocks_ms"]
    print("longest GUI block per action (ms):", blocks, "save_paths itself:", desktop["result"]["save_call_ms"])
    assert blocks["save planned paths"] < 100, blocks
