"""Architecture rules over both packages (overseec_core and the QGIS adapter overseec_qgis):
no import cycles, the stage order, Synthesize never interpreting, run-folder names only in
``runfiles``, and the light stages free of torch. Import rules read the source (``ast``): every
import counts, at module level or inside a function, except under ``if TYPE_CHECKING:``."""

from __future__ import annotations

import ast
import pkgutil
import re
import subprocess
import sys
import textwrap
from collections.abc import Collection, Iterator, Mapping, Sequence
from pathlib import Path

import pytest

import overseec_core

REPO = Path(__file__).resolve().parent.parent
CORE = Path(overseec_core.__file__).resolve().parent
#: The QGIS adapter, read as source only (importing it needs QGIS).
QGIS = REPO / "overseec_qgis"
PACKAGES = (CORE, QGIS)

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


def _import_nodes(
    tree: ast.AST, *, in_functions: bool, type_checking: bool = False
) -> Iterator[ast.Import | ast.ImportFrom]:
    """The imports a module runs when it is imported (``in_functions=False``: module and class
    bodies, ``try``/``if`` included) or only when one of its functions runs (``True``). Imports
    under ``if TYPE_CHECKING:`` never run and are skipped, unless ``type_checking`` (then they
    count as module level: what a reader and mypy must understand together)."""

    def walk(node: ast.AST, inside: bool) -> Iterator[ast.Import | ast.ImportFrom]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                yield from walk(child, True)
            elif isinstance(child, ast.If) and _is_type_checking(child.test):
                if type_checking and not in_functions:
                    yield from walk(child, inside)
                continue
            elif isinstance(child, (ast.Import, ast.ImportFrom)):
                if inside == in_functions:
                    yield child
            else:
                yield from walk(child, inside)

    return walk(tree, False)


def _module_files(root: Path) -> dict[str, Path]:
    return {_module_name(p, root): p for p in sorted(root.rglob("*.py"))}


def _imported(node: ast.Import | ast.ImportFrom, package: str, modules: Collection[str]) -> Iterator[str]:
    """The modules of ``modules`` one import statement names, each the most specific one:
    ``from a.b import c`` names ``a.b.c`` when that is a module, else ``a.b`` (``c`` is a name in
    it); relative imports are resolved against ``package``."""
    if isinstance(node, ast.Import):
        targets = [a.name for a in node.names]
    else:
        base = node.module or ""
        if node.level:
            parts = package.split(".")[: len(package.split(".")) - node.level + 1]
            base = ".".join(parts + ([node.module] if node.module else []))
        targets = [f"{base}.{a.name}" for a in node.names]
    for target in targets:
        while target and target not in modules:
            target = target.rpartition(".")[0]
        if target:
            yield target


def import_graph(root: Path, *, in_functions: bool, type_checking: bool = False) -> dict[str, set[str]]:
    """Module -> the package modules it imports, from the source (nothing is imported).

    ``from a.b import c`` depends on ``a.b.c`` when that is a module, else on ``a.b``; importing
    ``a.b.c`` also runs ``a`` and ``a.b`` (their ``__init__``), so those are dependencies too,
    except the module's own enclosing packages, which are always initialised first."""
    files = _module_files(root)
    graph: dict[str, set[str]] = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges: set[str] = set()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in _import_nodes(tree, in_functions=in_functions, type_checking=type_checking):
            for target in _imported(node, package, files):
                parts = target.split(".")
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


def _graphs(root: Path) -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    return import_graph(root, in_functions=False), import_graph(root, in_functions=True)


def _all_imports(root: Path) -> dict[str, set[str]]:
    """Module -> the package modules it imports anywhere (module level and functions alike)."""
    module_level, deferred = _graphs(root)
    return {name: module_level[name] | deferred[name] for name in module_level}


