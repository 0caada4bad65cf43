"""Benchmark: the Locate stage (CLIPSeg + SAM refinement) against the reference configuration.

Full-size architectures with random weights (speed does not depend on weight values):
CLIPSeg as CIDAS/clipseg-rd64-refined (CLIP ViT-B/16, 352 px input, reduce dim 64, refined
decoder) and SAM as facebook/sam-vit-base (ViT-B, 1024 px), built from their published config
values by tests/locate/builders.py and saved once under bench/out/models. Six entities.

What it prints, all measured in one process on the same image:

* overseec end to end (`segment_image` + `refine_image`: reading, tiles, blending, COG writing)
  on a generated scene of --size px, with the progress bars (ETA) on stderr; its seconds per
  megapixel as measured, and per-tile costs extrapolated to a 10000 x 10000 image (exact tile
  counts of both grids, so edge tiles of the small bench image do not inflate the figure);
* the reference configuration on --ref-tiles tiles of the same image: 512 px tiles at stride
  256, the whole CLIPSeg forward (vision encoder included) once per entity per tile, SAM on the
  512 px tile upscaled to 1024 px with one box-prompted decoder call per entity; model time only
  (no I/O, no blending: generous to the reference), extrapolated the same way;
* the bare model forward at overseec's tile densities (the CLIPSeg vision encoder per 512 px tile at
  352 px, the SAM image encoder per 1024 px tile, overseec's batch sizes and precision), the limit
  no tile loop can beat, and the overhead ratio (overseec end to end / bare forward);
* where the time went: each tile stage's busy seconds (reading and preparing prompts, the model,
  blending and writing) and the model's share of the stage's wall time (near 100 %: the other
  stages ran while the model did);
* peak GPU memory of overseec's run on CUDA;
* peak RSS of a full `overseec segment` run in a fresh process on a --rss-width px wide image
  (default 10000, as wide as the 10000 x 10000 target) whose data covers only the top-left
  corner: every buffer, writer and COG rewrite is full width and streams over the full height as
  for the big image, while models run only on the corner's tiles (a model's peak is per tile, the
  same for 4 tiles or 400). Run in a subprocess so the figure is that run's own.

    .venv/bin/python bench/bench_segment.py            # full size: several minutes on 2 cores
    .venv/bin/python bench/bench_segment.py --quick    # tiny models, small image: checks it runs
    .venv/bin/python bench/bench_segment.py --device cuda --size 4096 --skip-rss   # on a GPU
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

os.environ.setdefault("GDAL_CACHEMAX", "256")
REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
OUT = REPO / "bench" / "out" / "segment"
BIG = 10000  # the image side the per-megapixel figures are extrapolated to


def build_models(quick: bool) -> tuple[Path, Path]:
    """Random-weight checkpoints saved once (full size ~1 GB on disk)."""
    from tests.locate import builders as b

    tag = "tiny" if quick else "full"
    clipseg, sam = OUT / "models" / f"clipseg-{tag}", OUT / "models" / f"sam-{tag}"
    if not (clipseg / "model.safetensors").exists():
        b.save_clipseg(clipseg, b.tiny_clipseg_config if quick else b.full_clipseg_config)
    if not (sam / "model.safetensors").exists():
        b.save_sam(sam, b.tiny_sam_config if quick else b.full_sam_config)
    return clipseg, sam


def entities():
    """The default entity set (road, trail, grass, tree, building, water) the bench segments."""
    from overseec_core.schema import DEFAULT_ENTITIES, Entity

    return [Entity(n, g) for n, g in DEFAULT_ENTITIES]  # road, trail, grass, tree, building, water


def tiles_per_mpx(tile: int, overlap: int, side: int = BIG) -> float:
    """Tiles per megapixel that a TileGrid of this tile size and overlap cuts a ``side`` x ``side``
    image into: per-tile times scale by it to the big image."""
    from overseec_core.locate.tiling import TileGrid

    return len(TileGrid(side, side, tile, overlap)) / (side * side / 1e6)


# --------------------------------------------------------------------------------------------
# overseec
# --------------------------------------------------------------------------------------------


def truth_probs(scene, out: Path) -> Path:
    """Coarse probabilities from the scene's known classes (smoothed indicators), on its grid.

    Random CLIPSeg weights give pixel-noise masks (its transposed convolutions paint 4 px
    checkerboards: tens of thousands of tiny components per tile), which would make SAM's work
    unrepresentative either way; the truth has real roads, a river, a forest, scattered trees
    and buildings, so refinement does the work a real scene asks for.
    """
    import rasterio
    from scipy import ndimage

    from overseec_core.io.read import read_grid
    from overseec_core.io.write import write_array
    from overseec_core.sample import CLASSES

    ids = {name: k for k, name in CLASSES.items()}
    with rasterio.open(scene.labels) as ds:
        labels = ds.read(1)
    probs = np.stack(
        [0.05 + 0.9 * ndimage.gaussian_filter((labels == ids[e.name]).astype(np.float32), 2.0) for e in entities()]
    )
    out.mkdir(parents=True, exist_ok=True)
    return write_array(
        out / "probs_truth.tif",
        probs.astype(np.float32),
        read_grid(scene.image),
        nodata=float("nan"),
        descriptions=[e.name for e in entities()],
    )


def sync(device: str) -> None:
    """Wait for queued GPU work, so wall-clock times are the work's."""
    import torch

    if device.startswith("cuda"):
        torch.cuda.synchronize()


