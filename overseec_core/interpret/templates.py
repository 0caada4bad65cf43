"""Versioned LLM prompt templates, loaded from package data (``templates/<name>.<version>.md``).

The wording of what we ask an LLM is data, not code: it lives in Markdown files beside this
module, one file per call and version, split into sections by ``<!-- section: NAME -->`` lines
(``system``, ``user``, ``repair``). Placeholders are ``$name`` (:class:`string.Template`), filled
in one pass, so a ``$`` inside the user's prompt is never expanded. A changed wording gets a new
version file; the version used is recorded in the Interpretation's notes and so in the manifest.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from importlib import resources
from string import Template

from overseec_core.errors import InterpretError

#: The template version each LLM call uses.
TEMPLATE_VERSIONS: dict[str, str] = {"entities": "v2", "program": "v3"}

_SECTION = re.compile(r"^<!--\s*section:\s*([a-z_]+)\s*-->\s*$", re.MULTILINE)
_COMMENT = re.compile(r"^<!--.*?-->\s*\n", re.MULTILINE)


@dataclass(frozen=True)
class PromptTemplate:
    """One versioned template: ``id`` (e.g. ``entities.v1``) and its sections."""

    id: str
    sections: dict[str, str]

    def render(self, section: str, **values: str) -> str:
        """Fill one section's placeholders (all must be given)."""
        try:
            text = self.sections[section]
        except KeyError:
            raise InterpretError(f"template {self.id} has no '{section}' section") from None
        try:
            return Template(text).substitute(values).strip()
        except (KeyError, ValueError) as exc:
            raise InterpretError(f"template {self.id}, section {section}: bad placeholder {exc}") from None


def parse_template(template_id: str, text: str) -> PromptTemplate:
    """Split template text into its sections (comment lines before the first are dropped)."""
    parts = _SECTION.split(text)
    sections = {}
    for name, body in zip(parts[1::2], parts[2::2]):
        sections[name] = _COMMENT.sub("", body)
    if not sections:
        raise InterpretError(f"template {template_id} has no sections")
    return PromptTemplate(template_id, sections)


@cache
def load_template(name: str, version: str | None = None) -> PromptTemplate:
    """The template ``name`` at ``version`` (default: TEMPLATE_VERSIONS[name])."""
    version = version or TEMPLATE_VERSIONS.get(name)
    if version is None:
        raise InterpretError(f"no template named {name!r}")
    template_id = f"{name}.{version}"
    ref = resources.files(__package__).joinpath("templates").joinpath(f"{template_id}.md")
    try:
        text = ref.read_text(encoding="utf-8")
    except (FileNotFoundError, OSError):
        raise InterpretError(f"prompt template {template_id}.md is missing from the installation") from None
    return parse_template(template_id, text)


def template_ids() -> tuple[str, ...]:
    """Ids of the templates in use, e.g. ('entities.v1', 'program.v1')."""
    return tuple(f"{n}.{v}" for n, v in TEMPLATE_VERSIONS.items())
