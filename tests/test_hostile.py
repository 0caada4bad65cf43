"""A catalogue of hostile and careless inputs, each run through the real `overseec` command.

Every case runs the console script in a subprocess on a copy of the sample scene and asserts
what a user must be able to rely on whatever they typed:

- the exit status (2 for a user or input problem, 130 when cancelled), never a traceback;
- exactly one line on stderr, ``overseec: error: ...``, saying what is wrong (no GDAL chatter);
- no file under any of the command's final output names, and no hidden partial file left;
- every file that was there before is byte-for-byte unchanged (SHA-256 before and after);
- no secret (the API key, a URL password) in any stream or file.

Cases with their own machinery (LLM servers, signals, concurrent writers, full disks) follow the
table; the full-disk cases live in tests/io/test_full_disk.py, the LLM client's in
tests/interpret/test_llm_hostile.py.
"""

from __future__ import annotations

import hashlib
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.io.manifest import RunDir

REPO = Path(__file__).resolve().parent.parent
SAMPLE = REPO / "resources" / "sample"
#: Inside the sample (EPSG:32633, 1024 x 1024 px at 0.5 m).
START = ("534010", "5212990")
GOAL = ("534500", "5212500")
POINTS = ("--start", *START, "--goal", *GOAL)
SECRET = "sk-hostile-test-4f1c9e"
URL_PASSWORD = "pw-hostile-77ab"


def overseec(
    *argv: str, cwd: Path, env: dict | None = None, memory_cap: int | None = None, timeout: float = 120
) -> subprocess.CompletedProcess:
    """The console script, as a user runs it (quiet: stderr holds errors only)."""

    def limit() -> None:
        if memory_cap is not None:
            resource.setrlimit(resource.RLIMIT_AS, (memory_cap, memory_cap))

    return subprocess.run(
        [sys.executable, "-m", "overseec_core.console", "-q", *argv],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**os.environ, **(env or {})},
        preexec_fn=limit,
    )


def snapshot(folder: Path) -> dict[str, str]:
    """SHA-256 of every file under ``folder``, by relative path."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def partial_files(folder: Path) -> list[str]:
    return [
        str(p.relative_to(folder))
        for p in folder.rglob(".*")
        if ".partial" in p.name or p.name.endswith((".cog.tif", ".tmp"))
    ]


def assert_one_line_error(done: subprocess.CompletedProcess, status: int, says: str) -> None:
    lines = done.stderr.strip().splitlines()
    assert done.returncode == status, (done.returncode, done.stderr[-2000:])
    assert len(lines) == 1, done.stderr[-2000:]
    assert lines[0].startswith("overseec: error: "), lines[0]
    assert says.lower() in lines[0].lower(), lines[0]


# --------------------------------------------------------------------------------------------
# The scene: the sample plus the bad inputs the cases use (made once, copied per case)
# --------------------------------------------------------------------------------------------


def _profile(src: Path) -> dict:
    with rasterio.open(src) as ds:
        return dict(ds.profile)


def _write(path: Path, data: np.ndarray, base: dict, **changes) -> None:
    arr = data[None] if data.ndim == 2 else data
    profile = {
        **base,
        "count": arr.shape[0],
        "dtype": arr.dtype.name,
        "height": arr.shape[1],
        "width": arr.shape[2],
        **changes,
    }
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(arr)


def _huge_vrt(path: Path, source: Path, side: int, dtype: str = "Byte") -> None:
    """A valid VRT of ``side`` x ``side`` pixels over a small raster (a few bytes on disk)."""
    with rasterio.open(source) as ds:
        gt, crs, w, h = ds.transform.to_gdal(), ds.crs.to_wkt(), ds.width, ds.height
    path.write_text(f"""<VRTDataset rasterXSize="{side}" rasterYSize="{side}">
  <SRS>{crs}</SRS>
  <GeoTransform>{", ".join(map(str, gt))}</GeoTransform>
  <VRTRasterBand dataType="{dtype}" band="1">
    <SimpleSource><SourceFilename relativeToVRT="1">{source.name}</SourceFilename>
      <SourceBand>1</SourceBand>
      <SrcRect xOff="0" yOff="0" xSize="{w}" ySize="{h}"/>
      <DstRect xOff="0" yOff="0" xSize="{w}" ySize="{h}"/></SimpleSource>
  </VRTRasterBand>