def run_overseec(
    scene,
    clipseg: Path,
    sam: Path,
    out: Path,
    device: str,
    compile: bool = False,
    segmenter: str = "clipseg",
    model: str | None = None,
    gsd: float | str | None = None,
) -> dict:
    """Run overseec's segment and refine stages on ``scene`` (refine from the true-class
    probabilities, so it does not depend on random CLIPSeg weights) and return their results and seconds.

    ``segmenter`` (a registry name) segments with ``model`` (None: the bench's random CLIPSeg for
    clipseg, else that segmenter's default) at the processing resolution ``gsd`` (None: native);
    the reference and the bare forward stay CLIPSeg's."""
    from overseec_core.locate.models import release_models
    from overseec_core.locate.refine import RefineOptions, refine_image
    from overseec_core.locate.segment import SegmentOptions, segment_image
    from overseec_core.progress import TqdmProgress

    progress = TqdmProgress()
    t0 = time.perf_counter()
    seg = segment_image(
        scene.image,
        entities(),
        out,
        SegmentOptions(
            segmenter=segmenter,
            model=model or (str(clipseg) if segmenter == "clipseg" else None),
            device=device,
            compile=compile,
            gsd=gsd,
        ),
        progress,
    )
    t_seg = time.perf_counter() - t0
    release_models()
    coarse = truth_probs(scene, out / "truth")
    t0 = time.perf_counter()
    options = RefineOptions(sam_model=str(sam), device=device, compile=compile)
    ref = refine_image(scene.image, coarse, entities(), out, options, progress)
    t_ref = time.perf_counter() - t0
    return {
        "segment": seg.to_json(),
        "refine": ref.to_json(),
        "seconds_segment": t_seg,
        "seconds_refine": t_ref,
        "coarse": coarse,
    }


# --------------------------------------------------------------------------------------------
# the reference configuration
# --------------------------------------------------------------------------------------------


