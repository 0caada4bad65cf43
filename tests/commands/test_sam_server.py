"""`overseec sam-server`, the real worker process: open a view, prompt, apply, ping; bad requests get
one error line each and the worker keeps serving."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio

pytest.importorskip("torch")
pytest.importorskip("transformers")

from ..locate.builders import save_sam
from ..locate.conftest import write_geotiff
from ..locate.test_interactive import COLS, ROWS, pixel_xy, write_segment_dir

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def tiny_sam(tmp_path_factory) -> Path:
    return save_sam(tmp_path_factory.mktemp("models") / "tiny-sam")


class Worker:
    """One `overseec sam-server` process driven line by line."""

    def __init__(self) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "overseec_core.cli", "sam-server", "--device", "cpu"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            cwd=REPO,
        )
        self.ids = 0

    def line(self, text: str) -> dict:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(text + "\n")
        self.proc.stdin.flush()
        answer = self.proc.stdout.readline()
        assert answer, self.proc.stderr.read() if self.proc.stderr else "no answer"
        return json.loads(answer)

    def send(self, op: str, **fields) -> dict:
        self.ids += 1
        answer = self.line(json.dumps({"id": self.ids, "op": op, **fields}))
        assert answer["id"] == self.ids
        return answer

    def close(self) -> int:
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        code = self.proc.wait(timeout=30)
        for stream in (self.proc.stdout, self.proc.stderr):
            if stream is not None:
                stream.close()
        return code


@pytest.fixture
def scene(tmp_path: Path):
    image = write_geotiff(tmp_path / "image.tif", 200, 150, nodata_box=(30, 45, 40, 60))
    folder = write_segment_dir(tmp_path / "seg", image)
    with rasterio.open(image) as ds:
        t = ds.transform
    (x0, y1), (x1, y0) = t * (COLS[0], ROWS[0]), t * (COLS[1], ROWS[1])
    return image, folder, t, [x0, y0, x1, y1]


@pytest.fixture
def worker():
    w = Worker()
    yield w
    if w.proc.poll() is None:
        w.proc.kill()
        w.close()


def polygon_area(rings) -> float:
    def ring(r):
        xy = np.asarray(r)
        return 0.5 * abs(np.dot(xy[:-1, 0], xy[1:, 1]) - np.dot(xy[1:, 0], xy[:-1, 1]))

    return ring(rings[0]) - sum(ring(r) for r in rings[1:])


def test_open_prompt_apply_and_ping_through_the_worker(worker, scene, tiny_sam) -> None:
    image, folder, t, bounds = scene
    assert worker.send("ping")["version"] == 1
    view = dict(image=str(image), segment_dir=str(folder), bounds=bounds, model=str(tiny_sam))
    opened = worker.send("open", **view)
    assert opened["ok"] and opened["entities"] == ["road", "water"] and opened["window"] == [40, 30, 96, 80]
    assert opened["embed_ms"] > 0 and opened["reused"] is False and opened["mask_file"] == "masks.tif"
    assert worker.send("open", **view)["reused"] is True  # the same view is not embedded again
    assert worker.send("ping")["embeddings"] == 1

    box = [*(t * (COLS[0] + 10, ROWS[0] + 60)), *(t * (COLS[0] + 60, ROWS[0] + 10))]
    click = dict(entity="water", points=[list(pixel_xy(t, 70, 60))], labels=[0], box=box, mode="add")
    answer = worker.send("prompt", **click)
    assert answer["ok"] and answer["added_px"] > 0 and answer["removed_px"] == 0 and not answer["truncated"]
    assert answer["outline_scale"] == 1  # a smooth enough mask: its exact outline
    pixel_area = abs(t.a * t.e)
    assert sum(polygon_area(p) for p in answer["polygons"]) == pytest.approx(answer["area_px"] * pixel_area)
    candidate = worker.send("prompt", **click, show="candidate")
    assert sum(polygon_area(p) for p in candidate["polygons"]) == pytest.approx(answer["candidate_px"] * pixel_area)
    assert answer["decoder_ms"] > 0 and answer["ms"] >= answer["decoder_ms"]

    with rasterio.open(folder / "masks.tif") as ds:
        before = ds.read(2)
    applied = worker.send("apply", **click)
    assert applied["ok"] and applied["pixels_added"] == answer["added_px"] and applied["files"][0] == "masks.tif"
    with rasterio.open(folder / "masks.tif") as ds:
        after = ds.read(2)
    assert int((after != before).sum()) == answer["added_px"]
    edits = json.loads((folder / "manifest.json").read_text())["mask_edits"]
    assert list(edits) == [applied["edit"]] and edits[applied["edit"]]["entity"] == "water"
    again = worker.send("prompt", **click)  # the worker sees the applied mask
    assert again["added_px"] == 0 and again["area_px"] == answer["area_px"]
    assert worker.send("close")["closed"] is True
    assert worker.send("shutdown")["ok"]
    assert worker.proc.wait(timeout=30) == 0


def test_bad_requests_get_one_error_line_and_the_worker_keeps_serving(worker, scene, tiny_sam) -> None:
    image, folder, t, bounds = scene

    def refused(answer: dict, text: str) -> None:
        assert answer["ok"] is False and text in answer["error"] and "\n" not in answer["error"], answer

    refused(worker.line("this is not json"), "not a JSON request")
    refused(worker.line('{"id": 1, "op": "prompt", "points": [[NaN, 1]]}'), "finite")
    refused(worker.send("paint"), "unknown op 'paint'")
    refused(worker.send("prompt", entity="road", points=[[0, 0]]), 'send "open" first')
    refused(worker.send("open", image=str(image), segment_dir=str(folder), bounds=bounds[:3]), "bounds")
    refused(
        worker.send("open", image=str(image), segment_dir=str(folder), bounds=bounds, model="no/such-sam"),
        "no/such-sam",
    )
    huge = [-1e308, -1e308, 1e308, 1e308]  # finite, but past any map (issue 33 rule 4)
    refused(worker.send("open", image=str(image), segment_dir=str(folder), bounds=huge, model=str(tiny_sam)), "within")
    far = [bounds[0] + 1e5, bounds[1], bounds[2] + 1e5, bounds[3]]
    refused(worker.send("open", image=str(image), segment_dir=str(folder), bounds=far, model=str(tiny_sam)), "overlap")
    assert worker.send("open", image=str(image), segment_dir=str(folder), bounds=bounds, model=str(tiny_sam))["ok"]
    inside = [list(pixel_xy(t, 70, 50))]
    refused(worker.send("prompt", entity="tree", points=inside), "no entity 'tree'")
    refused(worker.send("prompt", entity="road", points=[list(pixel_xy(t, 2, 2))]), "outside the view")
    refused(worker.send("prompt", entity="road", points=inside, labels=[2]), "labels")
    refused(worker.send("prompt", entity="road", points=inside, mode="xor"), "unknown mode")
    refused(worker.send("prompt", entity="road"), "at least one point or a box")
    refused(worker.send("apply", entity="road", points=inside, box=[1, 2, 3]), "box")
    refused(worker.send("prompt", entity="road", points=[[1e308, -1e308]]), "within")
    refused(worker.send("prompt", entity="road", box=[-1e308, -1e308, 1e308, 1e308]), "within")
    assert worker.send("prompt", entity="road", points=inside)["ok"]
    assert worker.send("ping")["embeddings"] == 1
    assert worker.close() == 0
