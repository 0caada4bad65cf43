"""Processing resolution (``--gsd``): a segmenter runs at a chosen ground resolution, its outputs
land on the image's own grid.

A model trained on 30 cm imagery sees a 10 cm image as objects three times too large; Deepness and
geoai let the user pick the resolution (cm/px) the model works at. Here that is a wrapper around
the batch predictor the tiling engine drives (:class:`ResampledSegmenter`), so tiling, blending,
devices, the Dask path, out-of-memory back-off and the bounded-memory streaming stay the ones every
segmenter shares:

* the native tile side becomes ``round(model_size * gsd / native_gsd)`` px: a tile covers the
  ground the model sees at ``gsd`` (:meth:`Resampling.tile_size`);
* each native tile is resampled to the model's pixels (area averaging when shrinking, bilinear
  when enlarging: ``torch.nn.functional.interpolate``), predicted, and the probabilities are
  resampled back onto the native tile (bilinear when enlarging, area when shrinking) before the
  usual blending.

The native ground resolution is :meth:`overseec_core.io.grid.Grid.pixel_size_m` (ground metres,
also for geographic CRSs); the tile side uses the mean of its x and y sizes, and a tile is scaled
by one factor on both axes (a full tile becomes exactly ``model_size`` square), so a pixel that is
not square on the ground (a geographic CRS away from the equator) stays as it was.
``--gsd auto`` is the segmenter's trained resolution where it says one (the semantic backend's
``gsd_m``), else native (no resampling).

torch is imported inside the functions, never at import time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from overseec_core.errors import InputError

if TYPE_CHECKING:
    import torch

#: ``--gsd`` value meaning "the segmenter's trained resolution, else native".
GSD_AUTO = "auto"
#: The largest native tile side ``--gsd`` may ask for: a tile is read, resampled and blended whole,
#: so a processing resolution far coarser than the image would make tiles (and the blender's rows)
#: unbounded; beyond it, downsample the image first (gdal_translate -tr).
MAX_NATIVE_TILE = 4096
#: The smallest side, in model pixels, a tile may shrink to (an image smaller than a tile is one tile).
MIN_MODEL_SIDE = 16


def parse_gsd(value: object) -> float | str | None:
    """``--gsd`` as given (a number of metres per pixel, ``"auto"``, or None for native) checked:
    a positive finite number or ``auto``; anything else is a one-line InputError."""
    if value is None or value == "":
        return None
    if isinstance(value, str):
        text = value.strip().lower()
        if text == GSD_AUTO:
            return GSD_AUTO
        try:
            number = float(text)
        except ValueError:
            raise InputError(
                f"--gsd {value!r}: expected metres per pixel (e.g. 0.3) or 'auto' (the model's own)"
            ) from None
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        number = float(value)
    else:
        raise InputError(f"--gsd {value!r}: expected metres per pixel (e.g. 0.3) or 'auto'")
    if not math.isfinite(number) or number <= 0:
        raise InputError(f"--gsd {value!r}: the processing resolution must be a positive number of metres per pixel")
    return number


@dataclass(frozen=True)
class Resampling:
    """Where the model works (``gsd_m``, metres per model pixel) against the image's own ground
    resolution (``native_m``, metres per pixel along x and y); ``requested`` is ``--gsd`` as given."""

    requested: float | str
    gsd_m: float
    native_m: tuple[float, float]

    def tile_size(self, model_size: int) -> int:
        """The native tile side covering ``model_size`` model pixels of ground (mean pixel size)."""
        native = (self.native_m[0] + self.native_m[1]) / 2.0
        return max(1, round(model_size * self.gsd_m / native))

    def model_shape(self, height: int, width: int, model_size: int) -> tuple[int, int]:
        """The model-pixel shape of a native ``height`` x ``width`` tile: ``model_size`` for a side
        of a full tile, the same factor (model_size / tile side) for a smaller one (an image smaller
        than a tile is one tile of its own size)."""
        tile = self.tile_size(model_size)

        def side(n: int) -> int:
            return model_size if n == tile else max(1, round(n * model_size / tile))

        return side(height), side(width)

    def to_json(self) -> dict:
        """What the manifest records: the request, the processing and the native resolution."""
        return {
            "requested": self.requested,
            "processing_m": self.gsd_m,
            "native_m": [round(v, 6) for v in self.native_m],
        }


def plan_resampling(
    gsd: float | str | None, trained_m: float | None, native_m: tuple[float, float]
) -> Resampling | None:
    """The resampling ``--gsd`` asks for, or None to run at the native resolution.

    ``gsd`` is :func:`parse_gsd`'s value; ``trained_m`` the segmenter's trained resolution where it
    says one (``auto`` uses it; without one ``auto`` is native); ``native_m`` the image's ground
    pixel size (x, y) in metres.
    """
    gsd = parse_gsd(gsd)
    if gsd is None:
        return None
    if gsd == GSD_AUTO:
        if not trained_m:
            return None
        return Resampling(GSD_AUTO, float(trained_m), native_m)
    return Resampling(gsd, float(gsd), native_m)


def check_resampling(resampling: Resampling, model_size: int, width: int, height: int) -> int:
    """The native tile side for ``resampling``, or a one-line InputError when the tiles would be
    too large to stream (:data:`MAX_NATIVE_TILE`) or the image too small for the model."""
    tile = resampling.tile_size(model_size)
    gsd = f"--gsd {resampling.gsd_m:g} m/px on a {_native_label(resampling.native_m)} image"
    if tile > MAX_NATIVE_TILE:
        raise InputError(
            f"{gsd} makes tiles of {tile} px (the most is {MAX_NATIVE_TILE}); "
            "use a finer --gsd or downsample the image first (gdal_translate -tr)"
        )
    if tile < 32:
        raise InputError(
            f"{gsd} makes tiles of {tile} px (at least 32 px); use a coarser --gsd or a larger --model-size"
        )
    side = min(resampling.model_shape(min(height, tile), min(width, tile), model_size))
    if side < MIN_MODEL_SIDE:
        raise InputError(
            f"{gsd} shrinks this {width}x{height} px image to {side} px for the model "
            f"(at least {MIN_MODEL_SIDE}); use a finer --gsd"
        )
    return tile


def _native_label(native_m: tuple[float, float]) -> str:
    """'0.5 m/px' or '0.24 x 0.3 m/px'."""
    x, y = native_m
    return f"{x:.3g} m/px" if math.isclose(x, y, rel_tol=1e-3) else f"{x:.3g} x {y:.3g} m/px"


def resample_maps(maps: torch.Tensor, size: tuple[int, int]) -> torch.Tensor:
    """(N, C, h, w) float maps -> (N, C, *size): area averaging where both sides shrink (each
    output pixel the mean of the input it covers), bilinear (half-pixel centres) otherwise."""
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    h, w = maps.shape[-2:]
    if (h, w) == tuple(size):
        return maps
    if size[0] <= h and size[1] <= w:
        return F.interpolate(maps, size=size, mode="area")
    return F.interpolate(maps, size=size, mode="bilinear", align_corners=False)


def resample_tiles(rgb: np.ndarray, valid: np.ndarray, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """(B, h, w, 3) uint8 tiles and (B, h, w) validity onto ``size`` model pixels: colours by
    :func:`resample_maps` rounded back to uint8, validity where at least half the ground was valid."""
    import torch

    if rgb.shape[1:3] == tuple(size):
        return rgb, valid
    with torch.inference_mode():
        pixels = torch.from_numpy(np.ascontiguousarray(rgb)).permute(0, 3, 1, 2).float()
        out = resample_maps(pixels, size).round_().clamp_(0, 255).to(torch.uint8)
        ok = resample_maps(torch.from_numpy(valid).float()[:, None], size)[:, 0] >= 0.5
        return out.permute(0, 2, 3, 1).contiguous().numpy(), ok.numpy()


def resample_probabilities(probs: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """(B, E, H, W) probabilities back onto the native tile's ``size``, float32 in [0, 1]."""
    import torch

    if probs.shape[2:] == tuple(size):
        return probs
    with torch.inference_mode():
        maps = resample_maps(torch.from_numpy(np.ascontiguousarray(probs, np.float32)), size)
        return maps.clamp_(0.0, 1.0).numpy()