def run_reference(
    image: Path, coarse: Path, clipseg: Path, sam: Path, tiles: list[tuple[int, int]], device: str
) -> dict:
    """Per-tile model time of the reference way on 512 px tiles at (row, col) offsets; SAM gets
    one box per entity around its coarse mask in the tile (``coarse``, as overseec's SAM stage)."""
    import rasterio
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    from overseec_core.locate.clipseg import load_clipseg, preprocess
    from overseec_core.locate.entities import entity_prompts
    from overseec_core.locate.sam_model import load_sam, sam_preprocess

    ents = entities()
    cs = load_clipseg(str(clipseg), device, "fp32")  # the reference runs fp32
    dev = cs.device
    texts = [entity_prompts(e)[0] for e in ents]
    enc = {k: v.to(dev) for k, v in cs.tokenizer(texts, padding=True, return_tensors="pt").items()}
    sm = load_sam(str(sam), device, "fp32")
    s = sm.image_size
    times_clipseg, times_sam = [], []
    with torch.inference_mode():  # untimed warm-up: the first call builds kernels
        cs.model(
            input_ids=enc["input_ids"][:1],
            attention_mask=enc["attention_mask"][:1],
            pixel_values=torch.zeros(1, 3, cs.norm.size, cs.norm.size, device=dev),
        )
        sm.model.get_image_embeddings(torch.zeros(1, 3, sm.image_size, sm.image_size, device=dev))
    with rasterio.open(image) as ds, rasterio.open(coarse) as cds:
        for r, c in tiles:
            rgb = np.moveaxis(ds.read([1, 2, 3], window=((r, r + 512), (c, c + 512))), 0, -1)[None]
            masks = cds.read(window=((r, r + 512), (c, c + 512))) >= 0.5
            sync(device)
            t0 = time.perf_counter()
            with torch.inference_mode():
                pixels = preprocess(rgb, cs.norm, cs.norm.size, dev)
                for k in range(len(ents)):  # the whole model once per entity, encoder included
                    logits = cs.model(
                        input_ids=enc["input_ids"][k : k + 1],
                        attention_mask=enc["attention_mask"][k : k + 1],
                        pixel_values=pixels,
                    ).logits
                    up = F.interpolate(logits[:, None], size=(512, 512), mode="bilinear", align_corners=False)
                    torch.sigmoid(up).cpu()
            sync(device)
            times_clipseg.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            with torch.inference_mode():
                big = (
                    F.interpolate(
                        torch.from_numpy(rgb).to(dev).permute(0, 3, 1, 2).float(),
                        size=(s, s),
                        mode="bilinear",
                        align_corners=False,
                    )
                    .round()
                    .clamp(0, 255)
                )
                emb = sm.model.get_image_embeddings(sam_preprocess(big.permute(0, 2, 3, 1).byte().cpu().numpy(), sm))
                for mask in masks:  # one box per entity, components collapsed
                    ys, xs = np.nonzero(mask)
                    box = [0, 0, 511, 511] if len(xs) == 0 else [xs.min(), ys.min(), xs.max(), ys.max()]
                    box = torch.tensor([[[float(v) * s / 512 for v in box]]], device=dev)
                    sm.model(image_embeddings=emb, input_boxes=box, multimask_output=False).pred_masks.cpu()
            sync(device)
            times_sam.append(time.perf_counter() - t0)
    return {"tiles": len(times_clipseg), "clipseg_s": times_clipseg, "sam_s": times_sam}


# --------------------------------------------------------------------------------------------
# the bare model forward (the limit)
# --------------------------------------------------------------------------------------------


def run_bare(clipseg: Path, sam: Path, device: str, clip_batch: int, sam_batch: int, repeats: int = 2) -> dict:
    """Seconds per tile of the bare encoders on random pixels, as overseec batches and casts them
    (its precision on the device): CLIPSeg's vision model at its input size, SAM's image encoder."""
    import torch

    from overseec_core.locate.clipseg import load_clipseg
    from overseec_core.locate.models import autocast
    from overseec_core.locate.sam_model import load_sam

    def timed(fn, batch: int) -> float:
        with torch.inference_mode():
            fn()  # warm-up
            sync(device)
            times = []
            for _ in range(repeats):
                t0 = time.perf_counter()
                fn()
                sync(device)
                times.append(time.perf_counter() - t0)
        return float(np.median(times)) / batch

    cs = load_clipseg(str(clipseg), device)
    px = torch.randn(clip_batch, 3, cs.norm.size, cs.norm.size, device=cs.device)

    def clip_forward():
        with autocast(cs.device, cs.precision):
            return cs.model.clip.vision_model(pixel_values=px).last_hidden_state

    sm = load_sam(str(sam), device)
    spx = torch.randn(sam_batch, 3, sm.image_size, sm.image_size, device=sm.device)

    def sam_forward():
        with autocast(sm.device, sm.precision):
            return sm.model.get_image_embeddings(spx)

    return {
        "clipseg_s_per_tile": timed(clip_forward, clip_batch),
        "sam_s_per_tile": timed(sam_forward, sam_batch),
        "precision": cs.precision,
        "clip_batch": clip_batch,
        "sam_batch": sam_batch,
    }