</VRTDataset>
""")


@pytest.fixture(scope="module")
def scene_template(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("hostile_scene")
    for name in ("sample.tif", "sample_labels.tif", "classes.json", "reference_route.geojson"):
        shutil.copy(SAMPLE / name, d / name)
    img, lab = _profile(d / "sample.tif"), _profile(d / "sample_labels.tif")
    with rasterio.open(d / "sample.tif") as ds:
        rgb = ds.read()
    (d / "c").mkdir()
    done = overseec(
        "costmap",
        "--labels",
        "sample_labels.tif",
        "--classes",
        "classes.json",
        "--prompt",
        "prefer roads, avoid water",
        "--out",
        "c/costmap.tif",
        cwd=d,
    )
    assert done.returncode == 0, done.stderr
    _write(d / "two_band.tif", (rgb[:2] / 255).astype("float32"), img)
    _write(d / "class_like.tif", np.ones((1024, 1024), "uint8"), lab)
    _write(d / "costs_above_one.tif", np.full((1024, 1024), 3.5, "float32"), lab, nodata=None)
    _write(d / "small.tif", rgb[:, :512, :512], img)
    _write(d / "one_pixel.tif", rgb[:, :1, :1], img)
    _write(d / "nan_only.tif", np.full((3, 1024, 1024), np.nan, "float32"), img, nodata=None)
    raw = (d / "sample.tif").read_bytes()
    (d / "truncated.tif").write_bytes(raw[: len(raw) // 3])
    raw = (d / "sample_labels.tif").read_bytes()
    (d / "truncated_labels.tif").write_bytes(raw[: len(raw) // 2])
    (d / "other_classes.json").write_text(json.dumps({"41": "road", "42": "water"}))
    # one id matches by chance (1); the others are another dataset's, and the raster's 2..7 unnamed
    (d / "mostly_other_classes.json").write_text(
        json.dumps({"0": "background", "1": "road", "41": "water", "42": "tree"})
    )
    _huge_vrt(d / "huge_labels.vrt", d / "sample_labels.tif", 2_000_000)
    for name in ("r", "h", "e", "k", "p"):
        (d / name).mkdir()
    shutil.copy(d / "sample.tif", d / "r" / "costmap.tif")
    shutil.copy(d / "reference_route.geojson", d / "r" / "path.geojson")
    (d / "r" / "evaluation").mkdir()
    shutil.copy(d / "reference_route.geojson", d / "r" / "evaluation" / "paths.geojson")
    return d


@pytest.fixture
def scene(scene_template: Path, tmp_path: Path) -> Path:
    d = tmp_path / "scene"
    shutil.copytree(scene_template, d)
    return d


# --------------------------------------------------------------------------------------------
# The table
# --------------------------------------------------------------------------------------------

LABELS = ("--labels", "sample_labels.tif", "--classes", "classes.json")
RUN = ("--prompt", "prefer roads", "--offline", *LABELS)


@dataclass(frozen=True)
class Case:
    """One hostile input: the command, what it must say, and the outputs it must not leave."""

    id: str
    argv: tuple[str, ...]
    says: str
    outputs: tuple[str, ...] = ()
    status: int = 2
    env: dict = field(default_factory=dict)
    memory_cap: int | None = None


GIB = 1 << 30
LLM_ENV = {"OVERSEEC_LLM_URL": "http://127.0.0.1:9/v1", "OVERSEEC_LLM_MODEL": "m"}

CASES = [
    # inputs that would be overwritten
    Case("plan-out-is-the-lethal-sidecar", ("plan", "c/costmap.tif", *POINTS, "--out", "c/lethal.tif"), "is the input"),
    Case("plan-out-is-the-costmap", ("plan", "c/costmap.tif", *POINTS, "--out", "c/costmap.tif"), "is the input"),
    Case(
        "costmap-out-is-the-labels",
        ("costmap", *LABELS, "--prompt", "prefer roads", "--out", "sample_labels.tif"),
        "is the input",
    ),
    Case(
        "run-image-named-costmap-in-out",
        ("run", "r/costmap.tif", *RUN[:3], "--out", "r"),
        "where the run writes",
        ("r/manifest.json", "r/lethal.tif"),
    ),
    Case(
        "run-reference-named-path-in-out",
        ("run", "sample.tif", *RUN, *POINTS, "--reference", "r/path.geojson", "--out", "r"),
        "where the run writes",
        ("r/manifest.json", "r/lethal.tif"),
    ),
    Case(
        "run-reference-named-like-an-evaluation-output",
        ("run", "sample.tif", *RUN, *POINTS, "--reference", "r/evaluation/paths.geojson", "--out", "r"),
        "where the run writes",
        ("r/manifest.json", "r/lethal.tif"),
    ),
    # devices and oversized text inputs (under a memory cap: no MemoryError traceback)
    Case(
        "program-is-dev-zero",
        ("costmap", *LABELS, "--program", "/dev/zero", "--out", "e/c.tif"),
        "larger than",
        ("e/c.tif",),
        memory_cap=2 * GIB,
    ),
    Case(
        "prompt-file-is-dev-zero",
        ("interpret", "--offline", "--prompt-file", "/dev/zero", "--out", "e/i.json"),
        "larger than",
        ("e/i.json",),
        memory_cap=2 * GIB,
    ),
    Case(
        "classes-is-dev-zero",
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "/dev/zero",
            "--prompt",
            "prefer roads",
            "--out",
            "e/c.tif",
        ),
        "larger than",
        ("e/c.tif",),
        memory_cap=2 * GIB,
    ),
    Case(
        "program-is-binary",
        ("costmap", *LABELS, "--program", "c/lethal.tif", "--out", "e/c.tif"),
        "not UTF-8",
        ("e/c.tif",),
    ),
    # sizes
    Case(
        "two-million-pixel-square-labels",
        (
            "costmap",
            "--labels",
            "huge_labels.vrt",
            "--classes",
            "classes.json",
            "--prompt",
            "prefer roads",
            "--out",
            "h/c.tif",
        ),
        "pixel budget",
        ("h/c.tif",),
    ),
    Case(
        "pixel-budget-from-the-command-line",
        ("--max-pixels", "1000", "costmap", *LABELS, "--prompt", "prefer roads", "--out", "h/c.tif"),
        "--max-pixels 1048576",
        ("h/c.tif",),
    ),
    Case(
        "pixel-budget-not-a-number",
        ("--max-pixels", "lots", "costmap", *LABELS, "--prompt", "prefer roads", "--out", "h/c.tif"),
        "not a number",
        ("h/c.tif",),
    ),
    Case(
        "plan-pixel-budget",
        ("--max-pixels", "1e5", "plan", "c/costmap.tif", *POINTS, "--out", "p/p.geojson"),
        "pixel budget",
        ("p/p.geojson",),
    ),
    # wrong kinds of input
    Case(
        "rgb-photo-as-labels",
        (
            "costmap",
            "--labels",
            "sample.tif",
            "--classes",
            "classes.json",
            "--prompt",
            "prefer roads",
            "--out",
            "k/c.tif",
        ),
        "3 bands",
        ("k/c.tif",),
    ),
    Case(
        "classes-none-of-which-occur",
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "other_classes.json",
            "--prompt",
            "prefer roads",
            "--out",
            "k/c.tif",
        ),
        "none of the class ids",
        ("k/c.tif",),
    ),
    Case(
        "classes-most-of-which-miss-the-labels",
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "mostly_other_classes.json",
            "--prompt",
            "prefer roads",
        )
        + ("--out", "k/c.tif"),
        "2 of the 3 class ids in classes.json (41, 42) do not occur in the raster, which holds ids classes.json "
        "does not name (2, 3, 4, 5, 6, 7; ids found: 1, 2, 3, 4, 5, 6, 7)",
        ("k/c.tif",),
    ),
    Case(
        "costmap-out-below-a-file",
        ("costmap", *LABELS, "--prompt", "prefer roads", "--out", "classes.json/c.tif"),
        "cannot write classes.json/c.tif: classes.json is a file, not a folder",
    ),
    Case(
        "refused-plan-takes-back-the-folders-it-made",
        ("plan", "sample.tif", *POINTS, "--out", "new/deeper/p.geojson", "--cumulative", "other/c.tif"),
        "3 bands",
        ("new", "other"),
    ),
    Case(
        "lon-lat-points-without-crs",
        ("plan", "c/costmap.tif", "--start", "15.44", "47.07", "--goal", "15.45", "47.06", "--out", "p/p.geojson"),
        "is outside the costmap costmap.tif (bounds x 534000..534512, y 5212488..5213000); these look like "
        "longitude/latitude; add --crs EPSG:4326",
        ("p/p.geojson",),
    ),
    Case("rgb-photo-as-costmap", ("plan", "sample.tif", *POINTS, "--out", "k/p.geojson"), "3 bands", ("k/p.geojson",)),
    Case("two-band-costmap", ("plan", "two_band.tif", *POINTS, "--out", "k/p.geojson"), "2 bands", ("k/p.geojson",)),
    Case(
        "class-raster-as-costmap",
        ("plan", "class_like.tif", *POINTS, "--out", "k/p.geojson"),
        "holds uint8",
        ("k/p.geojson",),
    ),
    Case(
        "costs-outside-the-scale",
        ("plan", "costs_above_one.tif", *POINTS, "--out", "k/p.geojson"),
        "in [0, 1]",
        ("k/p.geojson",),
    ),
    Case(
        "band-beyond-the-costmap",
        ("plan", "two_band.tif", "--band", "3", *POINTS, "--out", "k/p.geojson"),
        "has 2 band",
        ("k/p.geojson",),
    ),
    Case(
        "run-image-off-the-labels-grid",
        ("run", "small.tif", *RUN, "--out", "k"),
        "not on the grid",
        ("k/manifest.json", "k/costmap.tif"),
    ),
    Case(
        "run-one-pixel-image",
        ("run", "one_pixel.tif", *RUN, "--out", "k"),
        "not on the grid",
        ("k/manifest.json", "k/costmap.tif"),
    ),
    Case(
        "run-truncated-image",
        ("run", "truncated.tif", *RUN, "--out", "k"),
        "truncated",
        ("k/manifest.json", "k/costmap.tif"),
    ),
    Case(
        "run-nan-only-image",
        ("run", "nan_only.tif", *RUN, "--out", "k"),
        "no valid pixel",
        ("k/manifest.json", "k/costmap.tif"),
    ),
    Case(
        "truncated-labels",
        (
            "costmap",
            "--labels",
            "truncated_labels.tif",
            "--classes",
            "classes.json",
            "--prompt",
            "prefer roads",
            "--out",
            "k/c.tif",
        ),
        "truncated",
        ("k/c.tif",),
    ),
    # noise: one line, not GDAL's or PROJ's
    Case(
        "unknown-points-crs",
        ("plan", "c/costmap.tif", "--crs", "EPSG:99999999", *POINTS, "--out", "p/p.geojson"),
        "not a CRS",
        ("p/p.geojson",),
    ),
    Case(
        "image-is-not-a-raster",
        ("run", "classes.json", *RUN, "--out", "k"),
        "not a readable raster",
        ("k/manifest.json",),
    ),
    # LLM settings
    *[
        Case(
            f"llm-timeout-{value}",
            ("interpret", "prefer roads", "--out", "e/i.json"),
            "timeout",
            ("e/i.json",),
            env={**LLM_ENV, "OVERSEEC_LLM_TIMEOUT": value},
        )
        for value in ("inf", "1e300", "nan", "-3", "0")
    ],
    Case(
        "llm-retries-not-a-number",
        ("interpret", "prefer roads", "--out", "e/i.json"),
        "RETRIES",
        ("e/i.json",),
        env={**LLM_ENV, "OVERSEEC_LLM_RETRIES": "many"},
    ),
]


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_hostile_input(case: Case, scene: Path) -> None:
    before = snapshot(scene)
    done = overseec(*case.argv, cwd=scene, env=case.env, memory_cap=case.memory_cap)
    assert_one_line_error(done, case.status, case.says)
    assert "Traceback" not in done.stdout + done.stderr
    for name in case.outputs:
        assert not (scene / name).exists(), f"{name} was written"
    assert not partial_files(scene)
    after = snapshot(scene)
    changed = [name for name, digest in before.items() if after.get(name) != digest]
    assert not changed, f"inputs changed: {changed}"
    # a refused command leaves nothing new behind
    assert set(after) == set(before)


def test_the_catalogue_covers_the_issue() -> None:
    """The hostile-input issue's classes of failure each have cases (at least the ones it lists)."""
    ids = " ".join(c.id for c in CASES)
    for needle in (
        "lethal-sidecar",
        "image-named-costmap",
        "reference-named-path",
        "dev-zero",
        "two-million",
        "rgb-photo-as-labels",
        "rgb-photo-as-costmap",
        "two-band",
        "off-the-labels-grid",
        "one-pixel",
        "truncated-image",
        "nan-only",
        "none-of-which-occur",
        "most-of-which-miss",
        "llm-timeout-inf",
        "llm-timeout-1e300",
        "crs",
    ):
        assert needle in ids, needle
    assert len(CASES) >= 30


