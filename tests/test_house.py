"""The house's shape, read from the source (issue 27): imports point down, the three engines meet
only through their faces, and a function longer than 80 lines says why it stays whole.

Pure ``ast``: nothing of the library is imported, so a circle shows here before it breaks an import.
"""
from __future__ import annotations

import ast
import functools
from pathlib import Path

PACKAGE = "frictionjoint"
ROOT = Path(__file__).resolve().parent.parent / PACKAGE

#: the engines of ``solvers/``: each reaches another only through that one's ``__init__`` (its face)
ENGINES = ("frictionjoint.solvers.sdof", "frictionjoint.solvers.marcher", "frictionjoint.solvers.frequency_domain")
#: engines a given engine must not import at all: the marcher sits below the other two
FORBIDDEN = {"frictionjoint.solvers.marcher": ("frictionjoint.solvers.sdof", "frictionjoint.solvers.frequency_domain")}

MAX_LINES = 80
#: functions over MAX_LINES lines (``def`` to last line, docstring included) that stay whole, and why
LONG = {
    "frictionjoint.solvers.frequency_domain.loop_kernels:flank_loop_kernel":
        "each piece of the loop is a compiled step; what stays is the workspace, the three starts and the "
        "march that dispatches the pieces (a further split would pass some thirty arrays per call)",
    "frictionjoint.solvers.marcher.consistency:check":
        "the piece's start as compiled helpers made the test 6-10 % slower; 50 of its lines are its docstring",
    "frictionjoint.solvers.marcher.search:first_event":
        "the marcher's hottest loop: its steps as compiled helpers cost 4-8 % per call",
    "frictionjoint.sweep:sweep":
        "the one sweep entry point: its docstring documents every kind of model it takes (about 70 "
        "lines), and its body is the 25-line dispatch on the model, whose branches are named functions",
}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


@functools.lru_cache(maxsize=1)  # read and parsed once for the whole module
def _sources() -> dict[str, tuple[Path, ast.Module]]:
    """Module name -> (path, syntax tree) of every module of the package."""
    return {_module_name(p): (p, ast.parse(p.read_text(encoding="utf-8"), str(p)))
            for p in sorted(ROOT.rglob("*.py"))}


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _imports(tree: ast.AST):
    """Every import statement in ``tree``, at module level and inside functions and classes, but
    not those under ``if TYPE_CHECKING:`` (they never run)."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
            continue
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            stack.extend(node.orelse)
            continue
        stack.extend(ast.iter_child_nodes(node))


def _targets(module: str, is_package: bool, node, known) -> set[str]:
    """The package's modules that the import ``node`` in ``module`` loads by name: ``from pkg import
    name`` is the submodule ``pkg.name`` where there is one, else ``pkg`` itself."""
    if isinstance(node, ast.Import):
        return {a.name for a in node.names if a.name in known}
    if node.level:
        base = module.split(".") if is_package else module.split(".")[:-1]
        base = base[:len(base) - (node.level - 1)]
        source = ".".join(base + ([node.module] if node.module else []))
    else:
        source = node.module or ""
    found = set()
    for alias in node.names:
        sub = f"{source}.{alias.name}"
        if sub in known:
            found.add(sub)
        elif source in known:
            found.add(source)
    return found


def import_graph(sources=None) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (self-imports left out)."""
    sources = _sources() if sources is None else sources
    graph = {}
    for module, (path, tree) in sources.items():
        is_package = path.name == "__init__.py"
        edges = set()
        for node in _imports(tree):
            edges |= _targets(module, is_package, node, sources)
        edges.discard(module)
        graph[module] = edges
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One circle of imports through each strongly connected component of more than one module
    (Tarjan), as the list of its modules with the first repeated at the end."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                components.append(set(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    circles = []
    for comp in components:  # a shortest way back to the start, inside the component
        start = min(comp)
        paths, frontier = {start: [start]}, [start]
        while frontier and start not in {w for v in frontier for w in graph[v]}:
            nxt = []
            for v in frontier:
                for w in sorted(graph[v] & comp):
                    if w not in paths:
                        paths[w] = paths[v] + [w]
                        nxt.append(w)
            frontier = nxt
        last = min(v for v in frontier if start in graph[v])
        circles.append(paths[last] + [start])
    return circles


def test_graph_reader_resolves_relative_and_submodule_imports():
    """The reader itself, on a small made-up package: relative imports, ``from pkg import
    submodule``, imports inside functions, and ``if TYPE_CHECKING:`` left out."""
    files = {
        "p": "from .a import f\nfrom . import b\n",
        "p.a": "def f():\n    from .b import g\n",
        "p.b": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .a import f\nfrom . import c\n",
        "p.c": "import p.a\nfrom p import X\n",
    }
    sources = {name: (Path(f"{name.replace('.', '/')}{'/__init__' if name == 'p' else ''}.py"), ast.parse(text))
               for name, text in files.items()}
    graph = import_graph(sources)
    assert graph == {"p": {"p.a", "p.b"}, "p.a": {"p.b"}, "p.b": {"p.c"}, "p.c": {"p.a", "p"}}
    assert _cycles(graph) == [["p", "p.b", "p.c", "p"]]  # the shortest way round


def test_no_circle_of_imports():
    """Imports point down: no module reaches itself again through the package's imports (module
    level or inside functions)."""
    circles = _cycles(import_graph())
    assert not circles, "circles of imports:\n" + "\n".join(" -> ".join(c) for c in circles)


def _engine(module: str) -> str | None:
    return next((e for e in ENGINES if module == e or module.startswith(e + ".")), None)


def test_engines_meet_only_through_their_faces():
    """A module of one engine imports another engine's package (its ``__init__``), never that
    engine's modules; the marcher imports neither the single-DOF kernel nor the frequency domain."""
    bad = []
    for module, targets in import_graph().items():
        own = _engine(module)
        if own is None:
            continue
        for target in sorted(targets):
            other = _engine(target)
            if other is None or other == own:
                continue
            if other in FORBIDDEN.get(own, ()):
                bad.append(f"{module} imports {target} ({own} imports no {other})")
            elif target != other:
                bad.append(f"{module} imports {target}, not the face {other}")
    assert not bad, "\n".join(bad)


def _functions(tree: ast.Module):
    """``(qualname, lines)`` of every function and method, nested ones too."""
    stack = [(tree, "")]
    while stack:
        node, prefix = stack.pop()
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = f"{prefix}{child.name}"
                if not isinstance(child, ast.ClassDef):
                    yield name, child.end_lineno - child.lineno + 1
                stack.append((child, name + "."))
            else:
                stack.append((child, prefix))


def test_long_functions_say_why():
    """No function is longer than MAX_LINES lines unless LONG gives the sentence why it stays whole;
    LONG lists only functions that are still that long."""
    long = {f"{module}:{name}": n for module, (_, tree) in _sources().items()
            for name, n in _functions(tree) if n > MAX_LINES}
    unexplained = {k: n for k, n in long.items() if k not in LONG}
    assert not unexplained, f"functions over {MAX_LINES} lines without their sentence in LONG: {unexplained}"
    stale = sorted(set(LONG) - set(long))
    assert not stale, f"LONG lists functions no longer over {MAX_LINES} lines (or gone): {stale}"
    assert all(isinstance(why, str) and why.strip() for why in LONG.values())
