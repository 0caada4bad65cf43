"""Hostile timing: a Ctrl-C at the very end of a command (issue 23).

A cancel that arrives after the last write but before the command finished -- during the final
renames or the manifest write -- must still undo the job: exit status 130 and every earlier
output byte for byte as it was. The test hook ``OVERSEEC_TEST_PAUSE_BEFORE_COMMIT`` (see
:mod:`overseec_core.io.transaction`) holds the command just before its last cancel check, after
every new file is in place, so the signal lands at the latest moment there is. Every command
that writes outputs is held and signalled there (issue 33 rule 5: before it, corridor, plan,
plan --pairs, plan --matrix and export path kept their new outputs and exited 0).

The plan worker's malformed-input cases live in tests/plan/test_server_fuzz.py.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from overseec_core.errors import Cancelled
from overseec_core.io.transaction import ENV_PAUSE_BEFORE_COMMIT, output_transaction
from overseec_core.progress import CancelToken, NullProgress, check_cancelled

from . import test_hostile as hostile
from .test_hostile import LABELS, partial_files, snapshot

#: The hostile catalogue's scene (the sample, with a finished costmap run in c/), per test.
scene_template = hostile.scene_template
scene = hostile.scene

COSTMAP = ("costmap", *LABELS, "--prompt", "prefer trails, avoid the buildings", "--out", "c/costmap.tif")


def _run(scene: Path, argv: tuple[str, ...], pause_s: float | None = None) -> subprocess.Popen:
    """The console script on ``argv`` in ``scene``; held at its commit for ``pause_s`` (test hook)."""
    env = dict(os.environ)
    if pause_s is not None:
        env[ENV_PAUSE_BEFORE_COMMIT] = str(pause_s)
    return subprocess.Popen(
        [sys.executable, "-m", "overseec_core.console", "-q", *argv],
        cwd=scene,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )


def _start_paused(scene: Path, pause_s: float) -> subprocess.Popen:
    return _run(scene, COSTMAP, pause_s)


def _wait_for_commit(proc: subprocess.Popen, timeout: float = 120) -> None:
    """Until the command reports (test hook) that it is about to commit."""
    assert proc.stderr is not None
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        line = proc.stderr.readline()
        if not line:
            pytest.fail(f"the command ended before committing ({proc.wait()})")
        if "test hook: committing" in line:
            return
    pytest.fail("the command never reached its commit")


@pytest.mark.parametrize("signals", [(signal.SIGINT,), (signal.SIGINT, signal.SIGINT), (signal.SIGTERM,)])
def test_ctrl_c_just_before_the_commit_keeps_the_earlier_outputs(scene: Path, signals) -> None:
    before = snapshot(scene / "c")
    assert "costmap.tif" in before and "manifest.json" in before
    proc = _start_paused(scene, 1.5)
    _wait_for_commit(proc)
    # every new file is in place under its final name: the signal comes after the last rename
    assert snapshot(scene / "c")["costmap.tif"] != before["costmap.tif"]
    for sig in signals:
        proc.send_signal(sig)
        time.sleep(0.05)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "cancelled" in err and "Traceback" not in err, err
    assert snapshot(scene / "c") == before
    assert not partial_files(scene)


def test_without_a_signal_the_paused_command_commits(scene: Path) -> None:
    """The control: the hook only waits; the same command unsignalled replaces the outputs."""
    before = snapshot(scene / "c")
    proc = _start_paused(scene, 0.2)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err
    after = snapshot(scene / "c")
    assert after["costmap.tif"] != before["costmap.tif"] and not partial_files(scene)


def test_a_cancel_after_the_last_write_undoes_the_transaction(tmp_path: Path) -> None:
    """In process: the token set after the block's last check_cancelled still rolls back."""
    kept, new = tmp_path / "kept.txt", tmp_path / "new.txt"
    kept.write_text("earlier")
    progress = NullProgress(CancelToken())
    with pytest.raises(Cancelled):
        with output_transaction():
            check_cancelled(progress)  # the job polls its token (not yet set)
            from overseec_core.io.atomic import write_text_atomic

            write_text_atomic(kept, "later")
            write_text_atomic(new, "created")
            progress.token.cancel()  # Ctrl-C during the last writes
    assert kept.read_text() == "earlier" and not new.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.txt"]


def test_a_cancel_of_the_given_progress_counts_too(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    progress = NullProgress(CancelToken())
    from overseec_core.io.atomic import write_text_atomic

    with pytest.raises(Cancelled), output_transaction(progress):
        write_text_atomic(target, "x")
        progress.token.cancel()
    assert not target.exists()
    with output_transaction(NullProgress(CancelToken())):  # not cancelled: kept
        write_text_atomic(target, "y")
    assert target.read_text() == "y"


#: Every command that writes outputs (but costmap, above), as run on the scene (its outputs in o/): each is run once
#: unpaused (its outputs in place), then again, held at its commit and signalled (issue 33 rule 5).
WRITERS = {
    "corridor": ("corridor", "c/costmap.tif", *hostile.POINTS, "--within", "10", "--out", "o/corridor.tif"),
    "plan": ("plan", "c/costmap.tif", *hostile.POINTS, "--out", "o/path.geojson"),
    "plan --pairs": ("plan", "c/costmap.tif", "--pairs", "pairs.csv", "--out", "o/routes.gpkg"),
    "plan --matrix": ("plan", "c/costmap.tif", "--points", "points.csv", "--matrix", "o/m.csv"),
    "export costmap": ("export", "costmap", "c/costmap.tif", "--to", "costmap2d", "--out", "o/c2d.tif"),
    "export path": ("export", "path", "reference_route.geojson", "--to", "gpx", "--out", "o/p.gpx"),
    "vectorize": ("vectorize", "--labels", "sample_labels.tif", "--classes", "classes.json", "--out", "o/v.gpkg"),
    "eval": ("eval", "--costmap", "c/costmap.tif", "--pairs", "2", "--out", "o/e", "--no-plots"),
    "run": ("run", "sample.tif", *hostile.RUN, *hostile.POINTS, "--out", "o/run", "--no-eval"),
    "compare": (
        "compare",
        *LABELS,
        "--prompt",
        "prefer roads",
        "--prompt",
        "avoid roads",
        *hostile.POINTS,
        "--out",
        "o/cmp",
    ),
}


@pytest.mark.parametrize("name", list(WRITERS))
def test_every_writing_command_undoes_itself_on_a_signal_at_its_commit(scene: Path, name: str) -> None:
    (s_x, s_y), (g_x, g_y) = hostile.START, hostile.GOAL
    (scene / "pairs.csv").write_text(f"start_x,start_y,goal_x,goal_y\n{s_x},{s_y},{g_x},{g_y}\n")
    (scene / "points.csv").write_text(f"id,x,y\na,{s_x},{s_y}\nb,{g_x},{g_y}\n")
    first = _run(scene, WRITERS[name])
    _, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    before = snapshot(scene / "o")
    assert before, "the first run wrote nothing"
    proc = _run(scene, WRITERS[name], pause_s=1.5)
    _wait_for_commit(proc)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "cancelled" in err and "Traceback" not in err, err
    assert snapshot(scene / "o") == before
    assert not partial_files(scene)
