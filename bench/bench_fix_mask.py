"""Benchmark: click to fix a mask through the SAM worker, as the QGIS tool drives it.

The plugin's own client (:class:`overseec_qgis.samclient.SamClient`, plain Python) starts
`overseec sam-server`, opens a 1024 x 1024 px view of the sample scene (resources/sample) with a
segment folder built from the scene's class raster, and sends --clicks prompts for the building
entity the way a user clicks: an include point on a building, an exclude point beside it, a box
around it, then the next building (each prompt carries all of the current object's points, as the
tool sends them). Printed per model:

* the view's embedding (SAM's image encoder once, in the worker) and the open request's round trip
  (the first one also loads the model);
* per click: the round trip seen from the client (median and max), the worker's time and its mask
  decoder's share (medians) -- the target is <= 300 ms per click on CPU after the embedding;
* one apply (the edit written into masks.tif + probs.tif and the manifest).

Models: the tiny random SAM of the tests and, unless --quick, a randomly initialised full-size
facebook/sam-vit-base (``SamConfig`` ViT-B at 1024 px: random weights cost the same compute),
both built by tests/locate/builders.py and saved once under bench/out/segment/models (shared with
bench_segment.py).

    .venv/bin/python bench/bench_fix_mask.py             # tiny and ViT-B on CPU
    .venv/bin/python bench/bench_fix_mask.py --quick     # tiny only: checks it runs
    .venv/bin/python bench/bench_fix_mask.py --decoder-threads 1,0   # one decoder thread vs all

Measured on a shared 2-core CPU (load average 2-4 from other jobs), SAM ViT-B, 1024 px view:
embedding 15.8-55 s (the load); per click median 154-253 ms round trip, max 351-747 ms, worker
CPU 140 ms per click (decoder about 100 ms of it). The decoder on all threads instead of one: median
766 ms, since a thread pool on a busy CPU waits for its threads longer than it saves.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
OUT = REPO / "bench" / "out" / "fix_mask"
MODELS = REPO / "bench" / "out" / "segment" / "models"
ENTITY = "building"


def build_model(tag: str) -> Path:
    """The random-weight SAM checkpoint ``tiny`` or ``full`` (saved once)."""
    from tests.locate import builders as b

    folder = MODELS / f"sam-{tag}"
    if not (folder / "model.safetensors").exists():
        b.save_sam(folder, b.tiny_sam_config if tag == "tiny" else b.full_sam_config)
    return folder


def build_scene() -> tuple[Path, Path, np.ndarray]:
    """The sample image and a segment folder (masks.tif, probs.tif; one band per class) from its
    class raster; returns the image, the folder and the class ids."""
    import rasterio

    from overseec_core.io.grid import Grid
    from overseec_core.io.read import read_classes_json
    from overseec_core.io.write import write_array

    sample = REPO / "resources" / "sample"
    OUT.mkdir(parents=True, exist_ok=True)
    image = Path(shutil.copy(sample / "sample.tif", OUT / "sample.tif"))
    seg = OUT / "seg"
    shutil.rmtree(seg, ignore_errors=True)
    seg.mkdir()
    classes = read_classes_json(sample / "classes.json")
    with rasterio.open(sample / "sample_labels.tif") as ds:
        labels = ds.read(1)
        grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
    names = list(classes.values())
    masks = np.stack([labels == k for k in classes]).astype(np.uint8)
    write_array(seg / "masks.tif", masks, grid, nodata=255, descriptions=names)
    write_array(seg / "probs.tif", np.where(masks > 0, 0.9, 0.1).astype(np.float32), grid, descriptions=names)
    ids = {v: k for k, v in classes.items()}
    return image, seg, labels == ids[ENTITY]


def clicks(buildings: np.ndarray, transform, n: int) -> list[dict]:
    """``n`` prompts on the buildings: include its centre, exclude beside it, box around it."""
    from scipy import ndimage

    comps, count = ndimage.label(buildings)
    boxes = sorted(ndimage.find_objects(comps), key=lambda s: -(s[0].stop - s[0].start) * (s[1].stop - s[1].start))

    def xy(col: float, row: float) -> tuple[float, float]:
        x, y = transform * (col, row)
        return float(x), float(y)

    prompts: list[dict] = []
    for rows, cols in boxes[: max(1, count)]:
        rc, cc = (rows.start + rows.stop) / 2, (cols.start + cols.stop) / 2
        inside = xy(cc, rc)
        beside = xy(min(1023.0, cols.stop + 6.0), rc)
        box = [*xy(cols.start - 2, rows.stop + 2), *xy(cols.stop + 2, rows.start - 2)]
        prompts += [
            {"points": [inside], "labels": [1], "box": None},
            {"points": [inside, beside], "labels": [1, 0], "box": None},
            {"points": [inside, beside], "labels": [1, 0], "box": box},
        ]
        if len(prompts) >= n:
            break
    while len(prompts) < n:  # few buildings: go round again
        prompts += prompts[: n - len(prompts)]
    return prompts[:n]


def run_model(tag: str, device: str, n_clicks: int, decoder_threads: int) -> dict:
    """Open the view, click, apply, through one worker; the figures."""
    import rasterio

    from overseec_qgis.samclient import SamClient

    model = build_model(tag)
    image, seg, buildings = build_scene()
    with rasterio.open(image) as ds:
        bounds, transform = list(ds.bounds), ds.transform
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    argv = [sys.executable, "-m", "overseec_core.cli", "sam-server", "--device", device]
    client = SamClient([*argv, "--decoder-threads", str(decoder_threads)], env=env)
    try:
        t0 = time.perf_counter()
        info = client.open(image, seg, bounds, model=str(model))
        open_ms = 1000.0 * (time.perf_counter() - t0)
        replies = [client.prompt(ENTITY, mode="add", **p) for p in clicks(buildings, transform, n_clicks)]
        last = clicks(buildings, transform, 3)[-1]
        t1 = time.perf_counter()
        applied = client.apply(ENTITY, mode="add", **last)
        apply_ms = 1000.0 * (time.perf_counter() - t1)
    finally:
        client.close()
    rt = [r.round_trip_ms for r in replies]
    return {
        "model": tag,
        "decoder_threads": decoder_threads or "all",
        "device": info.device,
        "view_px": list(info.window[2:]),
        "embed_ms": info.embed_ms,
        "open_round_trip_ms": open_ms,
        "clicks": len(rt),
        "click_median_ms": statistics.median(rt),
        "click_max_ms": max(rt),
        "click_ms": [round(v, 1) for v in rt],
        "worker_median_ms": statistics.median(r.worker_ms for r in replies),
        "decoder_median_ms": statistics.median(r.decoder_ms for r in replies),
        "worker_cpu_median_ms": statistics.median(r.worker_cpu_ms for r in replies),
        "polygons_median": statistics.median(len(r.polygons) for r in replies),
        "apply_ms": apply_ms,
        "apply_files": list(applied.files),
    }


def main() -> int:
    """Run the bench and print the figures (and bench/out/fix_mask/results.json)."""
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="the tiny model only")
    parser.add_argument("--models", default="tiny,full", help="which of tiny,full to run (default both)")
    parser.add_argument("--device", default="cpu", help="where SAM runs (default cpu)")
    parser.add_argument("--clicks", type=int, default=20, help="prompts per model (default 20)")
    parser.add_argument(
        "--decoder-threads",
        default="1",
        help="comma-separated worker settings to compare, 0 = torch's default (all cores); default 1",
    )
    args = parser.parse_args()
    settings = [int(v) for v in args.decoder_threads.split(",")]
    tags = ["tiny"] if args.quick else args.models.split(",")
    load = os.getloadavg()[0]
    results = [run_model(tag, args.device, args.clicks, n) for tag in tags for n in settings]
    print(f"cpu cores: {os.cpu_count()}, load average {load:.1f} before, {os.getloadavg()[0]:.1f} after")
    for r in results:
        name = "tiny SAM" if r["model"] == "tiny" else "SAM ViT-B (sam-vit-base config, random weights)"
        print(
            f"\n{name} on {r['device']}, view {r['view_px'][0]} x {r['view_px'][1]} px, "
            f"decoder threads: {r['decoder_threads']}"
        )
        print(f"  embedding (image encoder, once per view): {r['embed_ms']:.0f} ms")
        print(f"  open round trip (model load + embedding):  {r['open_round_trip_ms']:.0f} ms")
        print(
            f"  {r['clicks']} clicks, round trip: median {r['click_median_ms']:.0f} ms, max {r['click_max_ms']:.0f} ms"
            f" (worker median {r['worker_median_ms']:.0f} ms, of it mask decoder {r['decoder_median_ms']:.0f} ms;"
            f" worker CPU median {r['worker_cpu_median_ms']:.0f} ms)"
        )
        print(f"  apply ({', '.join(r['apply_files'])} + manifest): {r['apply_ms']:.0f} ms")
    (OUT / "results.json").write_text(json.dumps(results, indent=2), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
