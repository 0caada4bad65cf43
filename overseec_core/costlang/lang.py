"""Parse and check cost programs: Python-like text -> a small typed, bounded tree (never run as Python).

The text is parsed with :func:`ast.parse` (syntax only) and translated node by node into our own
frozen expression tree. Anything outside the closed grammar is refused with a
:class:`~overseec_core.errors.CostProgramError` carrying the line and column: attributes, imports,
loops, comprehensions, lambdas, keyword arguments, subscripts other than ``M["entity"]`` /
``P["entity"]``, names not assigned earlier, unknown operators or entities, wrong arity, a mask
where a number belongs and vice versa, radii above the limit, and programs over the size limits.

Every expression gets a static kind (number, mask, field), a static range (interval arithmetic:
a program that could divide by zero, take a root of a negative value or overflow is refused before
it runs) and a spatial reach in metres (the halo block-wise evaluation needs). The result,
:class:`Program`, is what the evaluator walks.
"""

from __future__ import annotations

import ast
import difflib
import math
import re
import warnings
from collections.abc import Callable, Sequence

from overseec_core.costlang.ops import (
    MAX_MAGNITUDE,
    MAX_RADIUS_M,
    MAX_VARIADIC,
    OPERATORS,
    TERRAIN,
    UNIT,
    Arg,
    Kind,
    OpSpec,
    Range,
    SpecError,
    apply_scalar,
    range_add,
    range_div,
    range_mul,
    range_pow,
    range_sub,
)
from overseec_core.costlang.tree import Apply, Assign, Const, Expr, Layer, Program, Terrain, Var
from overseec_core.errors import CostProgramError

#: Size limits (checked before anything else is done with the text).
MAX_PROGRAM_CHARS = 20_000
MAX_NODES = 5_000
MAX_DEPTH = 64
MAX_STATEMENTS = 400
#: Largest total reach (nested spatial operators add up), metres.
MAX_REACH_M = 2 * MAX_RADIUS_M

#: Names a program reads entity data through: M["x"] (bool mask), P["x"] (gated probability).
TABLES = ("M", "P")
#: The variables a program defines for the costmap.
COST, LETHAL, KEEP_OUT = "cost", "lethal", "keep_out"

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")

#: Internal operators the syntax maps to (arithmetic, comparison); the table holds the rest.
_ARITH = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_CMP = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="}
_BITS = {ast.BitAnd: "AND", ast.BitOr: "OR"}

#: A syntax node with a position (what the checked tree records as line and column).
_Located = ast.expr | ast.stmt

_NOT_ALLOWED = {
    ast.Attribute: "attribute access (a.b)",
    ast.Lambda: "lambda",
    ast.ListComp: "a comprehension",
    ast.SetComp: "a comprehension",
    ast.DictComp: "a comprehension",
    ast.GeneratorExp: "a generator",
    ast.List: "a list",
    ast.Tuple: "a tuple",
    ast.Set: "a set",
    ast.Dict: "a dict",
    ast.Starred: "*unpacking",
    ast.JoinedStr: "an f-string",
    ast.FormattedValue: "an f-string",
    ast.Await: "await",
    ast.Yield: "yield",
    ast.YieldFrom: "yield",
    ast.NamedExpr: "the := operator",
    ast.Slice: "a slice",
}


# --------------------------------------------------------------------------------------------
# The checked tree
# --------------------------------------------------------------------------------------------


# --------------------------------------------------------------------------------------------
# Checking
# --------------------------------------------------------------------------------------------


def _err(node: ast.AST | None, message: str) -> CostProgramError:
    if node is None or not hasattr(node, "lineno"):
        return CostProgramError(message, None, None)
    return CostProgramError(message, node.lineno, getattr(node, "col_offset", None))


def normalise_entity_name(name: str) -> str:
    """How entity names are matched: case-insensitive, whitespace collapsed."""
    return " ".join(str(name).split()).casefold()


