"""Opening and closing a project costs the same with the plugin as without (issue 32 item 9).

A first QGIS desktop session (the `qgis` binary under Xvfb) makes an analyst's project with the
plugin: the sample image (or, for the large case, a 7000² costmap alone), a costmap added through
the dock, a route planned with the map tool, a lethal polygon in the project's overrides layer and
the prompt interpreted (offline) in the dock; then it saves it. Fresh sessions, alternating
without and with the plugin (loaded as QGIS loads it, before the project), open it with QGIS's
own File › Open (``iface.addProject``) and close it (File › Close, ``iface.newProject``) twice:
the first open of a session is the one an analyst waits for, cold caches and first imports
included. Each step is timed as the GUI thread feels it, from the call until the event loop has
been free for 0.5 s (work the plugin puts on timers counts too): the time blocked in all (every
heartbeat gap over 30 ms) and the longest block. With the plugin each median must be within
0.3 s of the median without, and unloading the plugin (what QGIS runs as it quits) must take
under 0.3 s; the figures are printed.
"""

from __future__ import annotations

import statistics
import textwrap

import pytest

from .conftest import SAMPLE
from .desktop import META, desktop_config, needs_desktop, roads_costmap, run_desktop, sample_costmap

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

#: The most a step may cost more with the plugin than without (s), as the issue sets it.
MAX_EXTRA_S = 0.3
#: Fresh QGIS sessions per side (without, with), alternating.
SESSIONS = 2

SCRIPT = textwrap.dedent(
    r"""
    import uuid
    from pathlib import Path
    from qgis.core import QgsFeature, QgsGeometry, QgsPointXY, QgsProject, QgsRasterLayer

    result.update(rounds=[], step="start")

    def summary(costmap):
        from overseec_qgis.jobs import CostmapSummary
        return CostmapSummary(costmap=Path(costmap), lethal=Path(costmap).with_name("lethal.tif"),
            program_file=Path(costmap).with_suffix(".program.txt"), program="cost = 0.5",
            entities=("road",), notes=(), warnings=(), mean_cost=0.5)

    def settled(action, quiet_s=0.5, timeout_s=30.0):
        # (s the GUI thread was blocked in all, longest block s) from the call until the event
        # loop has been free for quiet_s: heartbeat gaps over BUSY_S count, less one tick each
        ticks = [time.monotonic()]
        beat = QTimer()
        beat.setInterval(10)
        beat.timeout.connect(lambda: ticks.append(time.monotonic()))
        beat.start()
        action()
        ticks.append(time.monotonic())
        deadline = ticks[0] + timeout_s
        while time.monotonic() < deadline:
            pump(0.02)
            last_busy = max(b for a, b in zip(ticks, ticks[1:]) if b - a > BUSY_S or a == ticks[0])
            if time.monotonic() - last_busy >= quiet_s:
                break
        beat.stop()
        gaps = [b - a for a, b in zip(ticks, ticks[1:])]
        blocked = sum(g - 0.01 for g in gaps if g > BUSY_S)
        result.setdefault("busy", []).append([round(g, 3) for g in gaps if g > BUSY_S])
        return round(blocked, 3), round(max(gaps), 3)

    BUSY_S = 0.03

    def make_project(plugin):
        from overseec_qgis.savedpaths import paths_layers
        project = QgsProject.instance()
        if CFG.get("image"):
            project.addMapLayer(QgsRasterLayer(CFG["image"], "sample image"))
        runs, tool, canvas = plugin.dock.runs, plugin.map_tool, iface.mapCanvas()
        runs._add_costmap(Path(CFG["run_dir"]), summary(CFG["costmap"]), CFG["prompt"])
        costmap = tool.costmap_layer
        canvas.setDestinationCrs(costmap.crs())
        canvas.setExtent(costmap.extent())
        tool.points = [QgsPointXY(*CFG["start"]), QgsPointXY(*CFG["goal"])]
        tool.complete, tool.path_key = True, uuid.uuid4().hex
        result["planned"] = tool.replan(block=True) is not None
        tool.cancel()
        layer = plugin.override_tool.target_layer(start_editing=True)
        feature = QgsFeature(layer.fields())
        feature.setAttribute("lethal", 1)
        x, y = CFG["start"]
        ring = [QgsPointXY(x + dx, y + dy) for dx, dy in ((5, 5), (15, 5), (15, 15), (5, 15))]
        feature.setGeometry(QgsGeometry.fromPolygonXY([ring]))
        layer.addFeature(feature)
        result["overrides_committed"] = layer.commitChanges()
        result["paths_layers"] = len(paths_layers(project))
        mission = plugin.dock.mission  # the mission interpreted offline, as the dock does it
        mission.offline_check.setChecked(True)
        mission.prompt_edit.setPlainText(CFG["prompt"])
        plugin.dock.runs.interpret()
        pump(0.2)
        wait_for(lambda: plugin.dock.slot.task is None, 120)
        result["entities"] = mission.entities_table.rowCount()
        result["written"] = project.write(CFG["project"])

    def main():
        if CFG["mode"] == "make":
            win, plugin = open_plugin()
            plugin.dock.show()
            pump(0.5)
            make_project(plugin)
            result["layers"] = sorted(l.name() for l in QgsProject.instance().mapLayers().values())
            plugin.unload()
            return
        if CFG["mode"] == "with":
            win, plugin = open_plugin()
            plugin.dock.show()
        else:
            win = iface.mainWindow()
            win.resize(1280, 860)
            win.show()
        pump(2.0)  # start-up settles (the plugin's environment check runs in the background)
        for i in range(2):  # the first open of the session (cold), then a second
            result["step"] = f"open {i}"
            open_s, open_gap = settled(lambda: iface.addProject(CFG["project"]))
            n = len(QgsProject.instance().mapLayers())
            result["step"] = f"close {i}"
            close_s, close_gap = settled(lambda: iface.newProject(False))
            result["rounds"].append(dict(round=i, layers=n, open_s=open_s, open_gap_s=open_gap,
                close_s=close_s, close_gap_s=close_gap))
        if CFG["mode"] == "with":
            result["step"] = "unload"
            result["unload_s"] = settled(plugin.unload)[0]  # what QGIS runs when it quits
        result["step"] = "done"


    def timed_out():
        result.setdefault("error", "timed out at " + result.get("step", "?"))
        finish(3)

    start(main, 400000, timed_out)
    """
)


