"""Parsing and checking cost programs: the closed grammar, kinds, ranges, limits, line/column."""

from __future__ import annotations

import pytest

from overseec_core.costlang import MAX_DEPTH, MAX_PROGRAM_CHARS, OPERATORS, check_program
from overseec_core.costlang.ops import Kind
from overseec_core.costlang.tree import Apply, Const
from overseec_core.errors import CostProgramError, OverseecError

ENTITIES = ("road", "trail", "grass", "baseball field", "building", "water")


def error(text: str) -> CostProgramError:
    with pytest.raises(CostProgramError) as info:
        check_program(text, ENTITIES)
    return info.value


def test_a_valid_program_is_checked_into_a_tree():
    p = check_program('w = 0.5\nacc = w * P["grass"] + 0.1 * M["road"]\ncost = acc\nlethal = M["water"]', ENTITIES)
    assert [s.target for s in p.statements] == ["w", "acc", "cost", "lethal"]
    assert p.entities == ("grass", "road", "water")
    assert ("P", "grass") in p.layers and ("M", "road") in p.layers
    assert p.has_lethal
    assert (p.cost_range.lo, p.cost_range.hi) == pytest.approx((0.0, 0.6))
    assert p.halo((0.5, 0.5)) == (0, 0)


def test_errors_are_overseec_errors_with_line_and_column():
    e = error('a = M["road"]\n\ncost = a.b')
    assert isinstance(e, OverseecError) and isinstance(e, ValueError)
    assert (e.line, e.col) == (3, 7)
    assert "attribute" in e.message
    assert str(e).startswith("line 3, column 7: ")