# --------------------------------------------------------------------------------------------
# Secrets: an LLM endpoint that echoes what it is sent
# --------------------------------------------------------------------------------------------


class _EchoUnauthorised(BaseHTTPRequestHandler):
    """Answers 401 with every request header echoed back in the body, as careless servers do."""

    def do_POST(self) -> None:
        length = int(self.headers.get("Content-Length") or 0)
        self.rfile.read(length)
        body = json.dumps({"error": {"message": f"bad credentials: {dict(self.headers)}"}}).encode()
        self.send_response(401)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args) -> None:
        pass


@pytest.fixture
def echo_server():
    server = ThreadingHTTPServer(("127.0.0.1", 0), _EchoUnauthorised)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield server.server_address[1]
    server.shutdown()
    server.server_close()


@pytest.mark.parametrize("secret", ["api-key", "url-password"])
@pytest.mark.parametrize("command", ["interpret", "run"])
def test_no_secret_in_any_stream_or_file(command: str, secret: str, scene: Path, echo_server: int) -> None:
    """The endpoint answers 401 with the request headers echoed: neither the key nor a password
    in the URL may reach stderr, stdout, the manifest or any other file."""
    env = {"OVERSEEC_LLM_RETRIES": "0"}
    if secret == "api-key":
        url = f"http://127.0.0.1:{echo_server}/v1"
        env["OVERSEEC_LLM_API_KEY"] = SECRET
    else:
        url = f"http://user:{URL_PASSWORD}@127.0.0.1:{echo_server}/v1"
    if command == "interpret":
        argv = ("interpret", "prefer roads", "--llm-url", url, "--llm-model", "m", "--out", "e/i.json")
    else:
        argv = (
            "run",
            "sample.tif",
            "--prompt",
            "prefer roads",
            *LABELS,
            "--llm-url",
            url,
            "--llm-model",
            "m",
            "--out",
            "e",
        )
    done = overseec(*argv, cwd=scene, env=env)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "401" in done.stderr
    for secret in (SECRET, URL_PASSWORD):
        assert secret not in done.stdout + done.stderr
        for path in scene.rglob("*"):
            if path.is_file():
                assert secret.encode() not in path.read_bytes(), path


