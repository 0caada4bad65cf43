"""Every cost level has one home, ``costlang/scale.py``: the interpreter's tiers, the priors and
the cues' levels are read from it, never written as numbers elsewhere (issue 34)."""

from __future__ import annotations

import ast
from pathlib import Path

from overseec_core.costlang import scale, synth
from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.priors import BUILT_IN

CORE = Path(__file__).resolve().parents[2] / "overseec_core"
#: Module-level names that hold a cost level.
TIER_NAMES = {"PREFER", "FINE", "TOLERABLE", "AVOID", "STRONG_AVOID", "LETHAL", "STEP", "ORDER_MAX", "NEUTRAL"}


def _level_literals(path: Path) -> list[str]:
    hits = []
    for node in ast.parse(path.read_text()).body:
        targets = node.targets if isinstance(node, ast.Assign) else []
        for t in targets:
            names = [e.id for e in (t.elts if isinstance(t, ast.Tuple) else [t]) if isinstance(e, ast.Name)]
            values = node.value.elts if isinstance(node.value, ast.Tuple) else [node.value]
            numeric = any(isinstance(v, ast.Constant) and isinstance(v.value, float) for v in values)
            if numeric and any(n.endswith("_LEVEL") or n in TIER_NAMES for n in names):
                hits.append(f"{path.relative_to(CORE)}:{node.lineno} {', '.join(names)}")
    return hits


def test_no_cost_level_is_written_outside_the_scale() -> None:
    files = [p for d in ("interpret", "costlang", "synthesize") for p in sorted((CORE / d).rglob("*.py"))]
    hits = [h for p in files if p.name != "scale.py" for h in _level_literals(p)]
    assert hits == []


def test_the_scan_finds_a_level_written_as_a_number(tmp_path: Path) -> None:
    (tmp_path / "m.py").write_text("AVOID = 0.7\nNEAR_LEVEL, X = 0.25, 1\nOTHER = 0.3\n")
    global CORE
    saved, CORE = CORE, tmp_path
    try:
        assert _level_literals(tmp_path / "m.py") == ["m.py:1 AVOID", "m.py:2 NEAR_LEVEL, X"]
    finally:
        CORE = saved


def test_the_tiers_priors_and_cue_levels_are_the_scales() -> None:
    assert (lx.PREFER, lx.AVOID, lx.LETHAL, lx.ORDER_MAX) == (
        scale.PREFER_LEVEL,
        scale.AVOID_LEVEL,
        scale.LETHAL_LEVEL,
        scale.ORDER_MAX_LEVEL,
    )
    assert {p.entity: p.level for p in BUILT_IN.priors} == scale.PRIOR_LEVELS
    assert (synth.NEAR_LEVEL, synth.FAR_EDGE_LEVEL) == (scale.NEAR_LEVEL, scale.FAR_EDGE_LEVEL)
