"""The harness of the desktop tests: the real `qgis` binary under Xvfb, driven by a script.

A desktop test writes a script for QGIS's ``--code`` that starts with :data:`SCRIPT_PRELUDE`
(the GUI-thread heartbeat of :mod:`tests.qgis.heartbeat`, the config, ``finish``, ``rendered``
and ``start``), then defines ``main()`` and ends with ``start(main, timeout_ms)``. The fixture
builds its config with :func:`desktop_config` (a pure-Python copy of the plugin, an output
folder, the result file) and runs QGIS with :func:`run_desktop`, which returns the JSON report
the script wrote. Screenshots are read back with :func:`as_rgb` and compared with :func:`near`.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from .conftest import REPO, SAMPLE, artifacts_dir

QGIS = shutil.which("qgis")
XVFB = shutil.which("xvfb-run")
WORKER = Path(sys.prefix) / "bin" / "overseec"
META = json.loads((SAMPLE / "sample.json").read_text())

needs_desktop = pytest.mark.skipif(
    QGIS is None or XVFB is None or not WORKER.exists(),
    reason="needs the qgis binary, xvfb-run and the venv's overseec",
)

#: heartbeat.py as it is (its ``from __future__`` import must open the script): ``Heartbeat``,
#: ``MAX_BLOCK_MS``, ``pump`` and ``wait_for`` inside QGIS.
HEARTBEAT = Path(__file__).with_name("heartbeat.py").read_text()

#: What every script given to QGIS starts with: the heartbeat, the config (``CFG``, the plugin
#: copy first on ``sys.path``), ``iface``, the report (``result``, written by ``finish(code)``),
#: ``open_plugin()`` (the main window shown, the plugin loaded: ``win, plugin``),
#: ``rendered(canvas)`` (waits for the canvas to draw), ``measure(name, action, done)`` (the
#: heartbeat around an action, into ``result["blocks"]`` and ``["gaps"]``) and
#: ``run(main)`` (a traceback goes into the report) or ``start(main, timeout_ms)`` (runs ``main``
#: once the event loop runs; a timeout goes into the report too).
SCRIPT_PRELUDE = (
    HEARTBEAT
    + "\n"
    + textwrap.dedent(
        r"""
        import json, os, sys, time, traceback
        CFG = json.load(open(os.environ["OVERSEEC_DESKTOP_CONFIG"]))
        sys.path.insert(0, CFG["plugin_dir"])
        from qgis.utils import iface

        result = {}

        def finish(code):
            with open(CFG["result"], "w") as f:
                json.dump(result, f, indent=1)
            os._exit(code)

        def rendered(canvas):
            canvas.refresh()
            pump(0.3)
            deadline = time.monotonic() + 30
            while canvas.isDrawing() and time.monotonic() < deadline:
                pump(0.05)
            pump(0.3)

        def open_plugin(size=(1280, 860), before=lambda: None):
            # QGIS's main window shown at the screenshots' size, then the plugin loaded from the
            # copy as QGIS loads it (before() runs first: to wrap methods the plugin connects)
            win = iface.mainWindow()
            win.resize(*size)
            win.show()
            pump(0.5)
            before()
            from overseec_qgis import classFactory
            plugin = classFactory(iface)
            plugin.initGui()
            return win, plugin

        def measure(name, action, done, timeout=60):
            # the longest GUI-thread block from just before the action until done() (ms), less the
            # time the thread waited for a CPU ("blocks") and as measured ("gaps")
            beat = Heartbeat().start()
            pump(0.05)
            action()
            ok = wait_for(done, timeout)
            pump(0.05)
            result.setdefault("blocks", {})[name] = round(beat.stop(), 1)
            result.setdefault("gaps", {})[name] = round(beat.longest_ms, 1)
            if not ok:
                raise AssertionError(f"{name}: not done within {timeout} s")

        def timed_out():
            result.setdefault("error", "timed out")
            finish(3)

        def run(main):
            try:
                main()
            except Exception:
                result["error"] = traceback.format_exc()
                finish(1)
            finish(0)

        def start(main, timeout_ms, on_timeout=timed_out):
            QTimer.singleShot(0, lambda: run(main))
            QTimer.singleShot(timeout_ms, on_timeout)
        """
    )
)


def pure_python_plugin(dest: Path) -> Path:
    """The plugin as the zip ships it: Python sources and resources, no compiled kernel."""
    ignore = shutil.ignore_patterns("*.so", "*.pyd", "*.dylib", "__pycache__", "*.aux.xml", "*.c")
    for name in ("overseec_qgis", "overseec_core", "resources"):
        shutil.copytree(REPO / name, dest / name, ignore=ignore)
    shutil.copy2(REPO / "metadata.txt", dest / "metadata.txt")
    assert not [p for p in dest.rglob("*") if p.suffix in (".so", ".pyd", ".dylib")]
    return dest


def sample_costmap(run_dir: Path) -> Path:
    """The sample scene's costmap for its own prompt, built into a new run folder."""
    from overseec_core.pipeline import run_costmap
    from overseec_core.synthesize.options import CostmapOptions

    run_dir.mkdir()
    cm = run_costmap(
        CostmapOptions(
            out=run_dir / "costmap.tif",
            labels=SAMPLE / "sample_labels.tif",
            classes=SAMPLE / "classes.json",
            prompt=META["prompt"],
        )
    )
    return cm.costmap


