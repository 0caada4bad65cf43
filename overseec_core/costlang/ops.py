"""The operator table of the cost language: every function a program may call.

A declarative table (operators -> arity, kinds, kernel, bounds, reach): exempt from the ~600-line module limit.

Each :class:`OpSpec` says how many arguments an operator takes and of which kind, what it returns,
how to compute it on numpy arrays, how to bound its result statically (interval arithmetic, used to
reject programs that could divide by zero or overflow before anything runs, and by
``normalize(x)``), and how far it looks around a pixel (its *reach* in metres, which sets the halo
of block-wise evaluation). The array work of the spatial operators is
:mod:`overseec_core.costlang.kernels`.

Why hand-written: no library offers a sandboxed array expression language with static bounds and a
spatial reach; numexpr and friends evaluate Python expressions and know nothing of metres. The
spatial work itself is scipy.ndimage (exact Euclidean distance transform with anisotropic
``sampling``, separable maximum filter).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import Enum
from functools import reduce
from typing import Any, TypeAlias, cast

import numpy as np
import numpy.typing as npt

from overseec_core.costlang.kernels import (
    Field,
    FieldValue,
    Mask,
    Poll,
    Sampling,
    centre_field,
    distance_to,
    never_cancelled,
    raw_distance,
)

# scipy and scikit-image are imported by the kernels that use them (costlang/kernels.py), not at
# import: checking a program (the parser and the range analysis, which QGIS's Python runs as the
# user types) needs numpy only.

#: Largest radius / width (metres) a single spatial operator may use.
MAX_RADIUS_M = 500.0
#: Default saturation distance of ``distance(mask)`` when no second argument is given.
DEFAULT_DISTANCE_CAP_M = 100.0
#: Largest absolute value any expression may reach (static bound); keeps float64 far from overflow.
MAX_MAGNITUDE = 1e12
#: Largest absolute exponent of ``**``.
MAX_EXPONENT = 8.0
#: Most arguments of a variadic operator.
MAX_VARIADIC = 64


#: Largest roughness (metres) a DEM can give: the static upper bound of ``roughness`` (values above
#: it, never met on real terrain in a 3x3 window, are clipped to it).
MAX_ROUGHNESS_M = 10_000.0


@dataclass(frozen=True)
class TerrainSpec:
    """A terrain field a program may read by name (``slope``, ``roughness``): computed from the
    DEM (``--dem``) on the costmap's grid, with its static range, unit and meaning."""

    name: str
    lo: float
    hi: float
    unit: str
    doc: str
    example: str


#: The terrain fields, read like entity layers (``cost = max(cost, normalize(slope, 15, 30))``).
#: Computed by :mod:`overseec_core.synthesize.terrain` from the DEM; reserved names.
TERRAIN: dict[str, TerrainSpec] = {
    t.name: t
    for t in (
        TerrainSpec(
            "slope",
            0.0,
            90.0,
            "degrees",
            "terrain slope in degrees (0 flat, 90 vertical): Horn's 3x3 gradient on ground metres (needs --dem)",
            "max(cost, normalize(slope, 15, 30))",
        ),
        TerrainSpec(
            "roughness",
            0.0,
            MAX_ROUGHNESS_M,
            "metres",
            "terrain roughness in metres: RMS of the 3x3 elevations about their best-fit plane "
            "(0 on any plane, whatever its slope; needs --dem)",
            "max(cost, normalize(roughness, 0.1, 0.5))",
        ),
    )
}


class Kind(Enum):
    """Static kinds of values: a constant number, a boolean mask or a float field."""

    NUM = "number"
    MASK = "mask"
    FIELD = "field"

    def describe(self) -> str:
        return {"number": "a number", "mask": "a mask", "field": "a float field"}[self.value]


@dataclass(frozen=True)
class Range:
    """A static interval [lo, hi] that contains every value an expression can take."""

    lo: float
    hi: float

    @staticmethod
    def of(*values: float) -> Range:
        return Range(min(values), max(values))

    def union(self, other: Range) -> Range:
        return Range(min(self.lo, other.lo), max(self.hi, other.hi))

    def contains_zero(self) -> bool:
        return self.lo <= 0.0 <= self.hi

    def __str__(self) -> str:
        return f"[{self.lo:g}, {self.hi:g}]"


UNIT = Range(0.0, 1.0)