@pytest.mark.parametrize("root", PACKAGES, ids=lambda r: r.name)
def test_no_import_cycles_at_import_time(root: Path) -> None:
    """No cycle among a package's modules through the imports that run when a module is
    imported (module level, class bodies, ``try``/``if`` blocks; not ``if TYPE_CHECKING``).

    These are the cycles that break: depending on which module a caller imports first, one of
    them sees the other half-initialised (an ImportError or a missing name). They also mark two
    modules that cannot be understood or tested apart. A cycle is fixed by moving what both need
    into a module below them (as ``schema.py`` and ``costlang/ops.py`` were), never by hiding an
    import inside a function."""
    module_level, _ = _graphs(root)
    assert import_cycles(module_level) == []


@pytest.mark.parametrize("root", PACKAGES, ids=lambda r: r.name)
def test_no_import_cycles_through_function_level_imports(root: Path) -> None:
    """The same over module-level and function-level imports together.

    Function-level imports are counted separately rather than ignored: they run after every
    module is initialised, so they cannot fail the way a module-level cycle does, which is
    exactly why they used to hide cycles (``costlang.lang`` <-> ``costlang.evaluator`` through
    ``apply_scalar``; ``costlang.synth`` -> ``interpret.schema`` -> ``interpret`` -> costlang).
    They stay legitimate for deferring a heavy optional dependency (torch, fiona, ...), which
    adds no edge between our own modules, so the whole graph must be acyclic too."""
    assert import_cycles(_all_imports(root)) == []


def test_no_import_cycles_through_type_only_imports() -> None:
    """The core's graph with its ``if TYPE_CHECKING:`` imports too has no cycle either: a type-only
    circle (synthesize.engine -> layers -> options -> engine) still ties modules that cannot be
    read apart. (The QGIS adapter's map-tool mixins annotate each other by design until they
    become collaborator objects: issue 34, rooms for the plugin.)"""
    root = PACKAGES[0]
    graph = _all_imports(root)
    for name, deps in import_graph(root, in_functions=False, type_checking=True).items():
        graph[name] = graph.get(name, set()) | deps
    assert import_cycles(graph) == []


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


# --- stage order ---------------------------------------------------------------------------------
#: overseec_core's parts (top-level modules and packages) from the bottom up. A module imports,
#: anywhere in it, only parts of its own layer or a lower one. Data flows io -> interpret ->
#: locate -> synthesize -> plan -> evaluate, so a stage never imports a later stage, the
#: pipeline, the commands or the CLI.
LAYERS: tuple[tuple[str, ...], ...] = (
    # base: plain facts and checks every layer shares (the package root only names its version)
    ("overseec_core", "errors", "defaults", "formats", "limits", "runfiles", "schema", "extras", "install", "liveness"),
    ("io",),
    # progress reports to the CLI and QGIS, and tells io's running output transaction to watch
    # for a cancel (io.transaction.watch), so it stands on io
    ("progress",),
    ("costlang",),  # the cost language: Interpret writes programs in it, Synthesize runs them
    ("interpret",),
    ("locate",),
    ("synthesize",),
    ("plan",),
    ("evaluate",),
    # tools over the stages: the Nav2/GIS exports, and the synthetic sample scene
    ("interop", "sample"),
    ("pipeline_costmap", "pipeline_compare", "pipeline"),  # chains the stages (costmap, compare, all)
    ("commands", "cli", "console"),  # the command line: one subcommand per stage or chain
)


