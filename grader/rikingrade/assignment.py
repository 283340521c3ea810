"""Loading an assignment: a hidden-test module that follows ``rikingrade.spec``.

``scara`` means ``rikingrade.hidden.scara``; a dotted name is imported as is; a path to a
``.py`` file is loaded from that file. The module must expose EXERCISE, NOTEBOOK,
FUNCTIONS and TESTS (a list of :class:`~rikingrade.spec.HiddenTest`).
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np

from .spec import Call, HiddenTest


class AssignmentError(ValueError):
    """The assignment cannot be found or does not follow the contract."""


@dataclass
class Assignment:
    """A loaded hidden-test module and the calls every submission gets."""

    name: str
    module: ModuleType
    exercise: str
    notebook: str
    functions: tuple[str, ...]
    tests: list[HiddenTest]
    source_path: Path | None
    fingerprint: str

    @property
    def max_score(self) -> float:
        return float(sum(t.weight for t in self.tests))

    def calls(self, seed: int) -> list[list[Call]]:
        """The calls of each test; the same for every submission of a batch.

        Test ``i`` draws from ``numpy.random.default_rng([seed, i])``, so adding a test does
        not change the inputs of the others.
        """
        out = []
        for i, t in enumerate(self.tests):
            try:
                calls = list(t.make_calls(np.random.default_rng([int(seed), i])))
            except Exception as exc:
                raise AssignmentError(
                    f"test {t.name}: make_calls failed: {type(exc).__name__}: {exc}"
                ) from exc
            for c in calls:
                if not isinstance(c, Call):
                    raise AssignmentError(
                        f"test {t.name}: make_calls returned {type(c).__name__}, not Call"
                    )
            out.append(calls)
        return out


def _module_source(mod: ModuleType) -> bytes:
    path = getattr(mod, "__file__", None)
    if path and Path(path).exists():
        return Path(path).read_bytes()
    return repr(mod).encode()


def load_assignment(name: str | Path) -> Assignment:
    """The assignment ``name`` (an exercise name, a dotted module or a .py path)."""
    text = str(name)
    path = Path(text)
    if text.endswith(".py") or path.is_file():
        if not path.is_file():
            raise AssignmentError(f"no such assignment file: {path}")
        modname = "rikingrade_assignment_" + re.sub(r"\W", "_", path.stem)
        spec = importlib.util.spec_from_file_location(modname, path)
        if spec is None or spec.loader is None:
            raise AssignmentError(f"cannot load {path} as a Python module")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[modname] = mod
        try:
            spec.loader.exec_module(mod)
        except Exception as exc:
            sys.modules.pop(modname, None)
            raise AssignmentError(f"loading {path} failed: {type(exc).__name__}: {exc}") from exc
    else:
        modname = text if "." in text else f"rikingrade.hidden.{text}"
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name and modname.startswith(exc.name):
                known = available_exercises()
                hint = f" (known: {', '.join(known)})" if known else ""
                raise AssignmentError(f"no assignment named {text!r}{hint}") from None
            raise
    missing = [a for a in ("EXERCISE", "NOTEBOOK", "FUNCTIONS", "TESTS") if not hasattr(mod, a)]
    if missing:
        raise AssignmentError(
            f"{mod.__name__} does not define {', '.join(missing)} (see rikingrade.spec)"
        )
    tests = list(mod.TESTS)
    if not tests:
        raise AssignmentError(f"{mod.__name__} has no TESTS")
    names = [t.name for t in tests]
    for t in tests:
        if not isinstance(t, HiddenTest):
            raise AssignmentError(
                f"{mod.__name__}.TESTS holds a {type(t).__name__}, not HiddenTest"
            )
        if not (t.weight >= 0):
            raise AssignmentError(f"test {t.name}: weight must be >= 0")
    dups = {n for n in names if names.count(n) > 1}
    if dups:
        raise AssignmentError(f"duplicate test names in {mod.__name__}: {sorted(dups)}")
    src = getattr(mod, "__file__", None)
    h = hashlib.sha256(_module_source(mod))
    if mod.__name__.startswith("rikingrade.hidden."):
        # The reference and the shared hidden-test helpers change scores too (read from
        # disk, so the key does not depend on what else this process imported).
        pkg = Path(__file__).resolve().parent
        for f in sorted([*pkg.glob("reference/*.py"), *pkg.glob("hidden/_*.py")]):
            h.update(f.name.encode() + b"\0" + f.read_bytes())
    return Assignment(
        name=text,
        module=mod,
        exercise=str(mod.EXERCISE),
        notebook=str(mod.NOTEBOOK),
        functions=tuple(mod.FUNCTIONS),
        tests=tests,
        source_path=Path(src).resolve() if src else None,
        fingerprint=h.hexdigest()[:16],
    )


def available_exercises() -> list[str]:
    """Names of the exercise modules in ``rikingrade.hidden``."""
    try:
        import rikingrade.hidden as hidden
    except ImportError:
        return []
    out = []
    for d in hidden.__path__:
        for p in sorted(Path(d).glob("*.py")):
            if not p.name.startswith("_"):
                out.append(p.stem)
    return out
