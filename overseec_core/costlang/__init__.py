"""The cost language: a small, safe, Python-like language that turns entity masks into a costmap.

Programs are data: :func:`check_program` parses them with :mod:`ast` into a closed, typed,
statically bounded tree; :func:`evaluate_program` walks that tree over numpy arrays. Nothing in a program
can run Python code. The full specification, with examples, is ``LANGUAGE.md`` beside this file;
:func:`operator_reference` is its compact form for LLM prompts.

Public API (other stages code against these names):

- ``check_program(text, entity_names) -> Program``  (raises CostProgramError(message, line, col))
- ``program_from_interpretation(entities, preferences, hierarchy, cues) -> str``
- ``operator_reference(terrain=False) -> str``
- ``evaluate_program(program, masks, probs, sampling, terrain=...) -> Evaluation``

Terrain: a program may read ``slope`` (degrees) and ``roughness`` (metres) by name
(:data:`~overseec_core.costlang.ops.TERRAIN`); :attr:`Program.terrain` lists those it reads and the
caller passes them to the evaluator (Synthesize computes them from ``--dem``).
"""

from __future__ import annotations

from pathlib import Path

from overseec_core.costlang.evaluator import Evaluation, evaluate_program
from overseec_core.costlang.lang import (
    COST,
    KEEP_OUT,
    LETHAL,
    MAX_DEPTH,
    MAX_NODES,
    MAX_PROGRAM_CHARS,
    MAX_REACH_M,
    check_program,
    normalise_entity_name,
)
from overseec_core.costlang.ops import (
    DEFAULT_DISTANCE_CAP_M,
    MAX_EXPONENT,
    MAX_MAGNITUDE,
    MAX_RADIUS_M,
    OPERATORS,
    TERRAIN,
    reference_table,
    terrain_table,
)
from overseec_core.costlang.synth import DEFAULT_LINEAR_WIDTH_M, program_from_interpretation
from overseec_core.costlang.tree import Program

LANGUAGE_FILE = Path(__file__).with_name("LANGUAGE.md")

_REFERENCE_HEAD = f"""\
## The overseec cost language

A program is a sequence of assignments in Python syntax; nothing else (no imports, loops,
functions, attributes, lists, keyword arguments, or Python builtins).

- Entity data: `M["name"]` is the entity's mask (true/false per pixel); `P["name"]` is its
  probability gated by the mask (0 outside it, in [0, 1]). Names must be among the entities given.
- Expressions: numbers, `True`/`False`, names assigned earlier, `+ - * / **` (the exponent a
  constant, at most {MAX_EXPONENT:g}), comparisons `< <= > >= == !=` (give masks), mask logic
  `&`, `|`, `~`, `and`, `or`, `not`, `a if mask else b`, and the operators below.
  A mask used in arithmetic counts as 0/1.
- Assign `cost` (required): lower = preferred. The costmap is `cost` clipped to [0, 1].
  Optionally assign `lethal` (a mask): those pixels cost 1.0 and are impassable, and
  `keep_out` (a mask): zones a rule forbids (a distance rule, a never-cross rule, an obstacle at
  level 1.0), impassable unless no route exists.
- The cost scale is fixed: pixels that belong to no entity (and entities the mission does not
  mention, unless they carry a prior: trees, railways, buildings, water) cost 0.5, neutral;
  preferred entities cost less, avoided ones more.
- Distances are metres; each radius at most {MAX_RADIUS_M:g} m and a constant.
  `distance()` saturates at its cap (default {DEFAULT_DISTANCE_CAP_M:g} m).
- Division only by values that cannot be zero (write `x / (d + 1)`, not `x / d`).
- Comments start with `#`.

Example ("prefer roads, grass is fine, avoid the baseball field, never enter water,
keep at least 20 m from buildings"):

```python
acc = sum(-0.5 * P["road"], 0.5 * P["baseball field"])   # (level - 0.5) * P; grass is neutral
cost = clip(0.5 + acc, 0.0, 1.0)
lethal = M["water"]
cost = where(lethal, 1.0, cost)
keep_out = near(M["building"], 20)
```

### Operators

"""


_TERRAIN_HEAD = """
### Terrain (this run has a DEM)

The run has a DEM, resampled onto the image's grid: these names are per-pixel fields, read like
entity layers (not assigned). Use them when the mission speaks of slopes, steep or rough ground.

"""


def operator_reference(terrain: bool = False) -> str:
    """A compact Markdown description of the language and its operator table (for LLM prompts).

    ``terrain``: the run has a DEM, so the reference also lists the terrain fields (``slope`` in
    degrees, ``roughness`` in metres, from :data:`~overseec_core.costlang.ops.TERRAIN`). Without
    one they are left out: a program that reads them would fail when the costmap is built.
    """
    text = _REFERENCE_HEAD + reference_table() + "\n"
    if terrain:
        text += _TERRAIN_HEAD + terrain_table() + "\n"
    return text


__all__ = [
    "COST",
    "KEEP_OUT",
    "DEFAULT_DISTANCE_CAP_M",
    "DEFAULT_LINEAR_WIDTH_M",
    "Evaluation",
    "LANGUAGE_FILE",
    "LETHAL",
    "MAX_DEPTH",
    "MAX_EXPONENT",
    "MAX_MAGNITUDE",
    "MAX_NODES",
    "MAX_PROGRAM_CHARS",
    "MAX_RADIUS_M",
    "MAX_REACH_M",
    "OPERATORS",
    "Program",
    "TERRAIN",
    "check_program",
    "evaluate_program",
    "normalise_entity_name",
    "operator_reference",
    "program_from_interpretation",
]