@pytest.fixture(scope="module", params=["sample", "7000"])
def desktop_run(request, tmp_path_factory) -> dict:
    """The analyst's project made in one QGIS session, then opened and closed in fresh sessions
    that alternate between without and with the plugin: ``{"made": report, "without": [reports],
    "with": [reports]}``."""
    tmp = tmp_path_factory.mktemp("open_close")
    if request.param == "sample":
        costmap = sample_costmap(tmp / "run")
        base = dict(image=str(SAMPLE / "sample.tif"), start=META["start"], goal=META["goal"])
    else:
        side = int(request.param)
        costmap, start, goal = roads_costmap(tmp / "run", side, (1500.5, 1200.5), (side - 1500.5, side - 1300.5))
        base = dict(start=start, goal=goal, prompt=META["prompt"])
    base["project"] = str(tmp / "analyst.qgz")
    runs: dict = {"without": [], "with": []}
    for i, mode in enumerate(["make"] + ["without", "with"] * SESSIONS):
        session = tmp / f"{i}-{mode}"
        session.mkdir()
        config = desktop_config(session, costmap if mode == "make" else None, mode=mode, **base)
        report = run_desktop(session, "open_close.py", SCRIPT, config, timeout=240, check_exit=False)
        if mode == "make":
            runs["made"] = report
        else:
            runs[mode].append(report)
    return runs


def _median(reports: list[dict], key: str, first: bool) -> float:
    return statistics.median(r["rounds"][0 if first else 1][key] for r in reports)


@needs_desktop
def test_the_project_holds_what_an_analyst_saves(desktop_run) -> None:
    made = desktop_run["made"]
    assert made["planned"] and made["overrides_committed"] and made["written"]
    assert made["paths_layers"] == 1
    assert made["entities"] >= 3  # the prompt's roads, trails, grass ... came back with the project
    opened = {r["layers"] for side in ("with", "without") for rep in desktop_run[side] for r in rep["rounds"]}
    assert opened == {len(made["layers"])}


@needs_desktop
def test_opening_and_closing_cost_no_more_than_0_3_s_more_with_the_plugin(desktop_run) -> None:
    print("\nmedian over sessions (s): without plugin / with plugin")
    for first in (True, False):
        for key in ("open_s", "open_gap_s", "close_s", "close_gap_s"):
            without = _median(desktop_run["without"], key, first)
            with_plugin = _median(desktop_run["with"], key, first)
            print(f"  {'first' if first else 'second'} {key:12s} {without:7.3f} {with_plugin:7.3f}")
            assert with_plugin <= without + MAX_EXTRA_S, (key, first, desktop_run)
    unload = statistics.median(r["unload_s"] for r in desktop_run["with"])
    print(f"  plugin unload (QGIS exit) {unload:7.3f}")
    assert unload <= MAX_EXTRA_S