@pytest.mark.parametrize(
    "text, fragment, where",
    [
        ('cost = __import__("os")', "unknown operator '__import__'", (1, 7)),
        ("import os\ncost = 1", "only assignments", (1, 0)),
        ("from os import path\ncost = 1", "only assignments", (1, 0)),
        ("for i in M:\n    cost = 1", "only assignments", (1, 0)),
        ("while True:\n    cost = 1", "only assignments", (1, 0)),
        ("def f():\n    return 1\ncost = 1", "only assignments", (1, 0)),
        ("if True:\n    cost = 1", "only assignments", (1, 0)),
        ('cost = M["road"].__class__', "attribute access", (1, 7)),
        ("cost = ().__class__.__bases__[0]", "only the entity tables", (1, 7)),
        ("cost = ().__class__", "attribute access", (1, 7)),
        ("cost = (lambda: 1)()", "only operators from the table", (1, 7)),
        ("cost = [1, 2]", "a list", (1, 7)),
        ("cost = sum([1, 2])", "a list", (1, 11)),
        ("cost = max(x for x in M)", "a generator", None),
        ('cost = f"{1}"', "f-string", (1, 7)),
        ("cost = 1 % 2", "operator %", (1, 7)),
        ("cost = 7 // 2", "operator //", (1, 7)),
        ('cost = M["road"] ^ M["grass"]', "operator ^", (1, 7)),
        ('cost = near(M["road"], metres=5)', "keyword arguments", (1, 7)),
        ('a = (M["road"], 5)\ncost = near(*a)', "a tuple", (1, 4)),
        ("cost = M[0]", "entity name in quotes", (1, 7)),
        ('cost = M["road"][0]', "only the entity tables", (1, 7)),
        ('x = {"a": 1}\ncost = 1', "a dict", (1, 4)),
        ('cost = Q["road"]', "only the entity tables", (1, 7)),
        ('cost = M["rood"]', "unknown entity 'rood'", (1, 9)),
        ("cost = foo(1)", "unknown operator 'foo'", (1, 7)),
        ("cost = open('/etc/passwd')", "unknown operator 'open'", (1, 7)),
        ("cost = x + 1", "unknown name 'x'", (1, 7)),
        ("cost = near", "is an operator", (1, 7)),
        ("cost = M", "entity table", (1, 7)),
        ("M = 1\ncost = 1", "cannot be assigned", (1, 0)),
        ("near = 1\ncost = 1", "cannot be assigned", (1, 0)),
        ("_x = 1\ncost = 1", "not allowed", (1, 0)),
        ("a = b = 1\ncost = 1", "one name at a time", (1, 0)),
        ("a, b = 1, 2\ncost = 1", "only plain names", (1, 0)),
        ("cost: float = 1", "annotations", (1, 0)),
        ("cost = 1\ncost", "does nothing", (2, 0)),
        ("x = 1", "never assigns cost", (1, 0)),
        ("cost = None", "constant NoneType", (1, 7)),
        ("cost = 'road'", "entity name", (1, 7)),
        ("cost = 1e999", "not finite", (1, 7)),
        ("cost = -1e999", "not finite", (1, 8)),
        ("cost = 10**10**10", "exponent", (1, 11)),
        ("cost = 2 ** 300", "exponent", (1, 7)),
        ("cost = 1 / 0", "may be zero", (1, 7)),
        ('cost = 1 / distance(M["road"], 10)', "may be zero", (1, 7)),
        ('cost = 1 / (M["road"] - 0.5)', "may be zero", (1, 7)),
        ('cost = sqrt(P["road"] - 0.5)', "may be negative", (1, 7)),
        ('cost = (P["road"] - 0.5) ** 0.5', "fractional power", (1, 7)),
        ('cost = exp(distance(M["road"], 100))', "exp()", (1, 7)),
        ("cost = 1e11 * 1e11", "beyond", (1, 7)),
        ('cost = 1e6 * P["road"] * 1e6 * P["grass"] * 10', "beyond", (1, 7)),
        ('cost = near(M["road"], 600)', "outside (0, 500]", (1, 7)),
        ('cost = near(M["road"], 0)', "outside (0, 500]", (1, 7)),
        ('cost = near(M["road"], -5)', "outside (0, 500]", (1, 7)),
        ('cost = distance(M["road"], 501)', "outside (0, 500]", (1, 7)),
        ('cost = near(M["road"])', "takes 2 arguments, got 1", (1, 7)),
        ('cost = NOT(M["road"], M["grass"])', "takes 1 argument, got 2", (1, 7)),
        ('cost = AND(M["road"])', "at least 2 arguments", (1, 7)),
        ('cost = normalize(P["road"], 0)', "both bounds", (1, 7)),
        ('cost = normalize(P["road"], 1, 0)', "below the lower bound", (1, 7)),
        ('cost = clip(P["road"], 1, 0)', "above its upper bound", (1, 7)),
        ('cost = AND(P["road"], M["grass"])', "must be a mask, got a float field", (1, 11)),
        ("cost = NOT(0.5)", "must be a mask, got a number", (1, 11)),
        ('cost = ~P["road"]', "must be a mask", (1, 7)),
        ('cost = where(P["road"], 1, 0)', "must be a mask", (1, 13)),
        ('cost = 1 if P["road"] else 0', "must be a mask", (1, 7)),
        ('cost = near(M["road"], P["grass"])', "must be a number", (1, 23)),
        ('r = P["grass"] * 5\ncost = near(M["road"], r)', "must be a number", (2, 23)),
        ('cost = P["road"] ** P["grass"]', "exponent of ** must be a constant", (1, 7)),
        ('cost = 0.5\nlethal = P["water"]', "lethal must be a mask", (2, 0)),
        ('cost = M["road"] in M["grass"]', "comparisons are allowed", (1, 7)),
        ("cost = y\ny = 1", "unknown name 'y'", (1, 7)),
        ("cost = cost + 1", "read before it is assigned", (1, 7)),
        ("acc += 1\ncost = 1", "before it is assigned", (1, 0)),
        ("cost = 1\ncost %= 2", "only +=", (2, 0)),
        ("cost = (1", "syntax error", None),
        ("cost = 1\n  x = 2", "syntax error", None),
        ("", "empty", (1, 0)),
        ("   \n# only a comment\n", "empty", (1, 0)),
        ("cost = 1\x00", "", None),
    ],
)
def test_invalid_programs_are_refused_with_a_located_message(text, fragment, where):
    e = error(text)
    assert fragment in e.message
    assert e.line is not None and e.col is not None
    if where is not None:
        assert (e.line, e.col) == where


def test_unknown_entity_lists_the_known_ones_and_suggests():
    e = error('cost = P["baseball feld"]')
    assert "baseball field" in e.message and "did you mean 'baseball field'" in e.message
    assert "road" in e.message and "water" in e.message


def test_entity_names_match_case_and_space_insensitively_to_canonical_names():
    p = check_program('cost = M["Baseball   Field"] | M["ROAD"]', ENTITIES)
    assert p.entities == ("baseball field", "road")


def test_size_limits_refuse_before_parsing():
    big = "cost = " + " + ".join(["1"] * 1_000_000)
    e = error(big)
    assert "characters" in e.message and str(MAX_PROGRAM_CHARS) in e.message


def test_deep_nesting_is_refused():
    """The depth check (not the parser) refuses it, at the first call deeper than MAX_DEPTH: the
    module is level 0, the assignment 1, the k-th NOT( call k + 1, so the 64th NOT, at column
    7 + 4 * 63."""
    nested = "cost = " + "NOT(" * 80 + 'M["road"]' + ")" * 80
    e = error(nested)
    assert type(e) is CostProgramError
    assert e.message == (f"expressions are nested too deeply (over {MAX_DEPTH} levels); split them into named steps")
    assert (e.line, e.col) == (1, 7 + 4 * (MAX_DEPTH - 1))
    # 61 calls put the road's name at level MAX_DEPTH exactly: still accepted
    assert check_program("cost = " + "NOT(" * 61 + 'M["road"]' + ")" * 61, ENTITIES).entities == ("road",)


