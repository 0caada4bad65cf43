"""Every shell example in README.md runs, verbatim, on the bundled sample scene.

The README's ```sh and ```bash blocks are split into command lines (a line ending in a backslash
continues on the next). Each block runs in its own temporary folder as one bash script with
``set -e -o pipefail`` (so ``export`` carries to the next line, and the first failing command
fails the block), the venv's ``bin`` first on PATH (the project's own ``overseec`` console
script), ``HOME`` inside the folder (a throw-away QGIS profile and caches) and no ``OVERSEEC_*`` /
``QGIS_*`` variables from the environment (no LLM: the offline interpreter, as documented).

Placeholders are files, not text substitutions: the folder holds what each placeholder names
(:data:`PLACEHOLDERS`), so the commands run exactly as printed. A command that cannot run here is
listed in :data:`SKIP` with the reason (each key is the start of exactly one README command, and
the skipped ones are reported as skipped tests, so they are counted); any other command runs. So a
new example runs in the suite the moment it is written, or fails it until it works or is listed.
:data:`XFAIL` marks a block whose command waits for a fix elsewhere (strict: the block turns the
suite red the moment it passes, so the entry is removed).

The README's synopsis of the command line is a ```text block (metavariables: IMAGE, X Y, a|b);
:func:`test_every_command_of_the_synopsis_has_a_runnable_example` checks that each subcommand it
lists is run by some example.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
README = REPO / "README.md"
SAMPLE = REPO / "resources" / "sample"
#: The venv's bin folder: its python runs the suite, its `overseec` runs the examples.
BIN = Path(sys.executable).parent

#: Placeholder in the README -> what the example's folder holds under that name.
PLACEHOLDERS: dict[str, str] = {
    "S/": "a copy of resources/sample/ (the bundled sample; `overseec sample --out S` writes the same)",
    "resources/sample/": "the same copy, where a checkout has it",
    "image.tif": "S/sample.tif (the sample's RGB GeoTIFF)",
    "gt.tif": "S/sample_labels.tif (its class raster)",
    "classes.json": "S/classes.json (the raster's class names)",
    "edits.gpkg": "one override polygon (field cost = 0.95, EPSG:32633) over the sample's middle",
    "runs/demo/": "what `overseec demo --out runs/demo` writes (made once per test session)",
    ".venv/": "a link to the checkout's venv (the README's `$PWD/.venv`)",
    "scripts/": "a link to the checkout's scripts/ (build_plugin.py)",
    "$HOME": "home/, an empty folder (QGIS profile, caches, the unpacked plugin)",
}

#: Start of a README command -> why it cannot run in the suite.
SKIP: dict[str, str] = {
    "make demo": "make: installs Debian packages (apt, sudo) before it runs; `overseec demo` itself runs below",
    "make test": "make: the lint gate and this very test suite",
    "make plugin": "make; the same scripts/build_plugin.py runs in the Processing example",
    "python -m venv overseec-env": "the pip recipe's first step; the rest of it needs a package index",
    "overseec-env/bin/pip wheel": "pip from a package index (build isolation fetches setuptools and numpy)",
    "overseec-env/bin/pip install dist/overseec-*.whl": "pip from a package index (the core's dependencies)",
    "overseec-env/bin/pip install torch": "network: PyTorch's CPU index (200 MB of wheels)",
    'overseec-env/bin/pip install "overseec[models]"': "pip from a package index (transformers ...)",
    "overseec-env/bin/overseec demo": "needs the environment the skipped pip lines build; `overseec demo` runs below",
    "overseec segment image.tif": "needs torch and the CLIPSeg + SAM weights (a download)",
    "qgis_process.bin run overseec:extractimagery": "network: fetches tiles from a tile server",
    "qgis_process.bin run overseec:segment": "needs torch and the CLIPSeg + SAM weights (a download)",
}

#: Start of a README command -> the fix it waits for (its block is xfail(strict=True)).
XFAIL: dict[str, str] = {}


@dataclass(frozen=True)
class Block:
    """One ```sh / ```bash block: where it is and its command lines (continuations joined)."""

    name: str
    line: int
    commands: tuple[str, ...]

    def runnable(self) -> tuple[str, ...]:
        return tuple(c for c in self.commands if skip_key(c) is None)


def skip_key(command: str, table: dict[str, str] | None = None) -> str | None:
    """The key of ``table`` (default :data:`SKIP`) that ``command`` starts with, if any."""
    return next((k for k in (SKIP if table is None else table) if command.startswith(k)), None)


def _slug(heading: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", heading.lower()).strip("-")


def _commands(body: str) -> tuple[str, ...]:
    out: list[str] = []
    pending = ""
    for raw in body.splitlines():
        line = raw.strip()
        if line.endswith("\\"):
            pending += line[:-1].strip() + " "
            continue
        line = (pending + line).strip()
        pending = ""
        if line and not line.startswith("#"):
            out.append(line)
    assert not pending, f"a continuation runs off the end of a block: {pending!r}"
    return tuple(out)


def readme_blocks(text: str | None = None) -> list[Block]:
    """The README's shell blocks, named after the heading above them."""
    text = README.read_text(encoding="utf-8") if text is None else text
    blocks: list[Block] = []
    heading, seen = "top", {}
    fence = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
    pos = 0
    for m in fence.finditer(text):
        for h in re.finditer(r"^#{1,6} (.+)$", text[pos : m.start()], re.M):
            heading = h.group(1)
        pos = m.end()
        if m.group(1) not in ("sh", "bash"):
            continue
        base = _slug(heading)
        seen[base] = seen.get(base, 0) + 1
        name = base if seen[base] == 1 else f"{base}-{seen[base]}"
        blocks.append(Block(name, text[: m.start()].count("\n") + 1, _commands(m.group(2))))
    return blocks