class ResampledSegmenter:
    """A loaded segmenter run at another ground resolution: the same batch predictor contract
    (:class:`overseec_core.locate.segmenters.base.LoadedSegmenter`), each batch resampled to the
    model's pixels and its probabilities back onto the native tiles (see the module docstring)."""

    def __init__(self, inner: Any, resampling: Resampling) -> None:
        self.inner = inner
        self.resampling = resampling
        self.ref = inner.ref
        self.device = inner.device
        self.precision = inner.precision
        self.state = inner.state
        self.model_size = int(inner.model_size)

    @property
    def encoder_calls(self) -> int:
        """Tiles through the wrapped model's encoder."""
        return int(self.inner.encoder_calls)

    @property
    def timings(self) -> dict[str, float]:
        """The wrapped segmenter's own load phases (e.g. text embeddings), if it reports any."""
        return dict(getattr(self.inner, "timings", None) or {})

    def describe(self) -> str:
        """The wrapped segmenter's line plus the processing resolution."""
        r = self.resampling
        return f"{self.inner.describe()}; at {r.gsd_m:g} m/px (image {_native_label(r.native_m)})"

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        """(B, h, w, 3) native tiles -> (B, E, h, w) probabilities, predicted at ``gsd_m``."""
        native = (int(rgb.shape[1]), int(rgb.shape[2]))
        small_rgb, small_valid = resample_tiles(rgb, valid, self.resampling.model_shape(*native, self.model_size))
        return resample_probabilities(np.asarray(self.inner(small_rgb, small_valid), np.float32), native)


def resampled(segmenter: Any, resampling: Resampling | None) -> Any:
    """``segmenter`` wrapped to run at ``resampling`` (itself when None)."""
    return segmenter if resampling is None else ResampledSegmenter(segmenter, resampling)


__all__ = [
    "GSD_AUTO",
    "MAX_NATIVE_TILE",
    "MIN_MODEL_SIDE",
    "ResampledSegmenter",
    "Resampling",
    "check_resampling",
    "parse_gsd",
    "plan_resampling",
    "resample_maps",
    "resample_probabilities",
    "resample_tiles",
    "resampled",
]
