"""The optional extras (``pip install "overseec[EXTRA]"``): which modules each brings, and the
one-line refusal of a stage whose extra is missing, before anything is read or written.
"""

from __future__ import annotations

import importlib.util

from overseec_core.errors import InputError, ModelError, OverseecError

#: The optional extras (``pip install "overseec[EXTRA]"``) and the modules each one brings.
EXTRAS: dict[str, tuple[str, ...]] = {
    "models": ("torch", "transformers", "safetensors", "huggingface_hub"),
    "dask": ("dask", "distributed"),
}


def extra_for(module: str | None) -> str | None:
    """The extra that installs ``module`` (or a submodule of it), or None."""
    root = (module or "").split(".")[0]
    return next((extra for extra, modules in EXTRAS.items() if root in modules), None)


def missing_extra(extra: str, what: str, module: str, hint: str = "") -> OverseecError:
    """The one-line error for a stage whose extra is not installed."""
    kind = ModelError if extra == "models" else InputError
    return kind(f'{what} needs {module}, which is not installed: pip install "overseec[{extra}]"{hint}')


def require_extra(extra: str, what: str, hint: str = "") -> None:
    """Refuse, before anything is read or written, a stage whose optional extra is missing:
    one line naming the pip extra, not an ImportError half-way."""
    for module in EXTRAS[extra]:
        try:
            found = importlib.util.find_spec(module) is not None
        except (ImportError, ValueError):  # a broken install, or an import hook refusing it
            found = False
        if not found:
            raise missing_extra(extra, what, module, hint)