def run_switches(clipseg: Path, sam: Path, device: str, repeats: int = 3) -> None:
    """The speed switches measured on and off on the bare encoders (random pixels, the device's
    precision): attention eager vs sdpa, channels-last off vs on, torch.compile off vs on; each
    line also gives the largest difference of the outputs from the default configuration's and
    the first call's seconds (warm-up, compilation)."""
    import torch
    from transformers import CLIPSegForImageSegmentation, SamModel

    from overseec_core.locate.models import autocast, load_pretrained, resolve_device, resolve_model, resolve_precision

    dev = resolve_device(device)
    prec = resolve_precision("auto", dev)

    def timed(fn, reps: int) -> tuple[float, float, Any]:
        """(first call s, median of ``reps`` later calls s, output)"""
        with torch.inference_mode():
            t0 = time.perf_counter()
            out = fn()
            sync(device)
            first = time.perf_counter() - t0
            times = []
            for _ in range(reps):
                t0 = time.perf_counter()
                fn()
                sync(device)
                times.append(time.perf_counter() - t0)
        return first, float(np.median(times)), out.float()

    gen = torch.Generator().manual_seed(0)
    cases = (
        ("CLIPSeg vision encoder, batch 4", CLIPSegForImageSegmentation, clipseg, "clipseg", 4, repeats),
        ("SAM image encoder, batch 1", SamModel, sam, "sam", 1, 1),
    )
    variants = (
        ("sdpa (default)", "sdpa", False, False),
        ("eager attention", "eager", False, False),
        ("sdpa + channels-last", "sdpa", True, False),
        ("sdpa + torch.compile", "sdpa", False, True),
    )
    for name, cls, path, kind, batch, reps in cases:
        side = int(json.loads((path / "config.json").read_text())["vision_config"]["image_size"])
        px = torch.randn(batch, 3, side, side, generator=gen).to(dev)
        base = None
        for label, attn, channels_last, compiled in variants:
            model = load_pretrained(cls, resolve_model(str(path), kind), dev, attn_implementation=attn)
            enc = model.clip.vision_model if kind == "clipseg" else model.vision_encoder
            if channels_last:
                model.to(memory_format=torch.channels_last)
            if compiled:
                enc.compile()

            def forward(enc=enc, px=px):
                with autocast(dev, prec):
                    return enc(px).last_hidden_state

            first, seconds, out = timed(forward, reps)
            diff = 0.0 if base is None else float((out - base).abs().max())
            base = out if base is None else base
            print(
                f"  {name:32s} {label:22s} {seconds / batch * 1e3:9.1f} ms/tile   max |diff| {diff:.1e}   "
                f"(first call {first:.1f} s)",
                flush=True,
            )
            del model, enc


def stage_profile(label: str, wall: float, busy: dict[str, float], model: str) -> str:
    """One line: each stage's busy seconds, their sum, and the model stage's share of the wall
    time (1.0: the model never waited for reading, prompt preparation, blending or writing)."""
    parts = ", ".join(f"{k} {v:.1f}" for k, v in busy.items())
    total = sum(busy.values())
    return (
        f"  {label}: wall {wall:.1f} s; busy {parts} (sum {total:.1f} s); "
        f"the model busy {busy.get(model, 0.0) / max(wall, 1e-9):.0%} of the wall"
    )


# --------------------------------------------------------------------------------------------
# peak RSS (child process)
# --------------------------------------------------------------------------------------------


