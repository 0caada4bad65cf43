"""SAM for the Locate stage: the model bundle and the refiner of coarse masks on SAM tiles.

The refiner runs SAM's image encoder once per tile (batched over tiles) and its mask decoder on
component prompts (:mod:`overseec_core.locate.prompts`), fed back for a few iterations. The work is
split so that each part scales with what it serves:

* :meth:`SamRefiner.prepare` (CPU, no model; the tile pipeline runs it in the reader stage, ahead
  of the model): components, first prompts, the coarse calibration, and each component's mask
  prompt on SAM's low-resolution grid computed from cell sums over its bounding box (the tile-wide
  parts once per entity, never per component);
* :meth:`SamRefiner.refine`: the encoder for a batch of tiles, then the prompts of all components
  of the batch decoded together (``decoder_batch`` per call, gathering each one's tile embedding),
  each pass's low-resolution logits brought to the host once, upsampled and thresholded only on
  each component's context region; the next pass's mask prompt stays on the device.

Per entity the tile's refined probability is SAM's (max over components) inside the components'
context regions and, elsewhere, the coarse probability recalibrated so that the entity's threshold
maps to 0.5 (:func:`overseec_core.locate.prompts.calibrate`).

The refiner is any of the SAM family in :mod:`overseec_core.locate.refiners` (SAM, SAM-HQ, SAM 2):
they share the prompt encoder and the mask decoder's inputs (points with labels, one box, a
low-resolution mask of logits) and its low-resolution output, and differ only in what the image
encoder hands the decoder. That difference is adapted in one place, :func:`encode_tiles`,
:func:`decoder_inputs` and :meth:`SamRefiner.decode_tiles` (SAM-HQ's tile features passed once per
tile, not per component): the embeddings of a tile are a tuple of tensors with the tile as first
dimension (SAM: the image embedding; SAM-HQ: plus the first global block's ViT features its HQ
token fuses; SAM 2: the two high-resolution FPN levels plus the image embedding), and the refiner
gathers each component's tile from every member alike. All three take mask prompts: SAM 2's
library forward resizes a mask prompt whose side is not 4x the embedding's, which ours always is,
so no refiner runs on points and boxes only.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

from overseec_core.errors import InputError
from overseec_core.locate.models import (
    BatchState,
    autocast,
    default_batch_size,
    run_with_backoff,
)
from overseec_core.locate.prompts import (
    MASK_PROMPT_LIMIT,
    Component,
    ComponentPrompt,
    RefineParams,
    calibrate,
    cell_pool,
    cell_span,
    coarse_mask_logits,
    context_region,
    find_components,
    iou,
    make_prompt,
    sigmoid,
    upsample_region,
)
from overseec_core.locate.sam_model import (
    Embeddings,
    SamBundle,
    decoder_inputs,
    encode_tiles,
    encoder_blocks,
    gather_tiles,
    sam_preprocess,
)
from overseec_core.progress import Progress, check_cancelled


def prompt_arrays(prompts: Sequence[ComponentPrompt]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The decoder's sparse prompts of n components: points (n, 1, k, 2) and labels (n, 1, k),
    padded to the most points with label -10 (which every SAM family's prompt encoder zeroes), and
    one box each (n, 1, 4)."""
    n, k = len(prompts), max(len(p.labels) for p in prompts)
    points = np.zeros((n, 1, k, 2), np.float32)
    labels = np.full((n, 1, k), -10, np.int64)
    for i, p in enumerate(prompts):
        points[i, 0, : len(p.labels)] = p.points
        labels[i, 0, : len(p.labels)] = p.labels
    return points, labels, np.array([[p.box] for p in prompts], np.float32)


@dataclass
class TileStats:
    """Counts for the manifest."""

    tiles_sam: int = 0
    tiles_no_mask: int = 0
    components_refined: int = 0
    components_coarse: int = 0
    decoder_calls: int = 0  # mask-decoder calls (each a batch of components)
    decoder_prompts: int = 0  # component prompts decoded, passes counted
    encoder_calls: int = 0

    def add(self, other: TileStats) -> None:
        for k in vars(self):
            setattr(self, k, getattr(self, k) + getattr(other, k))


@dataclass
class _Job:
    """One component being refined: its prompt, its current mask and SAM's answer, both on the
    prompt's context region, and its first mask prompt on SAM's low-resolution grid."""

    tile: int
    prompt: ComponentPrompt
    mask: np.ndarray  # bool, on prompt.region
    mask_prompt: np.ndarray  # (m, m) float32 logits
    answer: np.ndarray | None = None  # float32 probabilities on prompt.region


