"""``redact`` removes a secret whole even when another secret is part of it.

Two secrets where one is a prefix, a suffix or an inner part of the other: replacing the shorter
one first would cut the longer one apart and leave the rest of it on show ("***-extra-456").
``redact`` replaces the longest forms first, whatever order the secrets come in.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.llm import MASK, redact

LONG = "tok-1234-extra-5678"
#: Parts of LONG that are secrets of their own: its prefix, its suffix, its middle.
PARTS = ("tok-1234", "extra-5678", "1234-extra")


def fragments(secret: str, size: int = 4) -> set[str]:
    """Every piece of ``secret`` ``size`` characters long: none may survive redaction."""
    return {secret[i : i + size] for i in range(len(secret) - size + 1)}


@pytest.mark.parametrize("part", PARTS)
@pytest.mark.parametrize("shorter_first", [True, False])
def test_a_secret_containing_another_is_removed_whole(part: str, shorter_first: bool) -> None:
    secrets = [part, LONG] if shorter_first else [LONG, part]
    text = f"reply: key={LONG}; again {part}, done"
    out = redact(text, secrets)
    assert out == f"reply: key={MASK}; again {MASK}, done"
    assert not [f for f in fragments(LONG) | fragments(part) if f in out]


def test_forms_of_one_secret_nested_in_another_are_removed_whole() -> None:
    # the percent-encoded spelling of the longer secret contains the shorter secret as is
    short, long_ = "k-99", "k-99/x&y"
    out = redact("url ?key=k-99%2Fx%26y and k-99/x&y", [short, long_])
    assert out == f"url ?key={MASK} and {MASK}"