def _part(module: str) -> str:
    """overseec_core.plan.grid -> 'plan'; overseec_core.errors -> 'errors'; the root -> itself."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def layer_violations(graph: Mapping[str, set[str]], layers: Sequence[Sequence[str]]) -> list[str]:
    """'module -> dependency' for every import of a part above the importer's layer, and
    'module: not in LAYERS' for a module of a part no layer names (a new part gets a place)."""
    rank = {part: i for i, layer in enumerate(layers) for part in layer}
    found = []
    for module, deps in sorted(graph.items()):
        if _part(module) not in rank:
            found.append(f"{module}: not in LAYERS")
            continue
        found += [f"{module} -> {dep}" for dep in sorted(deps) if rank.get(_part(dep), -1) > rank[_part(module)]]
    return found


def test_stages_import_only_earlier_stages() -> None:
    """Each overseec_core module imports (module level or inside a function) only its own layer
    or lower ones (:data:`LAYERS`)."""
    assert layer_violations(_all_imports(CORE), LAYERS) == []


def test_layer_check_finds_upward_imports() -> None:
    """Self-check: the test above can fail."""
    layers = (("overseec_core", "errors"), ("io",), ("plan", "sample"), ("cli",))
    graph = {
        "overseec_core.errors": set(),
        "overseec_core.io.read": {"overseec_core.errors", "overseec_core.plan.grid"},
        "overseec_core.plan.grid": {"overseec_core.io", "overseec_core.io.read", "overseec_core.sample"},
        "overseec_core.sample": {"overseec_core.plan"},
        "overseec_core.cli": {"overseec_core.plan", "overseec_core.errors"},
        "overseec_core.newpart.x": set(),
    }
    assert layer_violations(graph, layers) == [
        "overseec_core.io.read -> overseec_core.plan.grid",
        "overseec_core.newpart.x: not in LAYERS",
    ]


def test_the_core_never_imports_the_qgis_adapter() -> None:
    """The core is usable without QGIS: no core module imports overseec_qgis, even in a function."""
    found = []
    for name, path in _module_files(CORE).items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for in_functions in (False, True):
            for node in _import_nodes(tree, in_functions=in_functions):
                found += [f"{name} -> {t}" for t in _imported(node, package, {"overseec_qgis"})]
    assert found == []


# --- Synthesize never interprets -----------------------------------------------------------------
#: The Interpret modules Synthesize may use: data helpers (entity matching, rank merging, hazard
#: priors), never the interpreter. Synthesize receives an interpretation; it never makes one.
INTERPRET_HELPERS = frozenset({"matching", "merge", "priors"})
#: The interpreter's entry points: Synthesize calls none of them.
INTERPRETER_CALLS = frozenset({"interpret", "run_interpret", "interpret_offline", "interpret_llm"})


def interpreting(path: Path, module: str, modules: Collection[str]) -> list[str]:
    """What in one module interprets: an import of an Interpret module other than a data helper
    (``interpret.stage``, the package's ``interpret`` ...), or a call of an interpreter entry point."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = module.rpartition(".")[0] if path.name != "__init__.py" else module
    found = []
    for in_functions in (False, True):
        for node in _import_nodes(tree, in_functions=in_functions):
            for target in _imported(node, package, modules):
                parts = target.split(".")
                helper = len(parts) > 2 and parts[2] in INTERPRET_HELPERS
                if parts[:2] == ["overseec_core", "interpret"] and not helper:
                    found.append(f"{module}:{node.lineno} imports {target}")
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            func = node.func
            called = func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""
            if called in INTERPRETER_CALLS:
                found.append(f"{module}:{node.lineno} calls {called}()")
    return found


def test_synthesize_never_interprets() -> None:
    """No module of synthesize/ imports Interpret's front door or the interpreter, or calls it."""
    modules = _module_files(CORE)
    found = [
        hit
        for name, path in modules.items()
        if name.startswith("overseec_core.synthesize")
        for hit in interpreting(path, name, modules)
    ]
    assert found == []


def test_interpreting_check_finds_the_interpreter(tmp_path: Path) -> None:
    """Self-check: imports of interpret.stage or the package's interpret(), and calls, are found;
    the data helpers are not."""
    bad = tmp_path / "engine.py"
    bad.write_text(
        "from overseec_core.interpret.matching import match_entity\n"
        "from overseec_core.interpret import priors\n"
        "def f(p):\n"
        "    from overseec_core.interpret.stage import run_interpret\n"
        "    from overseec_core.interpret import interpret\n"
        "    return interpret(p)\n"
    )
    modules = {f"overseec_core.interpret.{m}" for m in ("matching", "priors", "stage")} | {"overseec_core.interpret"}
    assert interpreting(bad, "overseec_core.synthesize.engine", modules) == [
        "overseec_core.synthesize.engine:4 imports overseec_core.interpret.stage",
        "overseec_core.synthesize.engine:5 imports overseec_core.interpret",
        "overseec_core.synthesize.engine:6 calls interpret()",
    ]


# --- run-folder names only through runfiles ------------------------------------------------------
RUNFILES = CORE / "runfiles.py"
#: A run-folder file name as runfiles.py spells it: 'costmap.tif', '.manifest.lock' ...
_FILE_NAME = re.compile(r"\.?[\w-]+(\.[\w-]+)+")


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the docstring constants of a module, its classes and functions."""
    kinds = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
    return {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, kinds)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
        and isinstance(node.body[0].value.value, str)
    }


def _strings(tree: ast.AST) -> Iterator[ast.Constant]:
    """The string constants of a module that are not docstrings (f-string parts included)."""
    skip = _docstrings(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skip:
            yield node


def runfile_names() -> frozenset[str]:
    """The file names runfiles.py spells (its string constants that are file names)."""
    tree = ast.parse(RUNFILES.read_text(encoding="utf-8"))
    return frozenset(n.value for n in _strings(tree) if _FILE_NAME.fullmatch(n.value))


def name_literals(path: Path, names: Collection[str]) -> list[str]:
    """'file:line: name' for every string constant of ``path`` (docstrings aside) that spells one
    of ``names`` as a whole file name (in a path, a message or an f-string part alike; not the
    tail of a longer name such as ``v2.lethal.tif``)."""
    alternatives = "|".join(re.escape(n) for n in sorted(names, key=len, reverse=True))
    pattern = re.compile(rf"(?<![\w.-])(?:{alternatives})(?![\w-])")
    tree = ast.parse(path.read_text(encoding="utf-8"))
    rel = path.relative_to(REPO) if path.is_relative_to(REPO) else path
    return [
        f"{rel}:{node.lineno}: {name}"
        for node in sorted(_strings(tree), key=lambda n: (n.lineno, n.col_offset))
        for name in sorted(set(pattern.findall(node.value)))
    ]


def test_runfiles_owns_the_run_folder_names() -> None:
    """The scan below looks for the names that matter (so it cannot pass by finding none)."""
    must = {"costmap.tif", "lethal.tif", "path.geojson", "manifest.json", "masks.tif", "probs.tif"}
    assert must | {"refined_masks.tif", "interpretation.json", "metrics.json"} <= runfile_names()


def test_run_folder_names_are_spelled_only_in_runfiles() -> None:
    """Run-folder file names (costmap.tif, lethal.tif, manifest.json ...) appear as string
    literals only in ``runfiles.py``; every other module of the core and the QGIS adapter uses
    its constants, so renaming a file is one edit."""
    names = runfile_names()
    found = [
        hit
        for root in PACKAGES
        for path in sorted(root.rglob("*.py"))
        if path != RUNFILES
        for hit in name_literals(path, names)
    ]
    assert found == []


def test_name_scan_finds_literals_but_not_docstrings(tmp_path: Path) -> None:
    """Self-check: literals, f-string parts and messages are found; docstrings, comments and
    longer names that end in a run-folder name are not."""
    src = tmp_path / "m.py"
    src.write_text(
        '"""Writes costmap.tif."""\n'
        "def f(out, stem):\n"
        '    """Reads lethal.tif."""\n'
        '    a = out / "costmap.tif"  # lethal.tif\n'
        '    b = f"{stem}.lethal.tif", "v2.lethal.tif", "costmap.tiff"\n'
        '    raise ValueError(f"no masks.tif in {out}")\n'
    )
    assert name_literals(src, {"costmap.tif", "lethal.tif", "masks.tif"}) == [
        f"{src}:4: costmap.tif",
        f"{src}:6: masks.tif",
    ]