def test_deep_parentheses_and_long_unary_chains_are_refused_not_crashing():
    for text in (
        "cost = " + "(" * 300 + "1" + ")" * 300,
        "cost = " + "-" * 19_000 + "1",
        "cost = " + "not " * 4_000 + 'M["road"]',
        "cost = " + "+".join(["1"] * 6_000),
    ):
        e = error(text)
        assert e.line is not None


def test_too_many_nodes_is_refused():
    text = "\n".join(f"a{i} = 1 + 2 + 3 + 4 + 5 + 6 + 7 + 8 + 9 + 10" for i in range(350)) + "\ncost = 1"
    assert "too large" in error(text).message


def test_variadic_limit():
    text = "cost = max(" + ", ".join(['P["road"]'] * 65) + ")"
    assert "at most 64" in error(text).message


def test_nested_spatial_reach_adds_up_and_is_limited():
    p = check_program('a = near(M["road"], 10)\nb = near(a, 5)\ncost = distance(b, 20)', ENTITIES)
    assert p.reach_m == pytest.approx(35.0)
    assert p.roundings == 3
    assert p.halo((0.5, 0.25)) == (35 / 0.25 + 3, 35 / 0.5 + 3)
    text = 'a0 = M["road"]\n' + "\n".join(f"a{i + 1} = near(a{i}, 400)" for i in range(3)) + "\ncost = a3"
    assert "reach" in error(text).message


def test_centre_and_edge_reach_a_full_width_with_two_roundings():
    p = check_program('cost = centre(M["road"], 8)', ENTITIES)
    assert (p.reach_m, p.roundings) == (8.0, 2)
    assert p.halo((1.0, 1.0)) == (10, 10)


def test_constants_are_folded_and_names_of_constants_are_inlined():
    p = check_program('r = 2 * 5\nw = r / 20\ncost = near(M["road"], r) * w', ENTITIES)
    assert isinstance(p.statements[0].value, Const) and p.statements[0].value.value == 10.0
    mul = p.statements[2].value
    assert isinstance(mul, Apply) and mul.args[0].consts == (None, 10.0)
    assert p.reach_m == 10.0


def test_static_ranges_follow_interval_arithmetic():
    p = check_program('acc = 0.5 * P["grass"] + 1.0 * P["baseball field"]\ncost = normalize(acc)', ENTITIES)
    acc = p.statements[0].value
    assert (acc.range.lo, acc.range.hi) == (0.0, 1.5)
    norm = p.statements[1].value
    assert norm.consts == (None, 0.0, 1.5)
    assert p.warnings == ()


def test_cost_that_can_leave_the_unit_range_warns():
    p = check_program('cost = 2 * P["road"] - 0.5', ENTITIES)
    assert len(p.warnings) == 1 and "clipped" in p.warnings[0]


def test_kinds_promote_masks_in_arithmetic_and_comparisons_make_masks():
    p = check_program(
        'a = M["road"] * 0.5\nb = P["road"] > 0.3\nc = 1 < P["grass"] <= 2\n'
        'd = b & ~c | M["water"] and not M["road"]\ncost = where(d, a, 1)',
        ENTITIES,
    )
    kinds = [s.value.kind for s in p.statements]
    assert kinds == [Kind.FIELD, Kind.MASK, Kind.MASK, Kind.MASK, Kind.FIELD]


def test_augmented_assignment_and_comments_and_docstrings():
    p = check_program(
        '"""a docstring"""\n# a comment\ncost = 0.1 * M["road"]  # trailing\ncost += 0.2 * M["grass"]\ncost *= 0.5',
        ENTITIES,
    )
    assert [s.target for s in p.statements] == ["cost", "cost", "cost"]
    assert (p.cost_range.lo, p.cost_range.hi) == pytest.approx((0.0, 0.15))


def test_true_false_constants_are_masks():
    p = check_program("cost = 0.2\nlethal = False", ENTITIES)
    assert p.has_lethal
    assert check_program("cost = where(True, 0.1, 0.9)", ENTITIES).statements[0].value.value == 0.1


def test_every_operator_is_documented_with_an_example_that_checks():
    from overseec_core.costlang import LANGUAGE_FILE

    text = LANGUAGE_FILE.read_text()
    for name, op in OPERATORS.items():
        assert f"`{name}(" in text, name
        example = op.example
        names = ENTITIES + ("bridge",)
        prefix = 'x = P["road"]\nacc = P["grass"]\ncost = 0.5\n'
        check_program(prefix + f"y = {example}\ncost = 0.5", names)
