"""Versioned prompt templates: present, complete, and filled without re-expanding user text."""

from __future__ import annotations

import pytest

from overseec_core.errors import InterpretError
from overseec_core.interpret.templates import TEMPLATE_VERSIONS, load_template, parse_template, template_ids


def test_templates_in_use_load_with_all_sections():
    assert template_ids() == ("entities.v2", "program.v3")
    for name in TEMPLATE_VERSIONS:
        tpl = load_template(name)
        assert set(tpl.sections) == {"system", "user", "repair"}
    ent = load_template("entities")
    system = ent.render("system", defaults="road", schema="{}")
    assert "linear" in system and "unparsed" in system and "$" not in system
    assert "0.5 is NEUTRAL" in system  # the cost scale binds the LLM too
    assert "exactly 0.5 (neutral)" in load_template("program").render("system", reference="", names="")
    assert "<!--" not in system


def test_user_text_is_not_expanded():
    text = load_template("entities").render("user", prompt="avoid $schema and ${defaults} $$")
    assert "avoid $schema and ${defaults} $$" in text


def test_missing_placeholder_and_section_are_errors():
    tpl = load_template("program")
    with pytest.raises(InterpretError, match="bad placeholder"):
        tpl.render("user", prompt="x")
    with pytest.raises(InterpretError, match="no 'assistant' section"):
        tpl.render("assistant")
    with pytest.raises(InterpretError, match="no template named"):
        load_template("nope")
    with pytest.raises(InterpretError, match="missing"):
        load_template("entities", "v999")
    with pytest.raises(InterpretError, match="no sections"):
        parse_template("x.v1", "just text")
