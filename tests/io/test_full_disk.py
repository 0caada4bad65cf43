"""A full disk never leaves a broken file (issue 13).

Each CLI command whose output does not fit fails with exit status 2 and one line on stderr
(``overseec: error: cannot write PATH: no space left on device``), leaves nothing under that
output's name, no hidden temporary file, and every file it did publish reads back whole.

Two ways to run out of room: a real 3 MB tmpfs (needs root and ``mount``; skipped otherwise)
filled to a chosen margin, and a file size limit (``RLIMIT_FSIZE`` with SIGXFSZ ignored, so
writes fail with EFBIG), which always runs.
"""

from __future__ import annotations

import hashlib
import json
import os
import resource
import signal
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
import rasterio

CLI = [sys.executable, "-m", "overseec_core.cli"]
#: Hidden files other code keeps in an output folder on purpose (the manifest's lock).
KNOWN_HIDDEN = {".manifest.lock"}
TMPFS_SIZE = 3 << 20


# --------------------------------------------------------------------------------------------
# Helpers (also used by tests/io/test_raster.py and tests/plan/test_export.py)
# --------------------------------------------------------------------------------------------


@contextmanager
def fsize_limit(limit: int) -> Iterator[None]:
    """In this process, make writes past ``limit`` bytes of any file fail with EFBIG.

    Lowers only the soft limit (the hard one stays, so it can be restored) and ignores SIGXFSZ,
    which would otherwise kill the process at the first write past the limit.
    """
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, old_handler)


def digest(path: Path) -> str:
    """SHA-256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def hidden_leftovers(folder: Path) -> list[str]:
    """Hidden files in ``folder`` that a writer left behind (temporary files, sidecars)."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") and p.name not in KNOWN_HIDDEN)


def assert_published_files_are_whole(folder: Path) -> None:
    """Every file under a final name reads back: rasters block by block, JSON parses."""
    for p in folder.iterdir():
        if p.name.startswith(".") or p.name == "fill":
            continue
        if p.suffix == ".tif":
            with rasterio.open(p) as ds:
                ds.read()
        elif p.suffix in (".json", ".geojson"):
            json.loads(p.read_text(encoding="utf-8"))


def run_cli(args: list[str], fsize: int | None = None) -> subprocess.CompletedProcess:
    """Run ``overseec -q ARGS`` in a subprocess, optionally under a file size limit."""

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))

    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run(
        [*CLI, "-q", *args],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
        preexec_fn=limit if fsize is not None else None,
    )


def assert_clean_failure(proc: subprocess.CompletedProcess, folder: Path, target: Path, reason: str) -> None:
    """Exit 2, one stderr line naming an output in ``folder`` and ``reason``; ``target`` absent,
    no leftovers, and whatever was published is whole."""
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"overseec: error: cannot write {folder}"), lines[0]
    assert lines[0].endswith(reason), lines[0]
    assert not target.exists()
    assert hidden_leftovers(folder) == []
    assert_published_files_are_whole(folder)


# --------------------------------------------------------------------------------------------
# Fixtures: inputs, reference sizes, a tiny tmpfs
# --------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def scene(tmp_path_factory) -> dict:
    """The sample scene, a costmap of it and the sizes of every output when there is room."""
    root = tmp_path_factory.mktemp("scene")
    assert run_cli(["sample", "--out", str(root), "--size", "1024"]).returncode == 0
    ref = root / "ref"
    ref.mkdir()
    costmap_args = [
        "costmap",
        "--labels",
        str(root / "sample_labels.tif"),
        "--classes",
        str(root / "classes.json"),
        "--prompt",
        "prefer roads, avoid water",
    ]
    proc = run_cli([*costmap_args, "--out", str(ref / "costmap.tif")])
    assert proc.returncode == 0, proc.stderr
    with rasterio.open(ref / "costmap.tif") as ds:
        b = ds.bounds
        dx, dy = (b.right - b.left) / 20, (b.top - b.bottom) / 20
    plan_args = [
        "plan",
        str(ref / "costmap.tif"),
        "--start",
        str(b.left + dx),
        str(b.top - dy),
        "--goal",
        str(b.right - dx),
        str(b.bottom + dy),
    ]
    plan_ref = root / "plan_ref"
    plan_ref.mkdir()
    proc = run_cli([*plan_args, "--out", str(plan_ref / "path.geojson"), "--cumulative", str(plan_ref / "cum.tif")])
    assert proc.returncode == 0, proc.stderr
    return {
        "root": root,
        "costmap_args": costmap_args,
        "plan_args": plan_args,
        "sizes": {p.name: p.stat().st_size for p in ref.iterdir()},
        "plan_sizes": {p.name: p.stat().st_size for p in plan_ref.iterdir()},
    }


@pytest.fixture
def tiny_tmpfs(tmp_path: Path) -> Iterator[Path]:
    """A 3 MB tmpfs mounted in tmp_path (root only), unmounted afterwards."""
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    mnt = tmp_path / "tmpfs"
    mnt.mkdir()
    proc = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={TMPFS_SIZE}", "tmpfs", str(mnt)], capture_output=True, text=True
    )
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.strip() or proc.returncode}")
    try:
        yield mnt
    finally:
        if subprocess.run(["umount", str(mnt)], capture_output=True).returncode != 0:
            subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