# --------------------------------------------------------------------------------------------
# Signals
# --------------------------------------------------------------------------------------------


def _start(*argv: str, cwd: Path) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "overseec_core.console", "-q", *argv],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def test_ctrl_c_while_starting_is_one_line(scene: Path) -> None:
    proc = _start("costmap", *LABELS, "--prompt", "prefer roads", "--out", "k/c.tif", cwd=scene)
    time.sleep(0.3)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    if proc.returncode == 0:
        pytest.skip("the command finished before the signal")
    assert proc.returncode == 130 and len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err and not (scene / "k" / "c.tif").exists()


@pytest.mark.parametrize(
    "signals",
    [(signal.SIGINT,), (signal.SIGINT, signal.SIGINT), (signal.SIGTERM, signal.SIGINT, signal.SIGINT)],
    ids=["once", "twice", "term-then-twice"],
)
def test_cancel_during_costmap_is_clean_and_idempotent(scene: Path, signals) -> None:
    """However often the user presses Ctrl-C, the command ends cancelled with one line, no
    partial file and no output under the final names."""
    proc = _start(
        "costmap",
        *LABELS,
        "--prompt",
        "stay 40 m from the buildings, prefer roads",
        "--block-size",
        "64",
        "--out",
        "k/c.tif",
        cwd=scene,
    )
    _wait_for_begin(scene / "k", proc)
    for sig in signals:
        proc.send_signal(sig)
        time.sleep(0.05)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert len(err.strip().splitlines()) == 1 and "cancelled" in err, err
    assert not (scene / "k" / "c.tif").exists() and not (scene / "k" / "c.lethal.tif").exists()
    assert not partial_files(scene)