def make_corner_image(path: Path, width: int, height: int, data_w: int, data_h: int) -> None:
    """A wide RGBA image with data (the sample scene's texture) only in the top-left corner."""
    import rasterio
    from rasterio.transform import from_origin

    from overseec_core.sample import generate

    scene = generate(OUT / "scene-corner", size=max(data_w, data_h))
    with rasterio.open(scene.image) as ds:
        corner = ds.read(window=((0, data_h), (0, data_w)))
    profile = dict(
        driver="GTiff",
        width=width,
        height=height,
        count=4,
        dtype="uint8",
        crs="EPSG:32633",
        transform=from_origin(534000, 5213000, 0.5, 0.5),
        tiled=True,
        blockxsize=512,
        blockysize=512,
        compress="deflate",
        photometric="RGB",
    )
    with rasterio.open(path, "w", **profile) as ds:
        ds.colorinterp = [
            rasterio.enums.ColorInterp.red,
            rasterio.enums.ColorInterp.green,
            rasterio.enums.ColorInterp.blue,
            rasterio.enums.ColorInterp.alpha,
        ]
        for r0 in range(0, height, 512):
            h = min(512, height - r0)
            strip = np.zeros((4, h, width), np.uint8)
            if r0 < data_h:
                rows = min(h, data_h - r0)
                strip[:3, :rows, :data_w] = corner[:, r0 : r0 + rows]
                strip[3, :rows, :data_w] = 255
            ds.write(strip, window=((r0, r0 + h), (0, width)))


def child_rss(args: argparse.Namespace) -> None:
    """Runs `overseec segment` (the CLI path, both stages) and prints its peak RSS."""
    from overseec_core.cli import main

    argv = [
        "-q",
        "segment",
        str(args.image),
        "--out",
        str(args.out),
        "--device",
        args.device,
        "--clipseg-model",
        str(args.clipseg),
        "--sam-model",
        str(args.sam),
    ]
    for e in entities():
        argv += ["--entity", f"{e.name}:{e.geometry}"]
    t0 = time.perf_counter()
    code = main(argv)
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"exit": code, "peak_rss_mb": peak_mb, "seconds": time.perf_counter() - t0}))


# --------------------------------------------------------------------------------------------


