"""Architecture rules that must hold for the whole package."""

from __future__ import annotations

import ast
import pkgutil
import subprocess
import sys
import textwrap
from collections.abc import Iterator, Mapping
from pathlib import Path

import overseec_core

REPO = Path(__file__).resolve().parent.parent

#: Modules allowed to import torch/transformers at import time (the model stages: the Locate
#: package and its model loading).
MODEL_MODULES = ("locate", "models")


def _core_modules() -> list[str]:
    return sorted(
        m.name
        for m in pkgutil.walk_packages(overseec_core.__path__, "overseec_core.")
        if not m.name.rsplit(".", 1)[-1].startswith("_")
    )


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
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"


def test_only_model_stages_import_torch() -> None:
    """The non-ML stages (what the QGIS process may load) never pull in torch."""
    light = [
        m
        for m in _core_modules()
        if not any(part in MODEL_MODULES for part in m.split(".")) and not m.startswith("overseec_core.commands")
    ]
    script = textwrap.dedent(f"""
        import importlib, sys
        for name in {light!r}:
            importlib.import_module(name)
        heavy = sorted(m for m in ('torch', 'transformers') if m in sys.modules)
        print(','.join(heavy) or 'none')
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "none"


def test_cli_help_lists_the_commands() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "overseec_core.cli", "--help"], capture_output=True, text=True, cwd=REPO, timeout=300
    )
    assert done.returncode == 0 and "info" in done.stdout and "doctor" in done.stdout
    assert "torch" not in done.stderr


# --- import cycles -------------------------------------------------------------------------------
def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _import_nodes(tree: ast.AST, *, in_functions: bool) -> Iterator[ast.Import | ast.ImportFrom]:
    """The imports a module runs when it is imported (``in_functions=False``: module and class
    bodies, ``try``/``if`` included) or only when one of its functions runs (``True``). Imports
    under ``if TYPE_CHECKING:`` never run and are skipped."""

    def walk(node: ast.AST, inside: bool) -> Iterator[ast.Import | ast.ImportFrom]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                yield from walk(child, True)
            elif isinstance(child, ast.If) and _is_type_checking(child.test):
                continue
            elif isinstance(child, (ast.Import, ast.ImportFrom)):
                if inside == in_functions:
                    yield child
            else:
                yield from walk(child, inside)

    return walk(tree, False)


def import_graph(root: Path, *, in_functions: bool) -> dict[str, set[str]]:
    """Module -> the package modules it imports, from the source (nothing is imported).

    ``from a.b import c`` depends on ``a.b.c`` when that is a module, else on ``a.b``; importing
    ``a.b.c`` also runs ``a`` and ``a.b`` (their ``__init__``), so those are dependencies too,
    except the module's own enclosing packages, which are always initialised first."""
    files = {_module_name(p, root): p for p in sorted(root.rglob("*.py"))}
    graph: dict[str, set[str]] = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges: set[str] = set()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in _import_nodes(tree, in_functions=in_functions):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                base = node.module or ""
                if node.level:
                    parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join(parts + ([node.module] if node.module else []))
                targets = [base] + [f"{base}.{a.name}" for a in node.names]
            for target in targets:
                while target and target not in files:
                    target = target.rpartition(".")[0]
                parts = target.split(".") if target else []
                for i in range(1, len(parts) + 1):
                    dep = ".".join(parts[:i])
                    if dep != name and not name.startswith(dep + "."):
                        edges.add(dep)
        graph[name] = edges
    return graph


def _pop_component(stack: list[str], on_stack: set[str], root: str) -> list[str]:
    component = []
    while True:
        member = stack.pop()
        on_stack.discard(member)
        component.append(member)
        if member == root:
            return sorted(component)


def import_cycles(graph: Mapping[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (or with a self-import), each
    sorted: Tarjan's algorithm, iterative so a deep graph cannot hit the recursion limit."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(node: str) -> Iterator[str]:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        return iter(sorted(n for n in graph[node] if n in graph))

    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, visit(start))]
        while work:
            node, successors = work[-1]
            nxt = next((n for n in successors if n not in index or n in on_stack), None)
            if nxt is not None and nxt not in index:
                work.append((nxt, visit(nxt)))
            elif nxt is not None:
                low[node] = min(low[node], index[nxt])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = _pop_component(stack, on_stack, node)
                    if len(component) > 1 or node in graph[node]:
                        cycles.append(component)
    return sorted(cycles)


def _core_graphs() -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    root = Path(overseec_core.__file__).resolve().parent
    return import_graph(root, in_functions=False), import_graph(root, in_functions=True)


def test_no_import_cycles_at_import_time() -> None:
    """No cycle among overseec_core modules through the imports that run when a module is
    imported (module level, class bodies, ``try``/``if`` blocks; not ``if TYPE_CHECKING``).

    These are the cycles that break: depending on which module a caller imports first, one of
    them sees the other half-initialised (an ImportError or a missing name). They also mark two
    modules that cannot be understood or tested apart. A cycle is fixed by moving what both need
    into a module below them (as ``schema.py`` and ``costlang/ops.py`` were), never by hiding an
    import inside a function."""
    module_level, _ = _core_graphs()
    assert import_cycles(module_level) == []


def test_no_import_cycles_through_function_level_imports() -> None:
    """The same over module-level and function-level imports together.

    Function-level imports are counted separately rather than ignored: they run after every
    module is initialised, so they cannot fail the way a module-level cycle does, which is
    exactly why they used to hide cycles (``costlang.lang`` <-> ``costlang.evaluator`` through
    ``apply_scalar``; ``costlang.synth`` -> ``interpret.schema`` -> ``interpret`` -> costlang).
    They stay legitimate for deferring a heavy optional dependency (torch, fiona, ...), which
    adds no edge between our own modules, so the whole graph must be acyclic too."""
    module_level, deferred = _core_graphs()
    combined = {name: module_level[name] | deferred[name] for name in module_level}
    assert import_cycles(combined) == []


def test_cycle_finder_finds_cycles() -> None:
    """Self-check on synthetic graphs: the test above can fail."""
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert import_cycles({"a": {"a"}, "b": set()}) == [["a"]]
    two = {"a": {"b"}, "b": {"a", "c"}, "c": {"d"}, "d": {"c", "e"}, "e": set(), "x": {"e"}}
    assert import_cycles(two) == [["a", "b"], ["c", "d"]]
    deep = {f"m{i}": {f"m{i + 1}"} for i in range(5000)} | {"m5000": {"m0"}}
    assert import_cycles(deep) == [sorted(deep)]


def test_import_graph_reads_relative_and_package_imports(tmp_path: Path) -> None:
    """Self-check of the graph builder on a synthetic package: relative imports, submodules
    named in ``from . import x``, parent packages (``__init__``) as dependencies, function-level
    and TYPE_CHECKING imports kept apart, and a cycle through a package ``__init__`` found."""
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("from .b import B\n")
    (pkg / "a.py").write_text(
        "from .sub.c import C\nfrom typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n    from .d import D\n"
        "def f():\n    from . import d\n"
    )
    (pkg / "sub" / "b.py").write_text("from .. import a\nB = 1\n")
    (pkg / "sub" / "c.py").write_text("import pkg.d as d\nC = 1\n")
    (pkg / "d.py").write_text("import os\n")
    module_level = import_graph(pkg, in_functions=False)
    deferred = import_graph(pkg, in_functions=True)
    assert module_level["pkg.a"] == {"pkg.sub", "pkg.sub.c"}  # not pkg.d: TYPE_CHECKING only
    assert module_level["pkg.sub.b"] == {"pkg.a"}  # `from .. import a` names the module a
    assert module_level["pkg.sub.c"] == {"pkg.d"}  # its own packages are not dependencies
    assert deferred["pkg.a"] == {"pkg.d"}
    assert import_cycles(module_level) == [["pkg.a", "pkg.sub", "pkg.sub.b"]]  # via sub/__init__