@dataclass(frozen=True)
class TilePlan:
    """What :meth:`SamRefiner.prepare` derives from one tile's coarse maps, before any model runs."""

    shape: tuple[int, int]
    calibrated: np.ndarray  # (E, h, w) coarse probabilities with each threshold at 0.5
    prompts: tuple[ComponentPrompt, ...]
    masks: tuple[np.ndarray, ...]  # each component's coarse mask on its region
    mask_prompts: tuple[np.ndarray, ...]  # each component's (m, m) mask prompt
    components_coarse: int = 0


class SamRefiner:
    """Refines coarse per-entity probabilities of tiles with SAM (see the module docstring)."""

    def __init__(self, bundle: SamBundle, params: RefineParams | None = None, batch_size: int | None = None) -> None:
        params = params or RefineParams()
        params.check()
        self.bundle, self.params = bundle, params
        self.state = BatchState(batch_size or default_batch_size(bundle.device, 1, 4))
        self.per_call = params.components_per_call(bundle.device.type in ("cuda", "mps"))
        self.stats = TileStats()

    # -- CPU side, no model -------------------------------------------------------------------------

    def prepare(self, coarse: np.ndarray, thresholds: Sequence[float]) -> TilePlan:
        """Components, first prompts and mask prompts of one tile's (E, h, w) coarse maps."""
        e, h, w = coarse.shape
        p, s, m = self.params, self.bundle.image_size, self.bundle.mask_size
        if h > s or w > s:
            raise InputError(f"SAM tile {h}x{w} is larger than the model input {s}")
        cell = s // m
        pooled = s == cell * m
        prompts: list[ComponentPrompt] = []
        masks: list[np.ndarray] = []
        mask_prompts: list[np.ndarray] = []
        left = 0
        for ent, (probs, tau) in enumerate(zip(coarse, thresholds)):
            with np.errstate(invalid="ignore"):
                mask = probs >= tau
            labels, comps, n_left = find_components(mask, p.min_area, p.max_components)
            left += n_left
            if not comps:
                continue
            base = coarse_mask_logits(probs, tau)
            # the mask prompt of a component: coarse logits, other components forced to background
            # (-L), pooled to SAM's grid; = pool(base) + pool(others' shift) - pool(own shift),
            # the first two once per entity, the last on the component's box only
            shift = np.where(labels > 0, np.float32(-MASK_PROMPT_LIMIT) - base, np.float32(0))
            if pooled:
                canvas = np.full((2, s, s), 0.0, np.float32)
                canvas[0] = -MASK_PROMPT_LIMIT
                canvas[0, :h, :w] = base
                canvas[1, :h, :w] = shift
                tile_pool = cell_pool(canvas, cell)
                shared = tile_pool[0] + tile_pool[1]
            for comp in comps:
                region = context_region(comp, (h, w), p)
                rr, cc = region
                fg = labels[rr, cc] == comp.label
                prompts.append(make_prompt(ent, comp, fg, probs[rr, cc], p, (rr.start, cc.start), (h, w)))
                masks.append(fg)
                if pooled:
                    cr, ccl = cell_span(comp.rows, cell), cell_span(comp.cols, cell)
                    own = np.zeros(((cr.stop - cr.start) * cell, (ccl.stop - ccl.start) * cell), np.float32)
                    pr = slice(cr.start * cell, min(h, cr.stop * cell))
                    pc = slice(ccl.start * cell, min(w, ccl.stop * cell))
                    sub = labels[pr, pc] == comp.label
                    own[: pr.stop - pr.start, : pc.stop - pc.start] = np.where(sub, shift[pr, pc], np.float32(0))
                    prompt = shared.copy()
                    prompt[cr, ccl] -= cell_pool(own, cell)
                else:  # a checkpoint whose input is not a whole number of mask cells: pool the tile
                    prompt = self._pool_tile(np.where((labels > 0) & (labels != comp.label), -MASK_PROMPT_LIMIT, base))
                mask_prompts.append(prompt.astype(np.float32, copy=False))
        return TilePlan((h, w), calibrate(coarse, thresholds), tuple(prompts), tuple(masks), tuple(mask_prompts), left)

    def _pool_tile(self, logits: np.ndarray) -> np.ndarray:
        import torch
        import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

        s, m = self.bundle.image_size, self.bundle.mask_size
        h, w = logits.shape
        canvas = torch.full((1, 1, s, s), -MASK_PROMPT_LIMIT)
        canvas[0, 0, :h, :w] = torch.from_numpy(np.ascontiguousarray(logits, np.float32))
        return F.adaptive_avg_pool2d(canvas, (m, m))[0, 0].numpy()

    # -- model calls -----------------------------------------------------------------------------

    def embed(self, rgb: np.ndarray) -> Embeddings:
        """Image embeddings of B tiles (:func:`encode_tiles`): the encoder runs once per tile."""
        import torch

        b = self.bundle

        def run(a: int, z: int) -> Embeddings:
            with torch.inference_mode(), autocast(b.device, b.precision):
                return encode_tiles(b, sam_preprocess(rgb[a:z], b))

        parts = run_with_backoff(run, len(rgb), self.state)
        self.stats.encoder_calls += len(rgb)
        return tuple(torch.cat(members) for members in zip(*parts))

    def decode(
        self, embeddings: Embeddings, prompts: Sequence[ComponentPrompt], mask_inputs: torch.Tensor
    ) -> torch.Tensor:
        """One mask-decoder call for several components, each with its tile's embeddings
        (``embeddings`` holds one row per prompt). Returns low-res logits (n, m, m) on the device."""
        import torch

        b = self.bundle
        n = len(prompts)
        points, labels, boxes = prompt_arrays(prompts)
        dev = b.device
        with torch.inference_mode(), autocast(dev, b.precision):
            out = b.model(
                **decoder_inputs(b, embeddings),
                input_points=torch.from_numpy(points).to(dev, non_blocking=True),
                input_labels=torch.from_numpy(labels).to(dev, non_blocking=True),
                input_boxes=torch.from_numpy(boxes).to(dev, non_blocking=True),
                input_masks=mask_inputs,
                multimask_output=False,
            )
            low = out.pred_masks[:, 0, 0].float()
        self.stats.decoder_calls += 1
        self.stats.decoder_prompts += n
        return low

    def decode_tiles(
        self,
        embeddings: Embeddings,
        tiles: Sequence[int],
        prompts: Sequence[ComponentPrompt],
        mask_inputs: torch.Tensor,
    ) -> torch.Tensor:
        """:meth:`decode` for prompts on the given tiles of ``embeddings`` (one tile index each).

        SAM and SAM 2 gather each prompt's tile and decode all prompts in one call. SAM-HQ is
        decoded one tile at a time with that tile's ViT features passed once (batch 1): its
        decoder broadcasts them over the prompts, so the heaviest part of its HQ branch (a
        768-channel transposed convolution to 128 x 128 at ViT-B size) runs once per tile
        instead of once per component; the numbers are the same (the parity test decodes this way).
        """
        import torch

        dev = self.bundle.device
        if self.bundle.refiner != "sam-hq":
            return self.decode(gather_tiles(embeddings, torch.tensor(tiles, device=dev)), prompts, mask_inputs)
        answers: dict[int, torch.Tensor] = {}
        for tile in sorted(set(tiles)):
            idx = [i for i, t in enumerate(tiles) if t == tile]
            own = (embeddings[0][tile : tile + 1].expand(len(idx), -1, -1, -1), embeddings[1][tile : tile + 1])
            low = self.decode(own, [prompts[i] for i in idx], mask_inputs[torch.tensor(idx, device=dev)])
            answers.update(zip(idx, low))
        return torch.stack([answers[i] for i in range(len(tiles))])

    # -- per batch of tiles ----------------------------------------------------------------------

    def refine(self, embeddings: Embeddings, plans: Sequence[TilePlan]) -> list[np.ndarray]:
        """(E, h, w) refined probabilities (mask: >= 0.5) of the tiles whose embeddings and plans
        are given; all their components are decoded together, ``decoder_batch`` per call."""
        jobs = [
            _Job(t, prompt, mask, mp)
            for t, plan in enumerate(plans)
            for prompt, mask, mp in zip(plan.prompts, plan.masks, plan.mask_prompts)
        ]
        self.stats.components_refined += len(jobs)
        self.stats.components_coarse += sum(plan.components_coarse for plan in plans)
        for start in range(0, len(jobs), self.per_call):
            self._decode_iterated(embeddings, jobs[start : start + self.per_call], plans)
        outs = []
        for t, plan in enumerate(plans):
            best = plan.calibrated.copy()
            inside = np.zeros(best.shape, bool)
            for job in (j for j in jobs if j.tile == t):
                rr, cc = job.prompt.region
                ent = job.prompt.entity
                assert job.answer is not None  # the first pass answers every job
                target = np.where(inside[ent, rr, cc], best[ent, rr, cc], -np.inf)
                best[ent, rr, cc] = np.maximum(target, job.answer)
                inside[ent, rr, cc] = True
            outs.append(best)
        return outs

    def _decode_iterated(self, embeddings: Embeddings, jobs: list[_Job], plans: Sequence[TilePlan]) -> None:
        """Decode jobs up to ``iterations`` times, each pass prompted by the last answer (its
        low-res logits as mask prompt, points and box re-derived from its mask), all on each job's
        region. A job whose mask changed little (IoU >= ``stop_iou`` with the previous one, the
        coarse mask for the first pass) is done early."""
        import torch

        p, dev, s = self.params, self.bundle.device, self.bundle.image_size
        active = list(range(len(jobs)))
        mask_in = torch.from_numpy(np.stack([j.mask_prompt for j in jobs])[:, None]).to(dev, non_blocking=True)
        for it in range(p.iterations):
            low = self.decode_tiles(
                embeddings, [jobs[i].tile for i in active], [jobs[i].prompt for i in active], mask_in
            )
            low_host = low.cpu().numpy()  # one transfer per pass, (n, m, m)
            again = []
            for j, i in enumerate(active):
                job = jobs[i]
                job.answer = sigmoid(upsample_region(low_host[j], s, job.prompt.region))
                if it + 1 == p.iterations:
                    continue
                fg = job.answer >= 0.5
                if fg.any() and iou(fg, job.mask) < p.stop_iou:
                    job.prompt, job.mask = self._reprompt(job.prompt, fg, job.answer, plans[job.tile].shape)
                    again.append((i, j))
            if not again:
                break
            active = [i for i, _ in again]
            mask_in = low[[j for _, j in again]][:, None].clamp(-MASK_PROMPT_LIMIT, MASK_PROMPT_LIMIT)

    def _reprompt(
        self, prompt: ComponentPrompt, fg: np.ndarray, prob: np.ndarray, shape: tuple[int, int]
    ) -> tuple[ComponentPrompt, np.ndarray]:
        """Prompts for the next pass from SAM's answer ``fg`` on the component's region, and that
        mask on the new region (the union of the old one and the new prompt's)."""
        rr, cc = prompt.region
        rows = np.flatnonzero(fg.any(axis=1))
        cols = np.flatnonzero(fg.any(axis=0))
        comp = Component(
            prompt.component.label,
            slice(rr.start + int(rows[0]), rr.start + int(rows[-1]) + 1),
            slice(cc.start + int(cols[0]), cc.start + int(cols[-1]) + 1),
            int(np.count_nonzero(fg)),
        )
        nr, nc = context_region(comp, shape, self.params)
        # the accepted region never shrinks below the first pass's
        ur = slice(min(nr.start, rr.start), max(nr.stop, rr.stop))
        uc = slice(min(nc.start, cc.start), max(nc.stop, cc.stop))
        inner = (slice(rr.start - ur.start, rr.stop - ur.start), slice(cc.start - uc.start, cc.stop - uc.start))
        mask = np.zeros((ur.stop - ur.start, uc.stop - uc.start), bool)
        mask[inner] = fg
        score = np.full(mask.shape, np.nan, np.float32)
        score[inner] = prob
        new = make_prompt(prompt.entity, comp, mask, score, self.params, (ur.start, uc.start), shape)
        return ComponentPrompt(new.entity, comp, new.points, new.labels, new.box, (ur, uc)), mask

    def __call__(self, rgb: np.ndarray, coarse: Sequence[np.ndarray], thresholds: Sequence[float]) -> list[np.ndarray]:
        """Refine a batch of tiles (all needing SAM): prepare, one encoder pass each, decode."""
        plans = [self.prepare(c, thresholds) for c in coarse]
        return self.refine_prepared(rgb, plans)

    def refine_prepared(self, rgb: np.ndarray, plans: Sequence[TilePlan]) -> list[np.ndarray]:
        """Encoder and decoder for tiles whose plans :meth:`prepare` made (e.g. in another thread)."""
        outs = self.refine(self.embed(rgb), plans)
        self.stats.tiles_sam += len(rgb)
        return outs


@contextlib.contextmanager
def cancel_between_layers(bundle: SamBundle, progress: Progress | None) -> Iterator[None]:
    """Check for cancellation before each encoder block: a CPU tile of SAM ViT-B takes ~15 s, a block ~1 s."""
    if progress is None:
        yield
        return
    handles = [
        block.register_forward_pre_hook(lambda *_: check_cancelled(progress)) for block in encoder_blocks(bundle)
    ]
    try:
        yield
    finally:
        for h in handles:
            h.remove()


__all__ = ["SamRefiner", "TilePlan", "TileStats", "cancel_between_layers", "prompt_arrays"]