#: What a kernel takes and gives: an array (mask or field), or a numpy scalar for constants.
Value: TypeAlias = npt.NDArray[Any] | np.float64 | np.bool_
#: The constant arguments of a call, in argument order (None where an argument is not a constant).
Consts: TypeAlias = Sequence[float | None]
#: impl(arrays_or_scalars, consts, sampling, poll) -> array/scalar.
Kernel: TypeAlias = Callable[[Sequence[Value], Consts, Sampling, Poll], Value]
#: range(arg ranges, consts) -> Range of the result.
RangeFn: TypeAlias = Callable[[Sequence[Range], Consts], Range]
#: reach(consts) -> (metres, number of nested pixel roundings).
ReachFn: TypeAlias = Callable[[Consts], tuple[float, int]]


class SpecError(ValueError):
    """Raised by range/argument checks; the validator adds the line and column."""


@dataclass(frozen=True)
class Arg:
    """One formal argument: which kinds it accepts and whether it must be a constant (metres...)."""

    name: str
    kinds: tuple[Kind, ...]
    const: bool = False  # must be known when the program is checked (a radius, a bound)


MASK_ARG = (Kind.MASK,)
NUM_ARG = (Kind.NUM,)
VALUE_ARG = (Kind.NUM, Kind.FIELD, Kind.MASK)


@dataclass(frozen=True)
class OpSpec:
    """An operator: signature, result kind, implementation, static range and spatial reach."""

    name: str
    args: tuple[Arg, ...]
    #: Result kind, or a function of the argument kinds.
    result: Kind | Callable[[Sequence[Kind]], Kind]
    #: impl(arrays_or_scalars, consts, sampling, poll) -> array/scalar; a long impl calls
    #: ``poll()`` between units of work so that a cancel is honoured mid-operation.
    impl: Kernel
    #: range(arg ranges, consts) -> Range of the result.
    range: RangeFn
    doc: str
    example: str
    n_optional: int = 0  # trailing optional arguments
    variadic: bool = False  # the last argument repeats (at least len(args) arguments in all)
    #: reach(consts) -> (metres, number of nested pixel roundings) the operator looks around a pixel.
    reach: ReachFn | None = None
    #: How to write the call, when the generic form would mislead.
    signature: str | None = None

    def arity_text(self) -> str:
        if self.signature:
            return self.signature
        names = [a.name for a in self.args]
        if self.variadic:
            return f"{self.name}({', '.join(names)}, ...)"
        req = names[: len(names) - self.n_optional]
        opt = names[len(names) - self.n_optional :]
        return f"{self.name}({', '.join(req)}{''.join(f'[, {o}]' for o in opt)})"

    def result_kind(self, kinds: Sequence[Kind]) -> Kind:
        return self.result(kinds) if callable(self.result) else self.result


# --------------------------------------------------------------------------------------------
# Range helpers
# --------------------------------------------------------------------------------------------


def _check_magnitude(r: Range, what: str) -> Range:
    if not (math.isfinite(r.lo) and math.isfinite(r.hi)) or max(abs(r.lo), abs(r.hi)) > MAX_MAGNITUDE:
        raise SpecError(f"{what} may reach {r}, beyond the limit of ±{MAX_MAGNITUDE:g}; scale it down or clip() it")
    return r


def range_add(a: Range, b: Range) -> Range:
    """The range of ``a + b`` (an error when it may exceed the magnitude limit)."""
    return _check_magnitude(Range(a.lo + b.lo, a.hi + b.hi), "this sum")


def range_sub(a: Range, b: Range) -> Range:
    """The range of ``a - b`` (an error when it may exceed the magnitude limit)."""
    return _check_magnitude(Range(a.lo - b.hi, a.hi - b.lo), "this difference")


def range_mul(a: Range, b: Range) -> Range:
    """The range of ``a * b``: the extremes of the corner products (an error beyond the magnitude limit)."""
    return _check_magnitude(Range.of(a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi), "this product")


def range_div(a: Range, b: Range) -> Range:
    """The range of ``a / b``; a SpecError when ``b`` may be zero, so a program can never divide by zero."""
    if b.contains_zero():
        raise SpecError(
            f"division by a value that may be zero (the divisor ranges over {b}); "
            "add a positive constant to it, e.g. x / (d + 1)"
        )
    inv = Range.of(1.0 / b.lo, 1.0 / b.hi)
    return _check_magnitude(range_mul(a, inv), "this quotient")


