"""Which code cells the grader runs: every cell but those that only call the answer functions.

The hidden tests call a notebook's answer functions themselves, so a cell whose only job is
to call them (the exercise's visible checks, ``print_solutions(ik_scara(...))``, a
student's own test or drawing of the arm) adds nothing to the grade; run while grading, an
endless loop in a function it calls would cost the whole cell timeout once per such cell.
These cells are found by reading the code (never by running it), so the rule holds whether
or not the notebook kept the exercise's tags (``raises-exception`` in exercises/,
``nbval-check-output`` in solutions/ mark the same cells):

* the cell parses as Python, refers to an answer function outside any function body, and
  does not bind an answer function's name;
* no cell that runs uses a name the cell binds (an assignment, import, ``def`` or
  ``class`` at the cell's top level), so skipping it cannot change what runs.

The second rule is applied until nothing changes; anything in doubt runs.
"""

from __future__ import annotations

import ast
import re
import threading
from collections.abc import Iterable

_WORD = re.compile(r"[^\W\d]\w*")

_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)


def _free(node: ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda | ast.ClassDef) -> set[str]:
    """Names a function, lambda or class body reads from outside (its globals)."""
    args = getattr(node, "args", None)
    local: set[str] = set()
    if isinstance(args, ast.arguments):
        for a in [*args.posonlyargs, *args.args, *args.kwonlyargs, args.vararg, args.kwarg]:
            if a is not None:
                local.add(a.arg)
    body = node.body if isinstance(node.body, list) else [node.body]
    declared: set[str] = set()
    loads: set[str] = set()
    stack: list[ast.AST] = list(body)
    while stack:
        n = stack.pop()
        if isinstance(n, (ast.Global, ast.Nonlocal)):
            declared.update(n.names)
        elif isinstance(n, ast.Name):
            (loads if isinstance(n.ctx, ast.Load) else local).add(n.id)
        elif isinstance(n, _SCOPES):
            if not isinstance(n, ast.Lambda):
                local.add(n.name)
            loads |= _free(n)
            stack.extend(_outer_parts(n))
            continue
        elif isinstance(n, ast.alias):
            local.add((n.asname or n.name).split(".")[0])
        elif isinstance(n, ast.ExceptHandler) and n.name:
            local.add(n.name)
        stack.extend(ast.iter_child_nodes(n))
    return loads - (local - declared)


def _outer_parts(node: ast.AST) -> list[ast.AST]:
    """Decorators, defaults and bases: evaluated where the function or class is defined."""
    parts: list[ast.AST] = list(getattr(node, "decorator_list", []))
    args = getattr(node, "args", None)
    if isinstance(args, ast.arguments):
        parts += [*args.defaults, *[k for k in args.kw_defaults if k is not None]]
    parts += [*getattr(node, "bases", []), *getattr(node, "keywords", [])]
    return parts


class _Names:
    """Names a cell binds and reads at its top level, and every global name it reads."""

    def __init__(self, tree: ast.Module) -> None:
        self.bound: set[str] = set()
        self.top_used: set[str] = set()
        self.used: set[str] = set()
        self.dynamic = False  # globals()/exec/...: the cell may bind anything
        stack: list[ast.AST] = list(tree.body)
        while stack:
            n = stack.pop()
            if isinstance(n, ast.Name):
                if isinstance(n.ctx, ast.Load):
                    self.top_used.add(n.id)
                    self.dynamic |= n.id in _DYNAMIC
                else:
                    self.bound.add(n.id)
            elif isinstance(n, _SCOPES):
                if not isinstance(n, ast.Lambda):
                    self.bound.add(n.name)
                self.used |= _free(n)
                stack.extend(_outer_parts(n))
                continue
            elif isinstance(n, ast.alias):
                self.dynamic |= n.name == "*"
                self.bound.add((n.asname or n.name).split(".")[0])
            elif isinstance(n, ast.ExceptHandler) and n.name:
                self.bound.add(n.name)
            elif isinstance(n, (ast.Global, ast.Nonlocal)):
                self.bound.update(n.names)
            stack.extend(ast.iter_child_nodes(n))
        self.used |= self.top_used


_DYNAMIC = {"globals", "exec", "eval", "setattr", "vars", "__import__", "get_ipython"}


#: CPython 3.11's parser is not thread-safe: two grader workers parsing at once can fail
#: with "SystemError: AST constructor recursion depth mismatch" (fixed in 3.12). One parse
#: at a time.
_PARSE_LOCK = threading.Lock()


def _names(source: str) -> _Names | None:
    try:
        with _PARSE_LOCK:
            tree = ast.parse(source)
        return _Names(tree)
    except (SyntaxError, ValueError, RecursionError, MemoryError, SystemError):
        return None  # IPython syntax, a broken cell, a lone surrogate: run it


def calling_cells(cells: Iterable[tuple[int, str]], functions: Iterable[str]) -> set[int]:
    """Numbers of the cells that only call the answer ``functions`` (see the module)."""
    answers = set(functions)
    cells_list = list(cells)
    info: dict[int, _Names | None] = {n: _names(src) for n, src in cells_list}
    skip = {
        n
        for n, v in info.items()
        if v is not None and not v.dynamic and v.top_used & answers and not v.bound & answers
    }
    # a cell that cannot be parsed (IPython syntax) may use any word it contains
    words = {n: set(_WORD.findall(src)) for n, src in cells_list if info[n] is None}
    while True:
        used: set[str] = set()
        for n, v in info.items():
            if n not in skip:
                used |= v.used if v is not None else words[n]
        keep = {n for n in skip if info[n].bound & used}  # type: ignore[union-attr]
        if not keep:
            return skip
        skip -= keep