BLOCKS = readme_blocks()
ALL_COMMANDS = [c for b in BLOCKS for c in b.commands]

#: Blocks marked slow (`make test-fast` leaves them out): each took 10 s or more on the project's
#: 2-core machine (30-50 s, 16 s with the demo run it reads, 10 s); the others take about 5 s.
SLOW_BLOCKS = {"the-command-line", "exporting-for-robots-and-routing-tools", "processing-and-qgis-process"}


def _params() -> list:
    params = []
    for block in BLOCKS:
        if not block.runnable():
            continue
        marks = [pytest.mark.slow] if block.name in SLOW_BLOCKS else []
        waiting = [XFAIL[k] for c in block.runnable() if (k := skip_key(c, XFAIL)) is not None]
        if waiting:
            marks.append(pytest.mark.xfail(strict=True, reason="; ".join(waiting)))
        if any(c.startswith("qgis_process.bin") for c in block.runnable()):
            marks.append(pytest.mark.qgis)
        params.append(pytest.param(block, marks=marks, id=block.name))
    return params


# ------------------------------------------------------------------------------------------------
# The folder an example runs in


def _environment(folder: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OVERSEEC_", "QGIS_"))}
    env.update(
        PATH=os.pathsep.join([str(BIN), env.get("PATH", "")]),
        HOME=str(folder / "home"),
        QT_QPA_PLATFORM="offscreen",
        HF_HUB_OFFLINE="1",
    )
    return env


def _write_edits(path: Path) -> None:
    import fiona
    from fiona.crs import CRS

    schema = {"geometry": "Polygon", "properties": {"cost": "float"}}
    ring = [(534150.0, 5212750.0), (534250.0, 5212750.0), (534250.0, 5212850.0), (534150.0, 5212850.0)]
    with fiona.open(path, "w", driver="GPKG", crs=CRS.from_epsg(32633), schema=schema) as dst:
        dst.write({"geometry": {"type": "Polygon", "coordinates": [[*ring, ring[0]]]}, "properties": {"cost": 0.95}})


def lay_out(folder: Path, demo: Path | None) -> None:
    """Put :data:`PLACEHOLDERS` into ``folder``."""
    sample = folder / "S"
    shutil.copytree(SAMPLE, sample)  # a copy: GDAL and QGIS write .aux.xml statistics beside inputs
    (folder / "resources").mkdir()
    shutil.copytree(SAMPLE, folder / "resources" / "sample")
    for name, source in (("image.tif", "sample.tif"), ("gt.tif", "sample_labels.tif"), ("classes.json", None)):
        shutil.copy(sample / (source or name), folder / name)
    _write_edits(folder / "edits.gpkg")
    (folder / "home").mkdir()
    (folder / ".venv").symlink_to(BIN.parent, target_is_directory=True)
    (folder / "scripts").symlink_to(REPO / "scripts", target_is_directory=True)
    if demo is not None:
        shutil.copytree(demo, folder / "runs" / "demo")


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """`overseec demo --out runs/demo`, once: what the export examples read."""
    folder = tmp_path_factory.mktemp("readme_demo")
    done = subprocess.run(
        [str(BIN / "overseec"), "demo", "--out", "runs/demo"],
        cwd=folder,
        env=_environment(folder),
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return folder / "runs" / "demo"


def run_block(block: Block, folder: Path) -> tuple[int, str, str]:
    """Run the block's runnable commands in order; (index of the failing command or -1, out, err)."""
    commands = block.runnable()
    lines = ["set -e -o pipefail"]
    for i, command in enumerate(commands):
        lines += [f"echo {i} > .readme_step", command]
    lines.append("echo done > .readme_step")
    done = subprocess.run(
        ["bash", "-c", "\n".join(lines)],
        cwd=folder,
        env=_environment(folder),
        capture_output=True,
        text=True,
        stdin=subprocess.DEVNULL,
        timeout=600,
    )
    step = (folder / ".readme_step").read_text().strip() if (folder / ".readme_step").exists() else "0"
    failed = -1 if done.returncode == 0 and step == "done" else int(step) if step.isdigit() else 0
    return failed, done.stdout, done.stderr


# ------------------------------------------------------------------------------------------------
# The tests


@pytest.mark.parametrize("block", _params())
def test_readme_block_runs(block: Block, tmp_path: Path, request: pytest.FixtureRequest) -> None:
    if any(c.startswith("qgis_process.bin") for c in block.runnable()) and shutil.which("qgis_process.bin") is None:
        pytest.skip("needs qgis_process.bin (Debian's qgis package)")
    needs_demo = any("runs/demo/" in c for c in block.runnable())
    lay_out(tmp_path, request.getfixturevalue("demo_run") if needs_demo else None)
    failed, out, err = run_block(block, tmp_path)
    if failed >= 0:
        command = block.runnable()[failed]
        pytest.fail(
            f"README.md line {block.line} ({block.name}): command {failed + 1} of {len(block.runnable())} failed:\n"
            f"  {command}\n--- stdout (end)\n{out[-2000:]}\n--- stderr (end)\n{err[-3000:]}"
        )


@pytest.mark.parametrize("key", list(SKIP), ids=list(SKIP))
def test_readme_skipped_example(key: str) -> None:
    """One skipped test per command that cannot run here, with the reason (so they are counted)."""
    pytest.skip(f"README example not run: {SKIP[key]}")


def test_skip_table_names_readme_commands() -> None:
    """Each SKIP / XFAIL key starts exactly one README command: no stale or ambiguous entry."""
    for table in (SKIP, XFAIL):
        for key in table:
            matches = [c for c in ALL_COMMANDS if c.startswith(key)]
            assert len(matches) == 1, f"{key!r} starts {len(matches)} README commands: {matches}"


def test_readme_has_runnable_examples() -> None:
    """The extraction finds the README's blocks (a broken fence or regex must not pass silently)."""
    runnable = [c for b in BLOCKS for c in b.runnable()]
    assert len(BLOCKS) >= 8 and len(runnable) >= 30, (len(BLOCKS), len(runnable))
    assert len(ALL_COMMANDS) == len(runnable) + len(SKIP)


def test_every_command_of_the_synopsis_has_a_runnable_example() -> None:
    """Each `overseec SUBCOMMAND` of the README's synopsis is run by at least one example."""
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## The command line") :]
    synopsis = re.search(r"^```text\n(.*?)^```", section, re.S | re.M)
    assert synopsis, "the command-line synopsis (a ```text block) is missing"
    listed = {line.split()[1] for line in synopsis.group(1).splitlines() if line.startswith("overseec ")}
    assert len(listed) >= 14, listed
    ran = {m.group(1) for b in BLOCKS for c in b.runnable() for m in re.finditer(r"\boverseec ([a-z][\w-]*)", c)}
    missing = listed - ran - {"segment"}  # segment needs the models: its example is in SKIP
    assert not missing, f"synopsis commands without a runnable README example: {sorted(missing)}"
