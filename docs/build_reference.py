"""Build the API reference of ``overseec_core`` from its docstrings with pdoc (``make docs``).

    python docs/build_reference.py [--out build/docs] [--modules NAME ...]

pdoc imports each module it documents, so torch and transformers are blocked first: the reference
never needs the model packages (``overseec_core`` imports them only where a model runs), and a
module that imported them at import time fails the build here instead of pulling in gigabytes.
Every public module is listed explicitly: a package's ``__all__`` names what it re-exports, and
pdoc would otherwise leave out the modules behind it (``overseec_core.plan.stage``:
``PlanOptions``). A module that cannot be imported is an error, not a missing page. Works
offline: pdoc's pages load nothing from the network (the footer links to pdoc's site).
"""

from __future__ import annotations

import argparse
import pkgutil
import shutil
import sys
import warnings
from pathlib import Path

#: Packages the reference must never import (None in sys.modules: ``import torch`` fails).
BLOCKED = ("torch", "torchvision", "transformers", "huggingface_hub", "safetensors")
ROOT = Path(__file__).resolve().parent.parent
#: pdoc's warnings that mean a module is missing from the reference.
IMPORT_FAILURES = ("Error importing", "Error loading", "Cannot find spec")


def public_modules(package: str = "overseec_core") -> list[str]:
    """``package`` and every submodule without a leading underscore in its dotted name."""
    root = __import__(package)
    names = [m.name for m in pkgutil.walk_packages(root.__path__, f"{package}.")]
    return [package] + sorted(n for n in names if not any(part.startswith("_") for part in n.split(".")))


def build(out: Path, modules: list[str] | None = None) -> tuple[int, list[str]]:
    """Render ``modules`` (default: every public one) into ``out`` (replaced); returns the module
    count and the warnings pdoc gave."""
    for name in BLOCKED:
        sys.modules[name] = None  # type: ignore[assignment]
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    import pdoc
    import pdoc.render

    import overseec_core

    names = modules or public_modules()
    pdoc.render.configure(docformat="restructuredtext", footer_text=f"overseec {overseec_core.__version__}")
    if out.exists():
        shutil.rmtree(out)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # Annotations such as torch.Tensor (under TYPE_CHECKING) stay strings: that is the point.
        warnings.filterwarnings(
            "ignore", message=r"(?s)(Error parsing type annotation|Failed to run TYPE_CHECKING code).*\btorch\b"
        )
        # Subpackages are listed on purpose beside their package, whose walk may list them too.
        warnings.filterwarnings("ignore", message=r"(?s).*adds a module named .* has already been added")
        pdoc.pdoc(*names, output_directory=out)
    return len(names), [str(w.message) for w in caught]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "docs", help="output folder (replaced)")
    parser.add_argument("--modules", nargs="+", help="document only these modules (default: every public one)")
    args = parser.parse_args(argv)
    count, notes = build(args.out, args.modules)
    for note in notes:
        print(f"pdoc: {note}", file=sys.stderr)
    failed = [n for n in notes if n.startswith(IMPORT_FAILURES)]
    leaked = [name for name in BLOCKED if sys.modules.get(name) is not None]
    if failed or leaked:
        what = f"{len(failed)} module(s) could not be imported" if failed else f"{', '.join(leaked)} was imported"
        print(f"build_reference: error: {what} (see above)", file=sys.stderr)
        return 1
    pages = sum(1 for _ in args.out.rglob("*.html"))
    print(f"API reference: {args.out / 'index.html'} ({count} modules, {pages} pages)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
