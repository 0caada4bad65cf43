"""Every clause accounted for (issue 31): `costmap` warns once per clause it did not understand
and records the warnings in the manifest; `--strict` makes such a clause an error (exit 2) and
writes nothing."""

from __future__ import annotations

import json
from pathlib import Path

from overseec_core.cli import main

from ..invariants_data import SAMPLE

LAYERS = ["--labels", str(SAMPLE / "sample_labels.tif"), "--classes", str(SAMPLE / "classes.json")]
PROMPT = "prefer the trails. call base when you arrive. report back by noon"


def test_costmap_warns_once_per_unread_clause(tmp_path: Path, capsys) -> None:
    out = tmp_path / "cm" / "costmap.tif"
    assert main(["costmap", *LAYERS, "--prompt", PROMPT, "--out", str(out)]) == 0
    printed = capsys.readouterr()
    lines = [ln for ln in (printed.out + printed.err).splitlines() if "not understood, so it has no effect" in ln]
    assert len(lines) == 2, lines
    assert any("call base when you arrive" in ln for ln in lines)
    manifest = json.loads((out.parent / "manifest.json").read_text())
    warned = [w for w in manifest["cost_program"]["warnings"] if w.startswith("not understood")]
    assert len(warned) == 2


def test_strict_refuses_an_unread_clause_and_writes_nothing(tmp_path: Path, capsys) -> None:
    out = tmp_path / "cm" / "costmap.tif"
    assert main(["costmap", "--strict", *LAYERS, "--prompt", PROMPT, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--strict" in err and "call base when you arrive" in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_strict_passes_a_wholly_read_prompt(tmp_path: Path) -> None:
    out = tmp_path / "cm" / "costmap.tif"
    argv = ["costmap", "--strict", *LAYERS, "--prompt", "prefer the trails, avoid the water", "--out", str(out)]
    assert main(argv) == 0
    assert out.exists()


def test_strict_refuses_a_rule_about_something_no_layer_shows(tmp_path: Path, capsys) -> None:
    """ "keep the rover off the helipad" over layers without a helipad: read, but it has no
    effect. Without --strict one warning line quotes the prompt's words; with it, exit 2."""
    out = tmp_path / "cm" / "costmap.tif"
    prompt = "prefer the trails. keep the rover off the helipad"
    assert main(["costmap", *LAYERS, "--prompt", prompt, "--out", str(out)]) == 0
    printed = capsys.readouterr()
    lines = [ln for ln in (printed.out + printed.err).splitlines() if "matches no layer" in ln]
    assert len(lines) == 1 and "keep the rover off the helipad" in lines[0], lines
    out2 = tmp_path / "strict" / "costmap.tif"
    assert main(["costmap", "--strict", *LAYERS, "--prompt", prompt, "--out", str(out2)]) == 2
    err = capsys.readouterr().err
    assert "--strict" in err and "helipad" in err and len(err.strip().splitlines()) == 1
    assert not out2.exists()