def range_pow(a: Range, e: float) -> Range:
    """The range of ``a ** e``; a SpecError for an exponent out of bounds, a fractional power of a
    possibly negative value, or a negative power of a possibly zero one."""
    if not -MAX_EXPONENT <= e <= MAX_EXPONENT:
        raise SpecError(f"exponent {e:g} is outside [-{MAX_EXPONENT:g}, {MAX_EXPONENT:g}]")
    integer = float(e).is_integer()
    if not integer and a.lo < 0:
        raise SpecError(f"fractional power of a value that may be negative (range {a})")
    if e < 0 and a.contains_zero():
        raise SpecError(f"negative power of a value that may be zero (range {a})")
    try:
        cands = [math.pow(a.lo, e), math.pow(a.hi, e)]
        if a.lo < 0 < a.hi and e > 0:
            cands.append(0.0)
    except (OverflowError, ValueError):
        raise SpecError(f"this power may reach beyond ±{MAX_MAGNITUDE:g}") from None
    return _check_magnitude(Range.of(*cands), "this power")


def safe_pow(base: npt.ArrayLike, e: float) -> FieldValue:
    """``base ** e`` for arrays and scalars (ranges were checked, so this stays finite)."""
    if float(e).is_integer() and abs(e) <= MAX_EXPONENT:
        e = int(e)
    return np.power(np.asarray(base, dtype=np.float64), e)


# --------------------------------------------------------------------------------------------
# Implementations (arguments arrive as numpy arrays or numpy scalars; masks as bool)
# --------------------------------------------------------------------------------------------


def _as_mask(x: npt.ArrayLike) -> Mask:
    return np.asarray(x, dtype=bool)


def _as_field(x: npt.ArrayLike) -> Field:
    return np.asarray(x, dtype=np.float64)


def _const(consts: Consts, index: int) -> float:
    """A constant argument of a checked call: the operator's range function (run when the program
    was checked) refuses a call whose constant is missing, so it is a number here."""
    return cast(float, consts[index])


