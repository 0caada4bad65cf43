"""Ground-truth classes (classes.json) and the ranks users give them (``--ranks``)."""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from overseec_core.errors import EvaluateError
from overseec_core.io.read import read_classes_json


def norm_name(name: str) -> str:
    """A class name compared case- and spacing-insensitively: lower case, single spaces."""
    return " ".join(str(name).lower().split())


@dataclass(frozen=True)
class ClassTable:
    """Class ids and names of a ground-truth raster (from classes.json)."""

    names: Mapping[int, str]

    def aliases(self) -> dict[str, int]:
        """Lower-case names users may type for each class.

        Besides the full name, 'water (Hydro)' also answers to 'water' and 'hydro', as long as the
        short form names only one class.
        """
        out: dict[str, int] = {}
        seen: dict[str, set[int]] = {}
        for cid, name in self.names.items():
            full = norm_name(name)
            out[full] = cid
            m = re.fullmatch(r"(.*?)\s*\((.*)\)\s*", full)
            for alias in [m.group(1), m.group(2)] if m else []:
                if alias:
                    seen.setdefault(alias, set()).add(cid)
        for alias, ids in seen.items():
            if len(ids) == 1 and alias not in out:
                out[alias] = next(iter(ids))
        return out

    def lookup(self, key: str | int) -> int | None:
        """Class id for a name (case-insensitive, see :meth:`aliases`) or an id; None if unknown."""
        text = str(key).strip()
        if re.fullmatch(r"-?\d+", text):
            cid = int(text)
            return cid if cid in self.names else None
        return self.aliases().get(norm_name(text))

    def describe(self) -> str:
        return ", ".join(f"{cid}={name}" for cid, name in sorted(self.names.items()))


def load_classes(path: str | os.PathLike) -> ClassTable:
    """Read classes.json: an object mapping class id (as text) to class name (all kept)."""
    return ClassTable(names=read_classes_json(path, EvaluateError))


@dataclass(frozen=True)
class RankTable:
    """Rank per class id (1 = most preferred) and the rank of everything unranked."""

    ranks: Mapping[int, int]
    unranked_rank: int

    def penalties(self, values: np.ndarray, nodata: float | None = None) -> np.ndarray:
        """``rank - 1`` for each class value (int64); unknown values and nodata are unranked."""
        out = np.full(values.shape, self.unranked_rank - 1, dtype=np.int64)
        for cid, rank in self.ranks.items():
            if nodata is not None and cid == nodata:
                continue
            out[values == cid] = rank - 1
        return out

    def to_json(self, classes: ClassTable) -> dict[str, Any]:
        return {
            "ranks": {classes.names.get(c, str(c)): r for c, r in sorted(self.ranks.items(), key=lambda kv: kv[1])},
            "unranked_rank": self.unranked_rank,
        }


def parse_ranks(  # noqa: C901
    spec: str | Mapping[str, int],
    classes: ClassTable,
    unranked: int | str = "max",
) -> RankTable:
    """``'road=1,grass=2'`` (names or ids from classes.json) -> :class:`RankTable`.

    ``unranked`` is the rank of pixels whose class has no rank: ``"max"`` (the largest rank
    given, the default) or an integer >= 1.
    """
    items: list[tuple[str, str]]
    if isinstance(spec, Mapping):
        items = [(str(k), str(v)) for k, v in spec.items()]
    else:
        items = []
        for part in str(spec).split(","):
            if not part.strip():
                continue
            name, sep, value = part.rpartition("=")
            if not sep or not name.strip():
                raise EvaluateError(f"--ranks takes CLASS=RANK pairs like road=1,grass=2, not {part.strip()!r}")
            items.append((name.strip(), value.strip()))
    if not items:
        raise EvaluateError("--ranks is empty; give CLASS=RANK pairs like road=1,grass=2")
    ranks: dict[int, int] = {}
    for name, value in items:
        cid = classes.lookup(name)
        if cid is None:
            raise EvaluateError(f"--ranks: unknown class {name!r}; classes.json has {classes.describe()}")
        try:
            rank = int(value)
        except ValueError:
            raise EvaluateError(f"--ranks: rank of {name!r} must be an integer >= 1, not {value!r}") from None
        if rank < 1:
            raise EvaluateError(f"--ranks: rank of {name!r} must be >= 1 (1 = most preferred), not {rank}")
        if cid in ranks:
            raise EvaluateError(f"--ranks: class {classes.names[cid]!r} is ranked twice")
        ranks[cid] = rank
    if isinstance(unranked, str) and unranked.strip().lower() == "max":
        unranked_rank = max(ranks.values())
    else:
        try:
            unranked_rank = int(unranked)
        except (TypeError, ValueError):
            raise EvaluateError(f"--unranked-rank takes 'max' or an integer >= 1, not {unranked!r}") from None
        if unranked_rank < 1:
            raise EvaluateError(f"--unranked-rank must be >= 1, not {unranked_rank}")
    return RankTable(ranks=ranks, unranked_rank=unranked_rank)