def roads_costmap(
    folder: Path, side: int, start: tuple[float, float], goal: tuple[float, float]
) -> tuple[Path, list[float], list[float]]:
    """A side x side costmap (grass crossed by a grid of roads, 0.5 m, UTM 33N) written to
    ``folder/costmap.tif``, and the map points of the pixel centres ``start`` and ``goal``
    given as (column, row)."""
    from rasterio.crs import CRS
    from rasterio.transform import from_origin

    from overseec_core.io.grid import Grid
    from overseec_core.io.write import write_array

    folder.mkdir(parents=True, exist_ok=True)
    cost = np.full((side, side), 0.5, np.float32)
    cost[::97, :] = 0.05
    cost[:, ::89] = 0.05
    grid = Grid(CRS.from_epsg(32633), from_origin(540_000.0, 5_213_000.0, 0.5, 0.5), side, side)
    path = write_array(folder / "costmap.tif", cost, grid)
    return path, [float(v) for v in grid.transform * start], [float(v) for v in grid.transform * goal]


def passable(cost: np.ndarray, grid, x: float, y: float) -> list[float]:
    """The centre of the passable pixel nearest a map point (vias must be on open ground)."""
    r, c = grid.world_to_pixel(x, y)
    ok = np.argwhere(np.isfinite(cost))
    r, c = ok[np.argmin(np.abs(ok - (r, c)).sum(axis=1))]
    return list(grid.pixel_to_world(int(r), int(c)))


def desktop_config(tmp: Path, costmap: Path | None = None, **fields) -> dict:
    """A script's config: ``fields`` plus the plugin copy, the output folder and the result file;
    with a ``costmap`` (from :func:`sample_costmap`) its run folder, path and prompt too."""
    out = tmp / "out"
    out.mkdir()
    config = {"plugin_dir": str(pure_python_plugin(tmp / "plugin"))}
    if costmap is not None:
        config.update(run_dir=str(costmap.parent), costmap=str(costmap), prompt=META["prompt"])
    return {**config, **fields, "out_dir": str(out), "result": str(out / "result.json")}


def run_desktop(
    tmp: Path,
    name: str,
    script: str,
    config: dict,
    timeout: float,
    check_exit: bool = True,
    keep: dict[str, str] | None = None,
    worker: Path = WORKER,
) -> dict:
    """Run QGIS under Xvfb on ``SCRIPT_PRELUDE + script`` (saved as ``tmp/name``) with ``config``;
    the report it wrote. Fails the test when there is none, it holds an error, or (with
    ``check_exit``) QGIS exited with another status than 0. ``keep`` copies screenshots from the
    output folder into $OVERSEEC_ARTIFACTS (file name there → artifact name). ``worker`` is the
    ``overseec`` the plugin runs ($OVERSEEC_WORKER): the venv's by default."""
    (tmp / "config.json").write_text(json.dumps(config))
    path = tmp / name
    path.write_text(SCRIPT_PRELUDE + "\n" + script)
    env = {k: v for k, v in os.environ.items() if k not in ("QT_QPA_PLATFORM", "PYTHONPATH", "PYTHONHOME")}
    env.update(OVERSEEC_DESKTOP_CONFIG=str(tmp / "config.json"), OVERSEEC_WORKER=str(worker))
    argv = [str(XVFB), "-a", "-s", "-screen 0 1400x1000x24", str(QGIS), "--nologo", "--noversioncheck"]
    argv += ["--noplugins", "--profiles-path", str(tmp / "profiles"), "--code", str(path)]
    done = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=timeout, cwd=tmp)
    result_file = Path(config["result"])
    assert result_file.exists(), f"QGIS wrote no result (exit {done.returncode}): {done.stderr[-3000:]}"
    result = json.loads(result_file.read_text())
    if "error" in result:  # what the script reported so far says where it stopped
        so_far = json.dumps({k: v for k, v in result.items() if k != "error"})[-3000:]
        raise AssertionError(f"{result['error']}\nreported so far: {so_far}")
    if check_exit:
        assert done.returncode == 0, done.stderr[-3000:]
    for shot, artifact in (keep or {}).items():
        shutil.copy2(Path(config["out_dir"]) / shot, artifacts_dir() / artifact)
    return result


def print_blocks(result: dict) -> None:
    """Print the report's longest GUI-thread block per action (``blocks``, ``gaps``; ms)."""
    print("\nlongest GUI-thread block per action (ms): blocked (heartbeat gap less CPU wait) / gap as measured")
    for action, ms in result["blocks"].items():
        print(f"  {ms:8.1f} {result['gaps'][action]:8.1f}  {action}")


def as_rgb(path: Path) -> np.ndarray:
    """A screenshot's pixels, rows × columns × RGB (ints)."""
    from qgis.PyQt.QtGui import QImage

    image = QImage(str(path)).convertToFormat(QImage.Format_RGB888)
    ptr = image.constBits()
    ptr.setsize(image.sizeInBytes())
    rows = np.frombuffer(ptr, np.uint8).reshape(image.height(), image.bytesPerLine())
    return rows[:, : image.width() * 3].reshape(image.height(), image.width(), 3).astype(int)


def near(rgb: np.ndarray, colour, tol: int = 40) -> bool:
    """Whether a pixel (or every pixel of an array) is within ``tol`` of ``colour`` per channel."""
    return bool(np.all(np.abs(rgb - np.asarray(colour)) <= tol))
