"""The JSON wire format between the grader and a sandboxed child (never pickle).

Plain JSON plus one-key marker objects, mirrored in ``sandbox/child.py``:

- ``{"$float": "nan" | "inf" | "-inf"}``: a non-finite float (JSON has none);
- ``{"$complex": [re, im]}``: a complex number;
- ``{"$dict": [[key, value], ...]}``: a dict that has a key starting with ``$``;
- ``{"$tuple": [...]}`` and ``{"$ndarray": {"dtype", "shape", "data"}}``: grader to
  child only, so a hidden test's numpy array arrives in the student's function as a numpy
  array of the same dtype and shape, and a tuple as a tuple.

Results coming back are decoded to plain Python: lists for arrays and tuples, floats for
non-finite markers. Anything else a child sends is a protocol error, never an object.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

MAX_DEPTH = 64


class WireError(ValueError):
    """Data that cannot cross the wire, or a malformed message from a child."""


def _float(x: float) -> Any:
    if math.isfinite(x):
        return x
    return {"$float": "nan" if x != x else ("inf" if x > 0 else "-inf")}


def encode_input(obj: Any, depth: int = 0) -> Any:
    """Wire data for a hidden test's keyword argument (grader to child)."""
    if depth > MAX_DEPTH:
        raise WireError("test input nested too deeply")
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (int, np.integer)) and not isinstance(obj, np.bool_):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, (float, np.floating)):
        return _float(float(obj))
    if isinstance(obj, (complex, np.complexfloating)):
        return {"$complex": [_float(float(obj.real)), _float(float(obj.imag))]}
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind not in "biufc":
            raise WireError(f"cannot send an array of dtype {obj.dtype}")
        return {
            "$ndarray": {
                "dtype": obj.dtype.str,
                "shape": list(obj.shape),
                "data": encode_input(obj.ravel().tolist(), depth + 1),
            }
        }
    if isinstance(obj, tuple):
        return {"$tuple": [encode_input(x, depth + 1) for x in obj]}
    if isinstance(obj, list):
        return [encode_input(x, depth + 1) for x in obj]
    if isinstance(obj, dict):
        out = {}
        for k, v in obj.items():
            if not isinstance(k, str):
                raise WireError(f"test input dict keys must be strings, got {type(k).__name__}")
            out[k] = encode_input(v, depth + 1)
        if any(k.startswith("$") for k in out):
            return {"$dict": [[k, v] for k, v in out.items()]}
        return out
    raise WireError(f"cannot send a {type(obj).__name__} to a student function")


def _hook(d: dict[str, Any]) -> Any:
    if len(d) == 1:
        ((k, v),) = d.items()
        if k == "$float":
            if v not in ("nan", "inf", "-inf"):
                raise WireError(f"bad float marker {v!r}")
            return float(v)
        if k == "$complex":
            if not (isinstance(v, list) and len(v) == 2):
                raise WireError("bad complex marker")
            re_, im_ = v
            if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
                raise WireError("bad complex marker")
            return complex(re_, im_)
        if k == "$dict":
            if not (isinstance(v, list) and all(isinstance(p, list) and len(p) == 2 for p in v)):
                raise WireError("bad dict marker")
            return {str(kk): vv for kk, vv in v}
    return d


def _no_constant(name: str) -> Any:
    raise WireError(f"JSON constant {name} is not allowed (non-finite floats use markers)")


def decode_message(line: bytes | str) -> dict[str, Any]:
    """One message from a child, with markers turned back into Python values."""
    try:
        msg = json.loads(line, object_hook=_hook, parse_constant=_no_constant)
    except WireError:
        raise
    except (ValueError, RecursionError, UnicodeDecodeError) as exc:
        raise WireError(f"malformed message from the notebook process: {exc}") from None
    if not isinstance(msg, dict):
        raise WireError("malformed message from the notebook process: not an object")
    return msg


def encode_message(msg: dict[str, Any]) -> bytes:
    """One grader message as a JSON line."""
    return (json.dumps(msg, allow_nan=False, separators=(",", ":")) + "\n").encode()


# ----------------------------------------------------------------------------- unreadable results
#: Type names a feedback line may show (the type of a student's return value is
#: student-controlled text: a class named after a hidden input must not reach the feedback).
KNOWN_TYPES = frozenset(
    {
        f"builtins.{n}"
        for n in (
            "set frozenset dict str bytes bytearray function builtin_function_or_method "
            "generator coroutine async_generator method module type object map filter zip "
            "range enumerate reversed list_iterator tuple_iterator NoneType ellipsis "
            "NotImplementedType property staticmethod classmethod slice memoryview "
            "dict_keys dict_values dict_items"
        ).split()
    }
    | {"numpy.dtype", "numpy.ufunc", "numpy.random._generator.Generator"}
)


def type_words(name: str) -> str:
    """Words for a returned value's type (``"module.Name"``): known names, else generic."""
    if name in KNOWN_TYPES:
        short = name.split(".")[-1]
        article = "an" if short[:1].lower() in "aeiou" else "a"
        return {"NoneType": "None"}.get(short, f"{article} {short}")
    if name.startswith("sympy."):
        return "a sympy object"
    if name.startswith(("numpy.", "builtins.")):
        return "a numpy object" if name.startswith("numpy.") else "a Python object"
    return "an object of a class defined in the notebook"


def unreadable_text(code: str) -> str:
    """The student-facing reason for a child's ``UnreadableResult`` code (see child.encode)."""
    kind, _, arg = str(code).partition(":")
    fixed = {
        "elements": "a result with more than a million numbers",
        "depth": "a result nested too deeply",
        "bigint": "a number too large for a float (beyond 1.8e308)",
        "string": "a very long string",
        "symbols": (
            "a sympy expression with free symbols (substitute the values and return numbers)"
        ),
    }
    if kind in fixed:
        return f"returned {fixed[kind]}, which the grader cannot read"
    if kind == "dictkey":
        return "returned a dict with keys the grader cannot read"
    if kind == "dtype":
        return "returned a numpy array whose dtype is not numbers"
    if kind == "type":
        return (
            f"returned {type_words(arg)}, which the grader cannot read; "
            "return numbers, lists or numpy arrays"
        )
    return "returned a value the grader cannot read"
