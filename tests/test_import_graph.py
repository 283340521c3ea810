"""No import circle in rikin or the grader, not even one hidden by a late import.

The graph is read from the source (no module is imported): every ``import`` and ``from ...
import`` statement counts, at module level, inside a function or class, and under ``if
TYPE_CHECKING:``, with relative imports resolved. ``from package import name`` is an edge to
the submodule ``package.name`` when there is one, else to the package's ``__init__``.
Importing a submodule also runs its package's ``__init__``, but that implied edge is not
drawn: a package's ``__init__`` re-exporting its children is the one loop Python's import
system is built for. A child importing a name back from its own package's ``__init__`` is an
explicit edge, and a circle through it fails like any other.

Show the graph's circles by hand: ``python3 tests/test_import_graph.py`` (prints none, or each).
"""

from __future__ import annotations

import ast
import sys
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: (package name, folder holding it)
PACKAGES = (("rikin", ROOT), ("rikingrade", ROOT / "grader"))

Graph = dict[str, set[str]]


def _modules() -> dict[str, tuple[Path, bool]]:
    """Dotted module name -> (path, whether it is a package's ``__init__``)."""
    found = {}
    for name, parent in PACKAGES:
        for path in sorted((parent / name).rglob("*.py")):
            if "__pycache__" in path.parts:
                continue
            parts = list(path.relative_to(parent).with_suffix("").parts)
            is_package = parts[-1] == "__init__"
            if is_package:
                parts.pop()
            found[".".join(parts)] = (path, is_package)
    return found


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    """The absolute name ``from <...> import`` refers to, seen from ``module``."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base.pop()  # a plain module's "." is its package
    if node.level > 1:
        base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _targets(module: str, is_package: bool, tree: ast.AST, known: set[str]) -> Iterator[str]:
    """Every module of ``known`` that ``tree`` imports, wherever the statement stands."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in known:
                    yield alias.name
        elif isinstance(node, ast.ImportFrom):
            source = _resolve(module, is_package, node)
            for alias in node.names:
                sub = f"{source}.{alias.name}"
                if sub in known:
                    yield sub
                elif source in known:
                    yield source


def import_graph() -> Graph:
    """Module -> the modules of rikin and rikingrade it imports (itself excluded)."""
    modules = _modules()
    known = set(modules)
    graph: Graph = {}
    for module, (path, is_package) in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        graph[module] = set(_targets(module, is_package, tree, known)) - {module}
    return graph


def cycles(graph: Graph) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
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
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 10 * len(graph) + 100))
    try:
        for v in sorted(graph):
            if v not in index:
                visit(v)
    finally:
        sys.setrecursionlimit(limit)
    return sorted(found)


def _describe(graph: Graph, component: list[str]) -> str:
    members = set(component)
    edges = [f"{a} -> {b}" for a in component for b in sorted(graph[a] & members)]
    return "; ".join(edges)


def test_no_import_circle_in_rikin_or_the_grader() -> None:
    graph = import_graph()
    found = cycles(graph)
    assert not found, "import circles:\n" + "\n".join(_describe(graph, c) for c in found)


def test_the_graph_sees_every_kind_of_import() -> None:
    graph = import_graph()
    assert len(graph) > 60, "the walk found too few modules: wrong folders?"
    assert "rikin.dh" in graph["rikin.transforms"] or "rikin._validate" in graph["rikin.dh"]
    # from . import robots (a submodule named in a package's __init__)
    assert "rikin.robots" in graph["rikin"]
    # from .. import dh, from ..dh import SerialArm (two levels up, under TYPE_CHECKING)
    assert "rikin.dh" in graph["rikin.ik.api"]
    assert "rikin.dh" in graph["rikin.ik.pieper_kernel"]
    # an import written inside a function (the grader's CLI imports its commands late)
    assert "rikingrade.api" in graph["rikingrade.cli"]


def test_the_circle_finder_finds_circles_and_only_them() -> None:
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": {"a"}, "c": {"d"}, "d": {"c"}}) == [["a", "b"], ["c", "d"]]


def test_a_late_import_back_is_a_circle() -> None:
    source_a = "from . import b\n"
    source_b = "def f():\n    from .a import g  # late\n    return g\n"
    known = {"p", "p.a", "p.b"}
    graph = {
        "p.a": set(_targets("p.a", False, ast.parse(source_a), known)),
        "p.b": set(_targets("p.b", False, ast.parse(source_b), known)),
    }
    assert graph == {"p.a": {"p.b"}, "p.b": {"p.a"}}
    assert cycles(graph) == [["p.a", "p.b"]]


if __name__ == "__main__":
    g = import_graph()
    print(f"{len(g)} modules, {sum(len(t) for t in g.values())} imports between them")
    for c in cycles(g):
        print("circle:", _describe(g, c))