def main() -> None:
    """Build the models, time the reference configuration on sample tiles before and after
    overseec's run, and print the per-tile and per-megapixel comparison (or only the speed switches)."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="tiny models and small images (a smoke test)")
    ap.add_argument("--device", default="auto", help="cpu | cuda | cuda:N | auto (default: CUDA if present, else CPU)")
    ap.add_argument("--compile", action="store_true", help="torch.compile the encoders in overseec's run")
    ap.add_argument(
        "--segmenter",
        default="clipseg",
        help="the segmenter overseec's run uses (a registry name; the reference stays CLIPSeg's)",
    )
    ap.add_argument("--model", help="its model (default: the bench's random CLIPSeg, or the segmenter's default)")
    ap.add_argument("--gsd", help="processing resolution of overseec's run: metres per pixel or auto (default: native)")
    ap.add_argument(
        "--switches", action="store_true", help="only time the speed switches on and off on the bare encoders"
    )
    ap.add_argument("--size", type=int, help="side of the bench scene (default 1536; quick 640)")
    ap.add_argument(
        "--ref-tiles",
        type=int,
        default=4,
        help="reference tiles to time, half before and half after overseec's run (default 4)",
    )
    ap.add_argument("--rss-width", type=int, help="width of the RSS image (default 10000; quick 3000)")
    ap.add_argument("--skip-rss", action="store_true")
    ap.add_argument("--child-rss", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--image", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--out", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--clipseg", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--sam", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child_rss:
        child_rss(args)
        return

    import torch

    from overseec_core.locate.models import describe_device, resolve_device
    from overseec_core.sample import generate

    dev = resolve_device(args.device)
    device = str(dev)
    OUT.mkdir(parents=True, exist_ok=True)
    size = args.size or (640 if args.quick else 1536)
    t0 = time.perf_counter()
    clipseg, sam = build_models(args.quick)
    if args.switches:
        print(f"speed switches on {describe_device(dev)}, torch {torch.__version__}:")
        run_switches(clipseg, sam, device)
        return
    print(
        f"models: {clipseg.name}, {sam.name} (random weights; built/loaded in {time.perf_counter() - t0:.0f} s); "
        f"torch {torch.__version__}, device {describe_device(dev)}, {torch.get_num_threads()} threads, "
        f"{os.cpu_count()} CPUs (shared with other developers: timings include their load)",
        flush=True,
    )
    scene = generate(OUT / f"scene-{size}", size=size)
    mpx = size * size / 1e6

    # the reference is timed on tiles before and after overseec's run, so both see the same load
    offsets = [(r, c) for r in range(0, size - 511, 256) for c in range(0, size - 511, 256)]
    picks = [offsets[(k * 7) % len(offsets)] for k in range(max(2, args.ref_tiles))]
    half = len(picks) // 2
    coarse = truth_probs(scene, OUT / f"run-{size}" / "truth")
    before = run_reference(scene.image, coarse, clipseg, sam, picks[:half], device)
    if dev.type == "cuda":
        torch.cuda.reset_peak_memory_stats(dev)
    ours = run_overseec(
        scene, clipseg, sam, OUT / f"run-{size}", device, args.compile, args.segmenter, args.model, args.gsd
    )
    peak_gpu = torch.cuda.max_memory_allocated(dev) / 2**30 if dev.type == "cuda" else None
    after = run_reference(scene.image, coarse, clipseg, sam, picks[half:], device)
    bare = run_bare(clipseg, sam, device, ours["segment"]["batch_size"], ours["refine"]["batch_size"], 2)
    reference = {
        "tiles": before["tiles"] + after["tiles"],
        "clipseg_s_per_tile": float(np.mean(before["clipseg_s"] + after["clipseg_s"])),
        "sam_s_per_tile": float(np.mean(before["sam_s"] + after["sam_s"])),
        "before": before,
        "after": after,
    }
    seg, ref = ours["segment"], ours["refine"]
    wall = ours["seconds_segment"] + ours["seconds_refine"]
    clip_tile = seg["timings_s"]["tiles"] / max(1, seg["tiles"] - seg["tiles_skipped"])  # wall, all stages
    sam_tile = ref["timings_s"]["tiles"] / max(1, ref["tiles_sam"])
    our_tpm = tiles_per_mpx(seg["tile_size"], seg["overlap"])
    our_sam_tpm = tiles_per_mpx(ref["tile_size"], ref["overlap"])
    ours_big = our_tpm * clip_tile + our_sam_tpm * sam_tile
    ref_tpm = tiles_per_mpx(512, 256)
    ref_big = ref_tpm * (reference["clipseg_s_per_tile"] + reference["sam_s_per_tile"])

    print(f"\nscene {size} x {size} px ({mpx:.2f} Mpx), 6 entities")
    print(
        f"overseec   {seg['segmenter']} {seg['tiles']} tiles of {seg['tile_size']} px (overlap {seg['overlap']}, "
        f"model {seg['model_size']} px, batch {seg['batch_size']}): {ours['seconds_segment']:.1f} s, "
        f"{clip_tile:.2f} s/tile, encoder passes {seg['encoder_calls']}"
    )
    print(
        f"           SAM {ref['tiles']} tiles of {ref['tile_size']} px (overlap {ref['overlap']}), "
        f"{ref['tiles_sam']} refined (coarse masks from the scene truth), {ref['components_refined']} components "
        f"({ref['components_coarse']} left coarse), {ref['decoder_prompts']} decoder prompts in "
        f"{ref['decoder_calls']} calls: "
        f"{ours['seconds_refine']:.1f} s, {sam_tile:.2f} s/SAM tile"
    )
    print(
        f"           end to end measured: {wall:.1f} s = {wall / mpx:.1f} s/Mpx (edge tiles of a small image included)"
    )
    print(
        f"reference  512 px tiles at stride 256, {reference['tiles']} tiles timed (half before, half after): "
        f"CLIPSeg {reference['clipseg_s_per_tile']:.2f} s/tile (encoder x6), SAM 512->1024 "
        f"{reference['sam_s_per_tile']:.2f} s/tile; per tile before "
        f"{[round(a + b, 1) for a, b in zip(reference['before']['clipseg_s'], reference['before']['sam_s'])]}"
        f" after {[round(a + b, 1) for a, b in zip(reference['after']['clipseg_s'], reference['after']['sam_s'])]} s"
    )
    print(
        f"\nextrapolated to {BIG} x {BIG} px (tiles per Mpx: overseec {our_tpm:.2f} CLIPSeg + "
        f"{our_sam_tpm:.2f} SAM, reference {ref_tpm:.2f}):"
    )
    print(f"  overseec  {ours_big:8.1f} s/Mpx   (CLIPSeg {our_tpm * clip_tile:.1f} + SAM {our_sam_tpm * sam_tile:.1f})")
    print(
        f"  reference {ref_big:8.1f} s/Mpx   (CLIPSeg {ref_tpm * reference['clipseg_s_per_tile']:.1f} + "
        f"SAM {ref_tpm * reference['sam_s_per_tile']:.1f})"
    )
    print(f"  speed-up  {ref_big / ours_big:8.1f} x   (measured-image figure: {ref_big / (wall / mpx):.1f} x)")
    print(
        f"  CLIPSeg alone: {ref_tpm * reference['clipseg_s_per_tile'] / (our_tpm * clip_tile):.1f} x; "
        f"SAM alone: {ref_tpm * reference['sam_s_per_tile'] / (our_sam_tpm * sam_tile):.1f} x",
        flush=True,
    )
    bare_big = our_tpm * bare["clipseg_s_per_tile"] + our_sam_tpm * bare["sam_s_per_tile"]
    print(
        f"  bare forward {bare_big:8.3f} s/Mpx   (CLIPSeg vision encoder "
        f"{bare['clipseg_s_per_tile'] * 1e3:.1f} ms/tile "
        f"at batch {bare['clip_batch']}, SAM image encoder {bare['sam_s_per_tile'] * 1e3:.0f} ms/tile at batch "
        f"{bare['sam_batch']}, {bare['precision']}; every SAM tile counted)"
    )
    print(f"  overhead  {ours_big / bare_big:8.2f} x   (overseec end to end / bare forward)")
    print("\nwhere the time went (each stage's busy seconds; reading, preparing and writing overlap the model):")
    seg_busy = {k: seg["timings_s"][k] for k in ("read", "predict", "blend_write")}
    print(stage_profile("CLIPSeg", seg["timings_s"]["tiles"], seg_busy, "predict"))
    ref_busy = {k.removeprefix("stage_"): v for k, v in ref["timings_s"].items() if k.startswith("stage_")}
    print(stage_profile("SAM    ", ref["timings_s"]["tiles"], ref_busy, "model"))
    if peak_gpu is not None:
        print(f"peak GPU memory (overseec's run): {peak_gpu:.2f} GiB")
    print(f"peak RSS of this process: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB", flush=True)

    if args.skip_rss:
        return
    width = args.rss_width or (3000 if args.quick else BIG)
    height, data = (1200, 256) if args.quick else (2600, 1100)
    image = OUT / f"rss-{width}x{height}.tif"
    if not image.exists():
        make_corner_image(image, width, height, data_w=min(width, 896 if not args.quick else 256), data_h=data)
    done = subprocess.run(
        [
            sys.executable,
            __file__,
            "--child-rss",
            "--image",
            str(image),
            "--out",
            str(OUT / f"rss-run-{width}"),
            "--clipseg",
            str(clipseg),
            "--sam",
            str(sam),
            "--device",
            args.device,
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
    )
    if done.returncode != 0:
        print(done.stderr[-2000:])
        raise SystemExit("RSS run failed")
    rss = json.loads(done.stdout.strip().splitlines()[-1])
    print(
        f"\npeak RSS, `overseec segment` (CLIPSeg + SAM, 6 entities) on {width} x {height} px with data in "
        f"the top-left {min(width, 896 if not args.quick else 256)} x {data} px: "
        f"{rss['peak_rss_mb']:.0f} MB ({rss['seconds']:.0f} s, exit {rss['exit']})"
    )
    print(
        "  buffers and writers are full width and stream over the height, so a 10000 x 10000 image "
        "peaks the same: memory is bounded by tiles and width, not by image size"
    )


if __name__ == "__main__":
    main()
