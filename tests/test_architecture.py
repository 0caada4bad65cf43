"""Architecture rules that must hold for the whole package."""

from __future__ import annotations

import pkgutil
import subprocess
import sys
import textwrap
from pathlib import Path

import overseec_core

REPO = Path(__file__).resolve().parent.parent

#: Modules allowed to import torch/transformers at import time (the model stages).
MODEL_MODULES = ("segment", "refine", "models", "distributed")


def _core_modules() -> list[str]:
    return sorted(m.name for m in pkgutil.walk_packages(overseec_core.__path__, "overseec_core.")
                  if not m.name.rsplit(".", 1)[-1].startswith("_"))


def test_core_imports_with_qgis_and_qt_unimportable() -> None:
    """Every core module imports in a process where qgis and PyQt cannot be imported."""
    script = textwrap.dedent(f"""
        import importlib, sys
        class Block:
            def find_spec(self, name, path=None, target=None):
                if name.split('.')[0] in ('qgis', 'PyQt5', 'PyQt6', 'sip'):
                    raise ImportError('blocked: ' + name)
        sys.meta_path.insert(0, Block())
        for name in {_core_modules()!r}:
            importlib.import_module(name)
        assert not any(m.split('.')[0] in ('qgis', 'PyQt5') for m in sys.modules), 'qgis leaked'
        print('ok')
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"


def test_only_model_stages_import_torch() -> None:
    """The non-ML stages (what the QGIS process may load) never pull in torch."""
    light = [m for m in _core_modules() if not any(part in MODEL_MODULES for part in m.split("."))
             and not m.startswith("overseec_core.commands")]
    script = textwrap.dedent(f"""
        import importlib, sys
        for name in {light!r}:
            importlib.import_module(name)
        heavy = sorted(m for m in ('torch', 'transformers') if m in sys.modules)
        print(','.join(heavy) or 'none')
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "none"


def test_cli_help_lists_the_commands() -> None:
    done = subprocess.run([sys.executable, "-m", "overseec_core.cli", "--help"], capture_output=True,
                          text=True, cwd=REPO, timeout=300)
    assert done.returncode == 0 and "info" in done.stdout and "doctor" in done.stdout
    assert "torch" not in done.stderr
