"""Evaluate a checked cost program over numpy arrays (one block, or a whole small image).

The evaluator walks the :class:`~overseec_core.costlang.tree.Program` tree; there is no other way
for program text to cause computation. Only the entity layers the program reads are touched.

Result semantics (the same for every block, which is what makes block-wise evaluation exact):

- ``M["e"]`` is the entity's boolean mask, ``P["e"]`` its gated probability ``P * M`` in [0, 1].
- the costmap is ``cost`` clipped to [0, 1]; where ``lethal`` holds, the cost is 1.0;
- pixels covered by no entity get whatever the program gives them (the synthesised programs give
  them 1.0, the maximum), so nothing depends on pixels outside the block's halo.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from overseec_core.costlang.kernels import Field, Mask, Poll, never_cancelled
from overseec_core.costlang.lang import COST, KEEP_OUT, LETHAL
from overseec_core.costlang.ops import Value, apply_op
from overseec_core.costlang.tree import Apply, Const, Expr, Layer, Program, Terrain, Var
from overseec_core.errors import CostProgramError


@dataclass(frozen=True)
class Evaluation:
    """What a program gives for one block: cost in [0, 1] (float64), the lethal mask and the
    keep-out mask (where a distance rule forbids going; all False when the program has none)."""

    cost: Field
    lethal: Mask
    keep_out: Mask


class _Block:
    def __init__(
        self,
        masks: Mapping[str, npt.NDArray[Any]],
        probs: Mapping[str, npt.NDArray[Any]] | None,
        sampling: tuple[float, float],
        poll: Poll = never_cancelled,
        terrain: Mapping[str, npt.NDArray[Any]] | None = None,
    ) -> None:
        self.masks, self.probs, self.sampling, self.poll = masks, probs or {}, sampling, poll
        self.terrain = terrain or {}
        self.env: dict[str, Value] = {}

    def terrain_field(self, node: Terrain) -> Value:
        try:
            return np.asarray(self.terrain[node.name], dtype=np.float64)
        except KeyError:
            raise CostProgramError(missing_dem_message(node.name), node.line, node.col) from None

    def layer(self, node: Layer) -> Value:
        try:
            mask = np.asarray(self.masks[node.entity], dtype=bool)
        except KeyError:
            raise CostProgramError(f"no mask for entity '{node.entity}'", node.line, node.col) from None
        if node.table == "M":
            return mask
        prob = self.probs.get(node.entity)
        if prob is None:
            return mask.astype(np.float64)
        return np.where(mask, np.clip(np.asarray(prob, dtype=np.float64), 0.0, 1.0), 0.0)

    def value(self, node: Expr) -> Value:
        if isinstance(node, Const):
            return np.bool_(node.value) if isinstance(node.value, bool) else np.float64(node.value)
        if isinstance(node, Var):
            return self.env[node.name]
        if isinstance(node, Layer):
            return self.layer(node)
        if isinstance(node, Terrain):
            return self.terrain_field(node)
        if isinstance(node, Apply):
            args = [self.value(a) for a in node.args]
            self.poll()
            return apply_op(node.op, args, node.consts, self.sampling, self.poll)
        raise AssertionError(type(node))


def missing_dem_message(name: str) -> str:
    """The one-line error for a program that reads a terrain field when no DEM was given."""
    return f"the program reads '{name}', which needs a DEM: pass --dem DEM.tif (an elevation raster in metres)"


def evaluate_program(
    program: Program,
    masks: Mapping[str, npt.NDArray[Any]],
    probs: Mapping[str, npt.NDArray[Any]] | None = None,
    sampling: tuple[float, float] = (1.0, 1.0),
    shape: tuple[int, int] | None = None,
    poll: Poll = never_cancelled,
    terrain: Mapping[str, npt.NDArray[Any]] | None = None,
) -> Evaluation:
    """Run ``program`` on one block of entity layers.

    ``masks[e]``: bool (h, w) per entity the program reads; ``probs[e]``: raw probabilities in [0, 1]
    (optional; without them ``P["e"]`` equals the mask). ``sampling``: pixel size (y, x) in metres,
    as scipy.ndimage wants it. ``poll``: a cancellation check, called before every operation
    and between units of work inside long spatial operations (each call is cheap; it raises, e.g.
    :class:`~overseec_core.errors.Cancelled`, to stop). ``terrain[name]``: the terrain fields
    the program reads (``slope`` in degrees, ``roughness`` in metres; float (h, w), finite),
    computed from the DEM by :mod:`overseec_core.synthesize.terrain`; a program that reads one
    that is not given fails with a one-line error naming ``--dem``. Returns cost (float64 in [0, 1]), lethal
    and keep_out (bool), shape (h, w).
    """
    block_shape: tuple[int, ...]
    if shape is None:
        if not masks:
            raise CostProgramError("no mask layers given and no block shape", None, None)
        block_shape = np.shape(next(iter(masks.values())))
    else:
        block_shape = shape
    block = _Block(masks, probs, sampling, poll, terrain)
    with np.errstate(all="ignore"):
        for statement in program.statements:
            block.env[statement.target] = block.value(statement.value)
        cost = np.broadcast_to(np.asarray(block.env[COST], dtype=np.float64), block_shape)
        cost = np.clip(cost, 0.0, 1.0)
    lethal_value = block.env.get(LETHAL, np.bool_(False))
    lethal = np.array(np.broadcast_to(np.asarray(lethal_value, dtype=bool), block_shape))
    cost[lethal] = 1.0
    keep_value = block.env.get(KEEP_OUT, np.bool_(False))
    keep_out = np.broadcast_to(np.asarray(keep_value, dtype=bool), block_shape) & ~lethal
    if not np.isfinite(cost).all():  # ranges were checked statically; this guards the guarantee
        raise CostProgramError("the program produced values that are not numbers", None, None)
    return Evaluation(cost=cost, lethal=lethal, keep_out=keep_out)
