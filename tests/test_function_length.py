"""No function in rikin/, grader/, tools/ or benchmarks/ is longer than a screen (80 lines).

A long function is split where a step wants a name. ``STILL_LONG`` lists the functions that
are longer today, each waiting for its split: the test fails when one of them has become
short (remove it from the list, so the list only shrinks) and when a function not in the
list grows past the limit.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("rikin", "grader", "tools", "benchmarks")
MAX_LINES = 80

#: "path::Qualified.name" of each function still over MAX_LINES. Only ever remove entries.
STILL_LONG = frozenset({
})


def _functions(tree: ast.AST, prefix: str = "") -> Iterator[tuple[str, int]]:
    """(qualified name, length in lines) of every function in ``tree``, nested ones too."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            assert node.end_lineno is not None
            yield prefix + node.name, node.end_lineno - node.lineno + 1
            yield from _functions(node, f"{prefix}{node.name}.")
        elif isinstance(node, ast.ClassDef):
            yield from _functions(node, f"{prefix}{node.name}.")
        else:
            yield from _functions(node, prefix)


def _lengths() -> dict[str, int]:
    lengths = {}
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            if ".venv" in path.parts or "__pycache__" in path.parts:
                continue
            tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
            rel = path.relative_to(ROOT).as_posix()
            for name, n in _functions(tree):
                lengths[f"{rel}::{name}"] = n
    return lengths


def test_no_new_function_longer_than_a_screen() -> None:
    lengths = _lengths()
    assert len(lengths) > 500, "the walk found too few functions: wrong folders?"
    new = {k: n for k, n in lengths.items() if n > MAX_LINES and k not in STILL_LONG}
    assert not new, f"longer than {MAX_LINES} lines (split where a step wants a name): {new}"


def test_the_list_of_long_functions_only_shrinks() -> None:
    lengths = _lengths()
    gone = sorted(k for k in STILL_LONG if k not in lengths)
    assert not gone, f"listed in STILL_LONG but no longer found (remove them): {gone}"
    short = sorted(k for k in STILL_LONG if lengths[k] <= MAX_LINES)
    assert not short, f"now at most {MAX_LINES} lines: remove them from STILL_LONG: {short}"


def test_the_walk_measures_nested_and_method_functions() -> None:
    source = "class A:\n    def f(self):\n        def g():\n            pass\n        return g\n"
    assert dict(_functions(ast.parse(source))) == {"A.f": 4, "A.f.g": 2}