def _wait_for_begin(folder: Path, proc: subprocess.Popen, timeout: float = 60) -> None:
    """Until the command has started writing into ``folder`` (its first hidden temporary file)."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if proc.poll() is not None:
            pytest.fail(f"finished before the signal: {proc.stderr.read()}")
        if any(p.name.startswith(".") and ".partial" in p.name for p in folder.iterdir()):
            return
        time.sleep(0.01)
    pytest.fail("the command never started writing")


def test_cancelled_run_leaves_the_folder_as_it_was(scene: Path) -> None:
    """A run into a folder that already holds a finished run, cancelled half-way, leaves every
    file of the earlier run as it was (and adds none)."""
    argv = (
        "run",
        "sample.tif",
        "--prompt",
        "prefer roads, avoid water",
        *LABELS[:4],
        "--offline",
        *POINTS,
        "--pairs",
        "40",
        "--out",
        "k",
    )
    first = overseec(*argv, cwd=scene)
    assert first.returncode == 0, first.stderr
    before = snapshot(scene / "k")
    second = _start(*argv[:3], "prefer trails, avoid the buildings", *argv[4:], cwd=scene)
    time.sleep(2.0)  # inside the run: the costmap and path are being replaced
    second.send_signal(signal.SIGINT)
    _, err = second.communicate(timeout=120)
    if second.returncode == 0:
        pytest.skip("the run finished before the signal")
    assert second.returncode == 130, err
    assert snapshot(scene / "k") == before
    assert not partial_files(scene)


# --------------------------------------------------------------------------------------------
# Concurrent writers of one folder
# --------------------------------------------------------------------------------------------


def test_interleaved_manifest_writers_lose_nothing(tmp_path: Path) -> None:
    """Two commands that load the manifest before either saves both end up in it."""
    first = RunDir(tmp_path, command="costmap", args={"n": 1})
    second = RunDir(tmp_path, command="plan", args={"n": 2})
    first.set("costmap", {"file": "c.tif"})
    second.set("plan", {"cost": 1.0})
    with first.stage("costmap"):
        pass
    with second.stage("plan"):
        pass
    data = json.loads((tmp_path / "manifest.json").read_text())
    assert [c["command"] for c in data["commands"]] == ["costmap", "plan"]
    assert data["costmap"] == {"file": "c.tif"} and data["plan"] == {"cost": 1.0}
    assert set(data["stages"]) == {"costmap", "plan"}


def test_concurrent_commands_keep_every_manifest_entry(scene: Path) -> None:
    procs = [
        _start("costmap", *LABELS, "--prompt", "prefer roads", "--out", f"k/c{i}.tif", cwd=scene) for i in range(4)
    ]
    for proc in procs:
        _, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
    data = json.loads((scene / "k" / "manifest.json").read_text())
    outs = sorted(c["args"]["out"] for c in data["commands"])
    assert outs == [f"k/c{i}.tif" for i in range(4)]
    layer_inputs = [k for k in data["inputs"] if k.startswith("costmap_layer")]
    assert layer_inputs


# --------------------------------------------------------------------------------------------
# Provenance of every input
# --------------------------------------------------------------------------------------------


def test_eval_records_the_image_with_its_hash(scene: Path) -> None:
    done = overseec(
        "eval",
        *LABELS,
        "--costmap",
        "c/costmap.tif",
        "--image",
        "sample.tif",
        "--ranks",
        "road=1",
        "--pairs",
        "3",
        "--out",
        "ev",
        cwd=scene,
    )
    assert done.returncode == 0, done.stderr
    entry = json.loads((scene / "ev" / "manifest.json").read_text())["inputs"]["eval_image"]
    assert entry["sha256"] == hashlib.sha256((scene / "sample.tif").read_bytes()).hexdigest()