def _check_size(text: str) -> ast.Module:  # noqa: C901
    if not isinstance(text, str):
        raise CostProgramError("a cost program must be text", None, None)
    if len(text) > MAX_PROGRAM_CHARS:
        raise CostProgramError(f"the program has {len(text)} characters; at most {MAX_PROGRAM_CHARS} are allowed", 1, 0)
    if not text.strip():
        raise CostProgramError('the program is empty; it must assign cost, e.g. cost = 0.5 * M["grass"]', 1, 0)
    try:
        with warnings.catch_warnings():  # e.g. "invalid escape sequence" in a user's string literal
            warnings.simplefilter("ignore")
            tree = ast.parse(text, mode="exec")
    except SyntaxError as exc:
        msg = (exc.msg or "invalid syntax").split("\n")[0]
        raise CostProgramError(f"syntax error: {msg}", exc.lineno or 1, max((exc.offset or 1) - 1, 0)) from None
    except (ValueError, RecursionError, MemoryError, OverflowError) as exc:
        raise CostProgramError(
            f"the program cannot be parsed ({type(exc).__name__}: {str(exc)[:80]}); simplify it", 1, 0
        ) from None
    # Size and depth without recursion (a hostile tree may be very deep).
    count = 0
    stack: list[tuple[ast.AST, int]] = [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        count += 1
        if count > MAX_NODES:
            raise _err(node, f"the program is too large (over {MAX_NODES} syntax nodes); simplify it")
        if depth > MAX_DEPTH:
            raise _err(
                node, f"expressions are nested too deeply (over {MAX_DEPTH} levels); split them into named steps"
            )
        for child in ast.iter_child_nodes(node):
            if not isinstance(child, (ast.expr_context, ast.operator, ast.unaryop, ast.cmpop, ast.boolop)):
                stack.append((child, depth + 1))
    if len(tree.body) > MAX_STATEMENTS:
        raise _err(tree.body[MAX_STATEMENTS], f"the program has over {MAX_STATEMENTS} statements")
    return tree


class _Checker:
    """Translates an ``ast`` tree into checked :class:`Expr` nodes, one statement at a time."""

    def __init__(self, entity_names: Sequence[str]) -> None:
        self.entities: dict[str, str] = {}
        for name in entity_names:
            self.entities.setdefault(normalise_entity_name(name), str(name))
        self.env: dict[str, Expr] = {}
        self.used_entities: list[str] = []
        self.used_layers: list[tuple[str, str]] = []
        self.terrain_uses: dict[str, tuple[int, int]] = {}

    # -- statements --------------------------------------------------------------------------

    def statement(self, node: ast.stmt) -> Assign | None:
        if _is_comment(node):
            return None
        if isinstance(node, ast.Assign):
            if len(node.targets) != 1:
                raise _err(node, "assign one name at a time (a = b = ... is not allowed)")
            target = self.target(node.targets[0])
            value = self.expr(node.value)
        elif isinstance(node, ast.AugAssign):
            target = self.target(node.target)
            if target not in self.env:
                raise _err(node.target, f"'{target}' is updated before it is assigned")
            op = _ARITH.get(type(node.op))
            if op is None:
                raise _err(node, "only +=, -=, *=, /= and **= are allowed")
            left = Var(
                node.lineno,
                node.col_offset,
                self.env[target].kind,
                self.env[target].range,
                self.env[target].reach,
                name=target,
            )
            value = self.arith(node, op, self._inline(left), self.expr(node.value))
        elif isinstance(node, ast.AnnAssign):
            raise _err(node, "type annotations are not allowed; write name = expression")
        elif isinstance(node, ast.Expr):
            raise _err(node, "a bare expression does nothing; assign it, e.g. cost = ...")
        else:
            what = type(node).__name__.lower()
            raise _err(node, f"only assignments are allowed in a cost program (found '{what}')")
        self.env[target] = value
        return Assign(target, value, node.lineno, node.col_offset)

    def target(self, node: ast.expr) -> str:
        if not isinstance(node, ast.Name):
            raise _err(node, "only plain names can be assigned (no subscripts, attributes or tuples)")
        name = node.id
        if not _NAME.match(name):
            raise _err(node, f"name '{name}' is not allowed (names start with a letter)")
        if name in TABLES:
            raise _err(node, f"'{name}' is the entity table and cannot be assigned")
        if name in OPERATORS:
            raise _err(node, f"'{name}' is an operator and cannot be assigned")
        if name in TERRAIN:
            raise _err(node, f"'{name}' is the terrain field of the DEM (--dem) and cannot be assigned")
        return name

    # -- expressions -------------------------------------------------------------------------

    def expr(self, node: ast.expr) -> Expr:
        for bad, what in _NOT_ALLOWED.items():
            if isinstance(node, bad):
                raise _err(node, f"{what} is not allowed in a cost program")
        method: Callable[[ast.expr], Expr] | None = getattr(self, f"_{type(node).__name__}", None)
        if method is None:
            raise _err(node, f"'{type(node).__name__}' is not allowed in a cost program")
        return method(node)

    def _Constant(self, node: ast.Constant) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        v = node.value
        if isinstance(v, bool):
            return Const(node.lineno, node.col_offset, Kind.MASK, Range.of(float(v)), value=v)
        if isinstance(v, (int, float)):
            if isinstance(v, int) and abs(v) > MAX_MAGNITUDE:
                raise _err(node, f"number {str(v)[:20]} is beyond ±{MAX_MAGNITUDE:g}")
            value = float(v)
            if not math.isfinite(value) or abs(value) > MAX_MAGNITUDE:
                raise _err(node, f"number {v!r} is not finite or beyond ±{MAX_MAGNITUDE:g}")
            return Const(node.lineno, node.col_offset, Kind.NUM, Range.of(value), value=value)
        if isinstance(v, str):
            raise _err(node, 'text is only allowed as an entity name, as in M["road"] or P["road"]')
        raise _err(node, f"constant {type(v).__name__} is not allowed (numbers, True and False only)")

    def _Name(self, node: ast.Name) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        name = node.id
        if name in self.env:
            bound = self.env[name]
            return self._inline(Var(node.lineno, node.col_offset, bound.kind, bound.range, bound.reach, name=name))
        if name in TERRAIN:
            spec = TERRAIN[name]
            self.terrain_uses.setdefault(name, (node.lineno, node.col_offset))
            return Terrain(node.lineno, node.col_offset, Kind.FIELD, Range(spec.lo, spec.hi), name=name)
        if name in TABLES:
            raise _err(node, f'{name} is the entity table; write {name}["entity name"]')
        if name in OPERATORS:
            raise _err(node, f"{name} is an operator; call it as {OPERATORS[name].arity_text()}")
        if name in (COST, LETHAL, KEEP_OUT):
            raise _err(node, f"'{name}' is read before it is assigned")
        raise _err(
            node,
            f"unknown name '{name}' (not assigned earlier; entity masks are written "
            'M["name"], probabilities P["name"])',
        )

    def _inline(self, var: Var) -> Expr:
        """A name bound to a constant is that constant (so radii may be named)."""
        bound = self.env[var.name]
        if isinstance(bound, Const):
            return Const(var.line, var.col, bound.kind, bound.range, value=bound.value)
        return var

    def _Subscript(self, node: ast.Subscript) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        table = node.value.id if isinstance(node.value, ast.Name) else None
        if table not in TABLES:
            raise _err(node, 'only the entity tables can be indexed: M["entity"] or P["entity"]')
        key = node.slice
        if not (isinstance(key, ast.Constant) and isinstance(key.value, str)):
            raise _err(node, f'{table}[...] takes an entity name in quotes, e.g. {table}["road"]')
        canon = self.entities.get(normalise_entity_name(key.value))
        if canon is None:
            known = sorted(self.entities.values())
            close = difflib.get_close_matches(key.value, known, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            listing = ", ".join(known) if known else "none"
            raise _err(key, f"unknown entity '{key.value}' (known entities: {listing}){hint}")
        if canon not in self.used_entities:
            self.used_entities.append(canon)
        if (table, canon) not in self.used_layers:
            self.used_layers.append((table, canon))
        kind = Kind.MASK if table == "M" else Kind.FIELD
        return Layer(node.lineno, node.col_offset, kind, UNIT, table=table, entity=canon)

    def _BinOp(self, node: ast.BinOp) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        left, right = self.expr(node.left), self.expr(node.right)
        if type(node.op) in _BITS:
            return self.apply_op(node, OPERATORS[_BITS[type(node.op)]], [left, right])
        op = _ARITH.get(type(node.op))
        if op is None:
            sym = {
                ast.Mod: "%",
                ast.FloorDiv: "//",
                ast.MatMult: "@",
                ast.LShift: "<<",
                ast.RShift: ">>",
                ast.BitXor: "^",
            }.get(type(node.op), "this operator")
            raise _err(node, f"operator {sym} is not supported (use + - * / ** and AND/OR/NOT)")
        return self.arith(node, op, left, right)

    def _value(self, node: ast.AST, e: Expr, what: str) -> None:
        if e.kind not in (Kind.NUM, Kind.FIELD, Kind.MASK):
            raise _err(node, f"{what} must be a number, mask or field")

    def arith(self, node: _Located, op: str, left: Expr, right: Expr) -> Expr:
        try:
            if op == "**":
                if not (isinstance(right, Const) and right.kind is Kind.NUM):
                    raise SpecError("the exponent of ** must be a constant number")
                rng = range_pow(left.range, float(right.value))
            else:
                fn = {"+": range_add, "-": range_sub, "*": range_mul, "/": range_div}[op]
                rng = fn(left.range, right.range)
        except SpecError as exc:
            raise _err(node, str(exc)) from None
        return self._make(node, op, [left, right], Kind.FIELD, rng, (0.0, 0))

    def _UnaryOp(self, node: ast.UnaryOp) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        operand = self.expr(node.operand)
        if isinstance(node.op, (ast.Not, ast.Invert)):
            return self.apply_op(node, OPERATORS["NOT"], [operand])
        if isinstance(node.op, ast.UAdd):
            return operand
        r = operand.range
        return self._make(node, "neg", [operand], Kind.FIELD, Range(-r.hi, -r.lo), (0.0, 0))

    def _BoolOp(self, node: ast.BoolOp) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        name = "AND" if isinstance(node.op, ast.And) else "OR"
        return self.apply_op(node, OPERATORS[name], [self.expr(v) for v in node.values])

    def _Compare(self, node: ast.Compare) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        left = self.expr(node.left)
        parts = []
        for op, comp in zip(node.ops, node.comparators):
            sym = _CMP.get(type(op))
            if sym is None:
                raise _err(node, "only < <= > >= == != comparisons are allowed (no 'in' or 'is')")
            right = self.expr(comp)
            parts.append(self._make(node, sym, [left, right], Kind.MASK, UNIT, (0.0, 0)))
            left = right
        if len(parts) == 1:
            return parts[0]
        return self.apply_op(node, OPERATORS["AND"], parts)

    def _IfExp(self, node: ast.IfExp) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        return self.apply_op(
            node, OPERATORS["where"], [self.expr(node.test), self.expr(node.body), self.expr(node.orelse)]
        )

    def _Call(self, node: ast.Call) -> Expr:  # noqa: N802 (named after the ast node class; see expr)
        if not isinstance(node.func, ast.Name):
            raise _err(node, "only operators from the table can be called, by name")
        name = node.func.id
        op = OPERATORS.get(name)
        if op is None:
            known = ", ".join(OPERATORS)
            close = difflib.get_close_matches(name, list(OPERATORS), n=1)
            hint = f"; did you mean {close[0]}?" if close else ""
            raise _err(node.func, f"unknown operator '{name}'{hint} (operators: {known})")
        if node.keywords:
            raise _err(node, f"keyword arguments are not supported; pass them in order: {op.arity_text()}")
        for a in node.args:
            if isinstance(a, ast.Starred):
                raise _err(a, "*unpacking is not allowed in a cost program")
        args = [self.expr(a) for a in node.args]
        n, n_formal = len(node.args), len(op.args)
        if op.variadic:
            ok = n_formal <= n <= MAX_VARIADIC
        else:
            ok = n_formal - op.n_optional <= n <= n_formal
        if not ok:
            if op.variadic and n > MAX_VARIADIC:
                raise _err(node, f"{name}() takes at most {MAX_VARIADIC} arguments, got {n}")
            raise _err(node, f"{name}() takes {self._count_text(op)}, got {n}: {op.arity_text()}")
        return self.apply_op(node, op, args, arg_nodes=node.args)

    @staticmethod
    def _count_text(op: OpSpec) -> str:
        n = len(op.args)
        if op.variadic:
            return f"at least {n} arguments"
        if op.n_optional:
            return f"{n - op.n_optional} to {n} arguments"
        return f"{n} argument{'s' if n != 1 else ''}"

    def apply_op(
        self, node: _Located, op: OpSpec, args: list[Expr], arg_nodes: Sequence[ast.expr] | None = None
    ) -> Expr:
        formals: list[Arg] = list(op.args)
        if op.variadic:
            formals += [op.args[-1]] * (len(args) - len(formals))
        for i, (formal, arg) in enumerate(zip(formals, args)):
            where = arg_nodes[i] if arg_nodes else node
            if arg.kind not in formal.kinds:
                raise _err(where, self._kind_error(op, i, formal, arg))
            if formal.const and not isinstance(arg, Const):
                raise _err(where, f"argument {i + 1} ({formal.name}) of {op.name}() must be a constant number")
        consts = [float(a.value) if isinstance(a, Const) else None for a in args]
        ranges = [a.range for a in args]
        if op.name == "normalize" and len(args) == 1:
            lo, hi = ranges[0].lo, ranges[0].hi
            consts += [lo, hi]
        try:
            rng = op.range(ranges, consts)
            reach = op.reach(consts) if op.reach else (0.0, 0)
        except SpecError as exc:
            raise _err(node, f"{op.name}(): {exc}") from None
        kind = op.result_kind([a.kind for a in args])
        return self._make(node, op.name, args, kind, rng, reach, consts)

    @staticmethod
    def _kind_error(op: OpSpec, i: int, formal: Arg, arg: Expr) -> str:
        want = " or ".join(k.describe() for k in formal.kinds)
        hint = ""
        if Kind.MASK in formal.kinds and arg.kind is Kind.FIELD:
            hint = " (compare it to make a mask, e.g. x > 0.5, or use M[...] instead of P[...])"
        elif formal.kinds == (Kind.NUM,):
            hint = " (a constant, e.g. 10)"
        return f"argument {i + 1} ({formal.name}) of {op.name}() must be {want}, got {arg.kind.describe()}{hint}"

    def _make(
        self,
        node: _Located,
        op: str,
        args: Sequence[Expr],
        kind: Kind,
        rng: Range,
        own_reach: tuple[float, int],
        consts: Sequence[float | None] | None = None,
    ) -> Expr:
        child_m = max((a.reach[0] for a in args), default=0.0)
        child_r = max((a.reach[1] for a in args), default=0)
        reach = (own_reach[0] + child_m, own_reach[1] + child_r)
        if reach[0] > MAX_REACH_M:
            raise _err(node, f"nested spatial operators reach {reach[0]:g} m; at most {MAX_REACH_M:g} m in all")
        if consts is None:
            consts = [float(a.value) if isinstance(a, Const) else None for a in args]
        line, col = node.lineno, node.col_offset
        const_args = [a for a in args if isinstance(a, Const)]
        if len(const_args) == len(args) and own_reach == (0.0, 0):
            return self._fold(node, op, const_args, kind, consts)
        if kind is Kind.MASK:
            rng = UNIT
        return Apply(line, col, kind, rng, reach, op=op, args=tuple(args), consts=tuple(consts))

    def _fold(
        self, node: _Located, op: str, args: Sequence[Const], kind: Kind, consts: Sequence[float | None]
    ) -> Const:
        """Evaluate an operator on constants now (ranges were checked, so this is safe)."""
        value = apply_scalar(op, [a.value for a in args], consts)
        if kind is Kind.MASK:
            b = bool(value)
            return Const(node.lineno, node.col_offset, Kind.MASK, Range.of(float(b)), value=b)
        v = float(value)
        if not math.isfinite(v) or abs(v) > MAX_MAGNITUDE:
            raise _err(node, f"this constant expression gives {v!r}, beyond ±{MAX_MAGNITUDE:g}")
        return Const(node.lineno, node.col_offset, Kind.NUM, Range.of(v), value=v)


def _is_comment(node: ast.stmt) -> bool:
    """A bare string statement (a docstring) is a comment."""
    return isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str)


def check_program(text: str, entity_names: Sequence[str]) -> Program:
    """Parse and validate a cost program against the entities that have masks.

    Raises :class:`CostProgramError` (message, line, col) on anything invalid; returns a
    :class:`Program` that :func:`~overseec_core.costlang.evaluate_program` can run on any block of masks.
    """
    tree = _check_size(text)
    checker = _Checker(entity_names)
    statements = []
    for node in tree.body:
        assign = checker.statement(node)
        if assign is not None:
            statements.append(assign)
    if not tree.body or all(_is_comment(node) for node in tree.body):
        raise CostProgramError('the program is empty; it must assign cost, e.g. cost = 0.5 * M["grass"]', 1, 0)
    if COST not in checker.env:
        raise CostProgramError(
            "the program never assigns cost; end it with e.g. cost = ...",
            (tree.body[-1].end_lineno or 1) if tree.body else 1,
            0,
        )
    cost = checker.env[COST]
    warnings = []
    lethal = checker.env.get(LETHAL)
    if lethal is not None and lethal.kind is not Kind.MASK:
        last = next(s for s in reversed(statements) if s.target == LETHAL)
        raise CostProgramError(
            f"lethal must be a mask (where the robot may not go), got {lethal.kind.describe()}", last.line, last.col
        )
    keep_out = checker.env.get(KEEP_OUT)
    if keep_out is not None and keep_out.kind is not Kind.MASK:
        last = next(s for s in reversed(statements) if s.target == KEEP_OUT)
        raise CostProgramError(
            f"keep_out must be a mask (where a distance rule forbids going), got {keep_out.kind.describe()}",
            last.line,
            last.col,
        )
    if cost.range.lo < 0 or cost.range.hi > 1:
        warnings.append(
            f"cost may range over {cost.range}; values outside [0, 1] are clipped (use normalize() to rescale)"
        )
    reach_m = max((s.value.reach[0] for s in statements), default=0.0)
    roundings = max((s.value.reach[1] for s in statements), default=0)
    return Program(
        text=text,
        statements=tuple(statements),
        entities=tuple(checker.used_entities),
        layers=tuple(checker.used_layers),
        reach_m=reach_m,
        roundings=roundings,
        cost_range=cost.range,
        has_lethal=lethal is not None,
        has_keep_out=keep_out is not None,
        warnings=tuple(warnings),
        terrain_uses=tuple((name, line, col) for name, (line, col) in checker.terrain_uses.items()),
    )