def _and(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return reduce(np.logical_and, args[1:], _as_mask(args[0]))


def _or(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return reduce(np.logical_or, args[1:], _as_mask(args[0]))


def _not(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.logical_not(args[0])


def _remove(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.logical_and(args[0], np.logical_not(args[1]))


def _distance(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    cap = consts[1] if len(consts) > 1 and consts[1] is not None else DEFAULT_DISTANCE_CAP_M
    return distance_to(args[0], sampling, cap)


def _near(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return raw_distance(args[0], sampling) <= _const(consts, 1)


def _far(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return raw_distance(args[0], sampling) > _const(consts, 1)


def _borders(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.logical_and(args[0], raw_distance(args[1], sampling) <= _const(consts, 2))


def _inside(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    mask = np.asarray(args[0], dtype=bool)
    return np.logical_and(mask, raw_distance(np.logical_not(mask), sampling) >= _const(consts, 1))


def _centre(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return centre_field(args[0], _const(consts, 1), sampling, edge=False, poll=poll)


def _edge(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return centre_field(args[0], _const(consts, 1), sampling, edge=True, poll=poll)


def _clip(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.clip(_as_field(args[0]), _const(consts, 1), _const(consts, 2))


def _where(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.where(args[0], args[1], args[2])


def _normalize(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    lo, hi = _const(consts, 1), _const(consts, 2)
    if hi <= lo:
        return np.zeros_like(_as_field(args[0]))
    return np.clip((_as_field(args[0]) - lo) / (hi - lo), 0.0, 1.0)


def _min(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return reduce(np.minimum, args[1:], _as_field(args[0]))


def _max(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return reduce(np.maximum, args[1:], _as_field(args[0]))


def _sum(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return reduce(np.add, args[1:], _as_field(args[0]))


def _abs(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.abs(_as_field(args[0]))


def _sqrt(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.sqrt(_as_field(args[0]))


def _exp(args: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll) -> Value:
    return np.exp(_as_field(args[0]))


# --------------------------------------------------------------------------------------------
# Static ranges and reaches
# --------------------------------------------------------------------------------------------


def _unit(ranges: Sequence[Range], consts: Consts) -> Range:
    return UNIT


def _radius(consts: Consts, index: int, what: str = "radius") -> float:
    value = consts[index]
    if value is None:
        raise SpecError(f"the {what} must be a constant number of metres")
    if not 0.0 < value <= MAX_RADIUS_M:
        raise SpecError(f"{what} {value:g} m is outside (0, {MAX_RADIUS_M:g}] m")
    return value


def _distance_range(ranges: Sequence[Range], consts: Consts) -> Range:
    cap = DEFAULT_DISTANCE_CAP_M if len(consts) < 2 or consts[1] is None else _radius(consts, 1, "cap")
    return Range(0.0, cap)


def _reach_at(index: int, factor: float = 1.0, roundings: int = 1, default: float | None = None) -> ReachFn:
    def reach(consts: Consts) -> tuple[float, int]:
        value = consts[index] if len(consts) > index and consts[index] is not None else default
        # the range function runs first and refuses a missing radius, so value is a number here
        return (factor * cast(float, value), roundings)

    return reach


def _checked_unit(index: int, what: str = "radius") -> RangeFn:
    def check(ranges: Sequence[Range], consts: Consts) -> Range:
        _radius(consts, index, what)
        return UNIT

    return check


def _clip_range(ranges: Sequence[Range], consts: Consts) -> Range:
    lo, hi = consts[1], consts[2]
    if lo is None or hi is None:
        raise SpecError("clip() bounds must be constant numbers")
    if lo > hi:
        raise SpecError(f"clip() lower bound {lo:g} is above its upper bound {hi:g}")
    x = ranges[0]
    return Range(min(max(x.lo, lo), hi), max(min(x.hi, hi), lo))


def _normalize_range(ranges: Sequence[Range], consts: Consts) -> Range:
    if len(consts) != 3 or consts[1] is None or consts[2] is None:
        raise SpecError("give both bounds, normalize(x, lo, hi), or neither, normalize(x)")
    if consts[2] < consts[1]:
        raise SpecError(f"upper bound {consts[2]:g} is below the lower bound {consts[1]:g}")
    return UNIT


def _where_range(ranges: Sequence[Range], consts: Consts) -> Range:
    return ranges[1].union(ranges[2])


def _min_range(ranges: Sequence[Range], consts: Consts) -> Range:
    return Range(min(r.lo for r in ranges), min(r.hi for r in ranges))


def _max_range(ranges: Sequence[Range], consts: Consts) -> Range:
    return Range(max(r.lo for r in ranges), max(r.hi for r in ranges))


def _sum_range(ranges: Sequence[Range], consts: Consts) -> Range:
    total = ranges[0]
    for r in ranges[1:]:
        total = range_add(total, r)
    return total


def _abs_range(ranges: Sequence[Range], consts: Consts) -> Range:
    r = ranges[0]
    if r.lo >= 0:
        return r
    if r.hi <= 0:
        return Range(-r.hi, -r.lo)
    return Range(0.0, max(-r.lo, r.hi))


def _sqrt_range(ranges: Sequence[Range], consts: Consts) -> Range:
    r = ranges[0]
    if r.lo < 0:
        raise SpecError(f"sqrt() of a value that may be negative (range {r})")
    return Range(math.sqrt(r.lo), math.sqrt(r.hi))


def _exp_range(ranges: Sequence[Range], consts: Consts) -> Range:
    r = ranges[0]
    if r.hi > math.log(MAX_MAGNITUDE):
        raise SpecError(f"exp() of a value that may reach {r.hi:g}; keep it below {math.log(MAX_MAGNITUDE):.1f}")
    return Range(math.exp(r.lo), math.exp(r.hi))


def _same_or_field(kinds: Sequence[Kind]) -> Kind:
    """where(): a mask when both branches are masks, else a float field."""
    return Kind.MASK if kinds[1] is Kind.MASK and kinds[2] is Kind.MASK else Kind.FIELD


# --------------------------------------------------------------------------------------------
# The table
# --------------------------------------------------------------------------------------------


def _op(
    name: str,
    args: Sequence[Arg],
    result: Kind | Callable[[Sequence[Kind]], Kind],
    impl: Kernel,
    rng: RangeFn,
    doc: str,
    example: str,
    **kw: Any,
) -> OpSpec:
    return OpSpec(name=name, args=tuple(args), result=result, impl=impl, range=rng, doc=doc, example=example, **kw)


_M = Arg("mask", MASK_ARG)
_X = Arg("x", VALUE_ARG)
_METRES = Arg("metres", NUM_ARG, const=True)

OPERATORS: dict[str, OpSpec] = {
    op.name: op
    for op in (
        _op(
            "AND",
            [Arg("a", MASK_ARG), Arg("b", MASK_ARG)],
            Kind.MASK,
            _and,
            _unit,
            "pixels in every mask",
            'AND(M["road"], M["bridge"])',
            variadic=True,
        ),
        _op(
            "OR",
            [Arg("a", MASK_ARG), Arg("b", MASK_ARG)],
            Kind.MASK,
            _or,
            _unit,
            "pixels in any mask",
            'OR(M["road"], M["trail"])',
            variadic=True,
        ),
        _op("NOT", [_M], Kind.MASK, _not, _unit, "pixels not in the mask", 'NOT(M["water"])'),
        _op(
            "REMOVE",
            [Arg("a", MASK_ARG), Arg("b", MASK_ARG)],
            Kind.MASK,
            _remove,
            _unit,
            "a and not b (hierarchy: a parent without its children)",
            'REMOVE(M["grass"], M["baseball field"])',
        ),
        _op(
            "distance",
            [_M, Arg("cap_metres", NUM_ARG, const=True)],
            Kind.FIELD,
            _distance,
            _distance_range,
            f"metres to the nearest mask pixel (0 inside), saturating at cap_metres "
            f"(default {DEFAULT_DISTANCE_CAP_M:g})",
            'distance(M["road"], 50)',
            n_optional=1,
            reach=_reach_at(1, default=DEFAULT_DISTANCE_CAP_M),
        ),
        _op(
            "near",
            [_M, _METRES],
            Kind.MASK,
            _near,
            _checked_unit(1),
            "pixels within `metres` of the mask (the mask included)",
            'near(M["road"], 5)',
            reach=_reach_at(1),
        ),
        _op(
            "far",
            [_M, _METRES],
            Kind.MASK,
            _far,
            _checked_unit(1),
            "pixels more than `metres` from the mask",
            'far(M["building"], 10)',
            reach=_reach_at(1),
        ),
        _op(
            "borders",
            [Arg("a", MASK_ARG), Arg("b", MASK_ARG), _METRES],
            Kind.MASK,
            _borders,
            _checked_unit(2),
            "pixels of a within `metres` of b",
            'borders(M["grass"], M["water"], 3)',
            reach=_reach_at(2),
        ),
        _op(
            "inside",
            [_M, _METRES],
            Kind.MASK,
            _inside,
            _checked_unit(1),
            "mask pixels at least `metres` from the mask's border",
            'inside(M["grass"], 2)',
            reach=_reach_at(1),
        ),
        _op(
            "centre",
            [_M, Arg("width_metres", NUM_ARG, const=True)],
            Kind.FIELD,
            _centre,
            _checked_unit(1, "width"),
            "0 on the centre line of a linear feature up to width_metres wide, rising to 1 at its "
            "border; 1 outside the mask",
            'centre(M["road"], 10)',
            reach=_reach_at(1, factor=1.0, roundings=2),
        ),
        _op(
            "edge",
            [_M, Arg("width_metres", NUM_ARG, const=True)],
            Kind.FIELD,
            _edge,
            _checked_unit(1, "width"),
            "low along the borders of a linear feature, 1 on its centre line and outside the mask",
            'edge(M["road"], 10)',
            reach=_reach_at(1, factor=1.0, roundings=2),
        ),
        _op(
            "clip",
            [_X, Arg("lo", NUM_ARG, const=True), Arg("hi", NUM_ARG, const=True)],
            Kind.FIELD,
            _clip,
            _clip_range,
            "x limited to [lo, hi]",
            "clip(cost, 0, 1)",
        ),
        _op(
            "where",
            [Arg("condition", MASK_ARG), Arg("a", VALUE_ARG), Arg("b", VALUE_ARG)],
            _same_or_field,
            _where,
            _where_range,
            "a where condition holds, else b",
            'where(M["bridge"], 0.2, cost)',
        ),
        _op(
            "normalize",
            [_X, Arg("lo", NUM_ARG, const=True), Arg("hi", NUM_ARG, const=True)],
            Kind.FIELD,
            _normalize,
            _normalize_range,
            "(x - lo) / (hi - lo) clipped to [0, 1]; without lo, hi: x's static range (constants "
            "derived from the program, never from the data)",
            "normalize(acc)",
            n_optional=2,
            signature="normalize(x[, lo, hi])",
        ),
        _op(
            "min",
            [Arg("a", VALUE_ARG), Arg("b", VALUE_ARG)],
            Kind.FIELD,
            _min,
            _min_range,
            "pixel-wise minimum",
            "min(acc, 1)",
            variadic=True,
        ),
        _op(
            "max",
            [Arg("a", VALUE_ARG), Arg("b", VALUE_ARG)],
            Kind.FIELD,
            _max,
            _max_range,
            "pixel-wise maximum",
            'max(cost, 0.8 * M["grass"])',
            variadic=True,
        ),
        _op(
            "sum",
            [Arg("a", VALUE_ARG), Arg("b", VALUE_ARG)],
            Kind.FIELD,
            _sum,
            _sum_range,
            "pixel-wise sum (flat, for many terms)",
            'sum(0.1 * P["road"], 0.5 * P["grass"])',
            variadic=True,
        ),
        _op("abs", [_X], Kind.FIELD, _abs, _abs_range, "absolute value", "abs(x - 0.5)"),
        _op(
            "sqrt",
            [_X],
            Kind.FIELD,
            _sqrt,
            _sqrt_range,
            "square root (x must be >= 0)",
            'sqrt(distance(M["road"], 20))',
        ),
        _op("exp", [_X], Kind.FIELD, _exp, _exp_range, "e ** x", 'exp(-distance(M["road"], 30) / 10)'),
    )
}


def reference_table() -> str:
    """The operator table as Markdown rows (for LANGUAGE.md and the LLM prompt)."""
    rows = ["| operator | returns | meaning | example |", "|---|---|---|---|"]
    for op in OPERATORS.values():
        result = op.result.value if isinstance(op.result, Kind) else "mask or field"
        rows.append(f"| `{op.arity_text()}` | {result} | {op.doc} | `{op.example}` |")
    return "\n".join(rows)


def terrain_table() -> str:
    """The terrain fields as Markdown rows (for LANGUAGE.md and the LLM prompt when a DEM is given)."""
    rows = ["| name | returns | meaning | example |", "|---|---|---|---|"]
    for t in TERRAIN.values():
        rows.append(f"| `{t.name}` | field in [{t.lo:g}, {t.hi:g}] {t.unit} | {t.doc} | `{t.example}` |")
    return "\n".join(rows)


def _arith(op: str, a: Value, b: Value) -> Value:
    if op == "+":
        return np.add(a, b, dtype=np.float64)
    if op == "-":
        return np.subtract(np.asarray(a, dtype=np.float64), b)
    if op == "*":
        return np.multiply(a, b, dtype=np.float64)
    if op == "/":
        return np.true_divide(a, b, dtype=np.float64)
    raise AssertionError(op)


_COMPARE: dict[str, np.ufunc] = {
    "<": np.less,
    "<=": np.less_equal,
    ">": np.greater,
    ">=": np.greater_equal,
    "==": np.equal,
    "!=": np.not_equal,
}


def apply_op(
    op: str, values: Sequence[Value], consts: Consts, sampling: Sampling, poll: Poll = never_cancelled
) -> Value:
    """Compute one operation of a checked program (arithmetic, comparison or a table operator)."""
    if op in ("+", "-", "*", "/"):
        return _arith(op, values[0], values[1])
    if op == "**":
        return safe_pow(values[0], _const(consts, 1))
    if op == "neg":
        return np.negative(np.asarray(values[0], dtype=np.float64))
    if op in _COMPARE:
        # a comparison ufunc gives a bool array, or np.bool_ on two 0-d values: a Value either way
        return cast(Value, _COMPARE[op](np.asarray(values[0], dtype=np.float64), values[1]))
    return OPERATORS[op].impl(values, consts, sampling, poll)


def apply_scalar(op: str, values: Sequence[npt.ArrayLike], consts: Consts) -> Value:
    """Apply an operator to constants (used by the checker to fold constant expressions)."""
    with np.errstate(all="ignore"):
        return apply_op(op, [np.asarray(v) for v in values], consts, (1.0, 1.0))
