"""The checked cost program: a small frozen tree of typed expressions (:class:`Expr` and its
kinds), the statements that bind them and the :class:`Program` the evaluator walks. Built only by
:func:`overseec_core.costlang.lang.check_program`, which parses and checks the text; kept apart
from it so the evaluator and the synthesiser read the tree without the checker.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from overseec_core.costlang.ops import Kind, Range


@dataclass(frozen=True)
class Expr:
    """A checked expression: where it is, its kind, its static range and spatial reach."""

    line: int
    col: int
    kind: Kind
    range: Range
    #: (metres, pixel roundings) this expression looks around a pixel, nested operators included.
    reach: tuple[float, int] = (0.0, 0)


@dataclass(frozen=True)
class Const(Expr):
    """A literal number or boolean."""

    value: float | bool = 0.0


@dataclass(frozen=True)
class Var(Expr):
    """A name bound by an earlier assignment of the program."""

    name: str = ""


@dataclass(frozen=True)
class Layer(Expr):
    """An entity layer read per pixel: its mask (table ``M``) or gated probability (table ``P``)."""

    table: str = "M"  # "M" mask, "P" gated probability
    entity: str = ""


@dataclass(frozen=True)
class Terrain(Expr):
    """A terrain field read per pixel (``slope``, ``roughness``): computed from the DEM on the grid."""

    name: str = ""


@dataclass(frozen=True)
class Apply(Expr):
    """An operator applied to arguments; ``op`` is a table name or one of + - * / ** neg < ..."""

    op: str = ""
    args: tuple[Expr, ...] = ()
    #: The constant value of each argument (None where it is not a constant).
    consts: tuple[float | None, ...] = ()


@dataclass(frozen=True)
class Assign:
    """One ``target = value`` statement of a program, with its position for error messages."""

    target: str
    value: Expr
    line: int
    col: int


@dataclass(frozen=True)
class Program:
    """A checked cost program, ready to evaluate on any block of masks."""

    text: str
    statements: tuple[Assign, ...]
    #: Canonical entity names the program reads, in order of first use.
    entities: tuple[str, ...]
    #: (table, entity) pairs read, e.g. ("M", "road"), ("P", "grass").
    layers: tuple[tuple[str, str], ...]
    reach_m: float
    roundings: int
    cost_range: Range
    has_lethal: bool
    has_keep_out: bool = False
    warnings: tuple[str, ...] = field(default=())
    #: Terrain fields read, each with the line and column of its first use: (name, line, col).
    terrain_uses: tuple[tuple[str, int, int], ...] = ()

    @property
    def terrain(self) -> tuple[str, ...]:
        """Names of the terrain fields the program reads (``slope``, ``roughness``), in order of first use."""
        return tuple(name for name, _, _ in self.terrain_uses)

    def halo(self, pixel_size_m: tuple[float, float]) -> tuple[int, int]:
        """Halo (rows, cols) in pixels that makes block-wise evaluation exact.

        ``pixel_size_m`` is (x, y) as :meth:`Grid.pixel_size_m` returns it. Each nested spatial
        operator rounds its radius up to whole pixels once, hence the ``roundings`` extra pixels.
        """
        if self.reach_m <= 0:
            return (0, 0)
        px, py = pixel_size_m
        return (math.ceil(self.reach_m / py) + self.roundings, math.ceil(self.reach_m / px) + self.roundings)
