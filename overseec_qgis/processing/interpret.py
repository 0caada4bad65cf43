"""``overseec:interpret``: a mission prompt to entities, preferences and a cost program (``overseec interpret``)."""

from __future__ import annotations

from pathlib import Path

from qgis.core import (
    QgsProcessingException,
    QgsProcessingOutputString,
    QgsProcessingParameterFileDestination,
    QgsProcessingParameterString,
)

from .base import OverseecAlgorithm, temp_file
from .parameters import (
    PRIORS_FLAGS,
    add_llm_parameters,
    add_priors_parameters,
    llm_args,
    llm_config,
    llm_env,
    priors_args,
)


class InterpretAlgorithm(OverseecAlgorithm):
    """Interpret prompt: the interpretation as JSON, its program and entity names as outputs."""

    ID = "interpret"
    TAGS = ("interpret", "prompt", "mission", "llm", "language", "cost program")
    DISPLAY = "Interpret prompt"
    HELP = (
        "Turns a mission prompt into entities (name, linear/areal, text prompts), preferences and "
        "a cost program, with the offline interpreter or an OpenAI-compatible LLM. Writes the "
        "interpretation as JSON (input of Segment entities). Same as `overseec interpret`.\n"
        "Needs: PROMPT."
    )
    COMMAND = "interpret"
    #: The prompt reaches the CLI as a file (any text, however long, whatever its first character).
    FLAGS = {"PROMPT": "--prompt-file", **PRIORS_FLAGS, "OUTPUT": "--out"}

    def initAlgorithm(self, config=None) -> None:
        """PROMPT, priors, the LLM (advanced) and the JSON destination."""
        self.param(
            QgsProcessingParameterString("PROMPT", "Mission prompt", multiLine=True),
            "what to prefer and avoid, e.g. 'prefer the roads, avoid the water'.",
        )
        add_priors_parameters(self)
        add_llm_parameters(self)
        self.param(
            QgsProcessingParameterFileDestination("OUTPUT", "Interpretation (JSON)", "JSON files (*.json)"),
            "the document `overseec interpret --json` prints.",
        )
        self.addOutput(QgsProcessingOutputString("PROGRAM", "Cost program"))
        self.addOutput(QgsProcessingOutputString("ENTITIES", "Entities (comma-separated)"))

    def processAlgorithm(self, parameters, context, feedback):
        """Run ``overseec interpret --json``; its notes go to the log."""
        prompt = self.parameterAsString(parameters, "PROMPT", context).strip()
        if not prompt:
            raise QgsProcessingException("PROMPT: write a mission prompt")
        out = Path(self.parameterAsFileOutput(parameters, "OUTPUT", context))
        out.parent.mkdir(parents=True, exist_ok=True)
        prompt_file = temp_file("prompt.txt")
        prompt_file.write_text(prompt, encoding="utf-8")
        llm = llm_config(self, parameters, context)
        args = [*self.arg("PROMPT", prompt_file), *self.arg("OUTPUT", out), "--json", *llm_args(llm)]
        args += priors_args(self, parameters, context)
        doc = self.cli(args, feedback, env=llm_env(llm))
        for note in list(doc.get("unparsed") or []) + list(doc.get("notes") or []):
            feedback.pushInfo(str(note))
        names = ",".join(e["name"] for e in doc.get("entities", []))
        return {"OUTPUT": str(out), "PROGRAM": doc.get("program", ""), "ENTITIES": names}
