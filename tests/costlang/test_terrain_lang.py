"""The terrain fields in the language: documented, reserved, typed, ranged, and read from the block."""

from __future__ import annotations

import numpy as np
import pytest

from overseec_core.costlang import LANGUAGE_FILE, check_program, evaluate_program
from overseec_core.costlang.ops import TERRAIN, terrain_table
from overseec_core.errors import CostProgramError


def test_every_terrain_field_is_documented_with_an_example_that_checks() -> None:
    text = LANGUAGE_FILE.read_text()
    table = terrain_table()
    for name, spec in TERRAIN.items():
        assert f"`{name}`" in text and f"`{name}`" in table
        program = check_program(f"cost = 0.5\ncost = {spec.example}\n", [])
        assert program.terrain == (name,)
        assert 0.0 <= program.cost_range.lo and program.cost_range.hi <= 1.0


def test_terrain_uses_record_the_first_line() -> None:
    program = check_program("a = 0.5\ncost = max(a, roughness / 10000)\ncost = max(cost, slope / 90)\n", [])
    assert program.terrain_uses == (("roughness", 2, 14), ("slope", 3, 17))
    assert program.reach_m == 0.0  # the 3x3 neighbourhood is read with the DEM, not from the block


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("slope = 1\ncost = 0.5", "cannot be assigned"),
        ("cost = 0.5\ncost += roughness\nroughness += 1", "cannot be assigned"),
        ("cost = 1 / slope", "may be zero"),
        ("cost = near(slope, 5)", "must be a mask"),
        ('cost = M["slope"]', "unknown entity"),
    ],
)
def test_terrain_misuse_is_refused(text: str, fragment: str) -> None:
    with pytest.raises(CostProgramError, match=fragment):
        check_program(text, ["road"])


def test_evaluation_reads_the_given_fields_and_keeps_the_costmap_in_range() -> None:
    program = check_program('cost = where(M["road"], 0.1, 0.5)\ncost = max(cost, normalize(slope, 15, 30))\n', ["road"])
    road = np.array([[True, True, False, False]])
    slope = np.array([[0.0, 25.0, 0.0, 60.0]])
    out = evaluate_program(program, {"road": road}, terrain={"slope": slope})
    np.testing.assert_allclose(out.cost, [[0.1, 10 / 15, 0.5, 1.0]])