def fill(folder: Path, leave: int) -> None:
    """Fill the file system of ``folder`` until about ``leave`` bytes are free."""
    st = os.statvfs(folder)
    free = st.f_bavail * st.f_frsize
    with open(folder / "fill", "wb") as f:
        f.write(b"\0" * max(0, free - leave))
    st = os.statvfs(folder)
    assert abs(st.f_bavail * st.f_frsize - leave) <= 8192


# --------------------------------------------------------------------------------------------
# A real full disk
# --------------------------------------------------------------------------------------------


def test_costmap_on_a_full_tmpfs_fails_in_one_line_and_leaves_no_costmap(scene, tiny_tmpfs) -> None:
    # Room for the lethal sidecar, not for the costmap.
    fill(tiny_tmpfs, 8192 + scene["sizes"]["costmap.tif"] // 2)
    target = tiny_tmpfs / "costmap.tif"
    proc = run_cli([*scene["costmap_args"], "--out", str(target)])
    assert_clean_failure(proc, tiny_tmpfs, target, "no space left on device")


def test_plan_cumulative_on_a_full_tmpfs_fails_in_one_line(scene, tiny_tmpfs) -> None:
    # Room for the GeoJSON, not for the cost-distance raster.
    sizes = scene["plan_sizes"]
    fill(tiny_tmpfs, 16384 + sizes["path.geojson"] + sizes["cum.tif"] // 2)
    target = tiny_tmpfs / "cum.tif"
    proc = run_cli(
        [
            *scene["plan_args"],
            "--out",
            str(tiny_tmpfs / "path.geojson"),
            "--cumulative",
            str(target),
            "--native-crs",
            "--pixels",
        ]
    )
    assert_clean_failure(proc, tiny_tmpfs, target, "no space left on device")


@pytest.mark.parametrize("leave_kib", [0, 12, 24, 40])
def test_costmap_at_any_fill_level_publishes_only_whole_files(scene, tiny_tmpfs, leave_kib: int) -> None:
    """Wherever the disk runs out, what is published is whole and nothing is left over."""
    fill(tiny_tmpfs, leave_kib * 1024)
    proc = run_cli([*scene["costmap_args"], "--out", str(tiny_tmpfs / "costmap.tif")])
    if proc.returncode != 0:
        lines = proc.stderr.strip().splitlines()
        assert proc.returncode == 2 and len(lines) == 1, proc.stderr
        assert lines[0].startswith("overseec: error: cannot write ")
        assert lines[0].endswith("no space left on device")
    assert hidden_leftovers(tiny_tmpfs) == []
    assert_published_files_are_whole(tiny_tmpfs)


# --------------------------------------------------------------------------------------------
# A file size limit (always runs)
# --------------------------------------------------------------------------------------------

EFBIG_REASON = "file too large for the file system or this process's file size limit"


def test_costmap_over_the_file_size_limit_fails_in_one_line(scene, tmp_path: Path) -> None:
    sizes = scene["sizes"]
    others = max(sizes["lethal.tif"], sizes["manifest.json"], sizes["costmap.program.txt"])
    limit = (sizes["costmap.tif"] + others) // 2
    assert others + 1024 < limit  # only the costmap is too big
    target = tmp_path / "costmap.tif"
    proc = run_cli([*scene["costmap_args"], "--out", str(target)], fsize=limit)
    assert_clean_failure(proc, tmp_path, target, EFBIG_REASON)
    assert f"cannot write {target}:" in proc.stderr


def test_plan_cumulative_over_the_file_size_limit_fails_in_one_line(scene, tmp_path: Path) -> None:
    sizes = scene["plan_sizes"]
    limit = sizes["cum.tif"] // 2
    assert max(sizes["path.geojson"], sizes["manifest.json"]) + 1024 < limit
    target = tmp_path / "cum.tif"
    proc = run_cli(
        [*scene["plan_args"], "--out", str(tmp_path / "path.geojson"), "--cumulative", str(target)], fsize=limit
    )
    assert_clean_failure(proc, tmp_path, target, EFBIG_REASON)
    assert f"cannot write {target}:" in proc.stderr
    # the plan's outputs are one transaction: the path written before the failure is taken back
    assert not (tmp_path / "path.geojson").exists()


def test_a_failed_costmap_keeps_the_previous_one_byte_for_byte(scene, tmp_path: Path) -> None:
    target = tmp_path / "costmap.tif"
    proc = run_cli([*scene["costmap_args"], "--out", str(target)])
    assert proc.returncode == 0, proc.stderr
    before = digest(target)
    proc = run_cli(
        [*scene["costmap_args"], "--out", str(target)],
        fsize=(scene["sizes"]["costmap.tif"] + scene["sizes"]["manifest.json"]) // 2,
    )
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert digest(target) == before
    assert hidden_leftovers(tmp_path) == []
