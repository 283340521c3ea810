"""The only engine file a sandbox can see: a zygote that forks one process per submission.

Run as a script inside the sandbox (never imported by the grader). It imports the heavy
libraries once (numpy, sympy, matplotlib with Agg, IPython and its shell, rikin), then
waits on its control socket. For each submission the grader sends ``fork`` together with a
fresh socket; the zygote forks a child that sets its resource limits, moves into an empty
working directory and serves JSON lines on that socket:

grader -> child
    {"op": "exec", "cells": [[index, source], ...], "output_limit": int, "limit": s,
     "leash": {function: s}}
    {"op": "call", "id": int, "function": str, "args": [<wire>, ...], "kwargs": <wire>}
    {"op": "calls", "calls": [{"id", "function", "args", "kwargs"}, ...], "limit": s,
     "leash": {function: s}}  (answered one by one)
child -> grader
    {"event": "cell_start", "cell": i}
    {"event": "cell_end", "cell": i, "error": ..., "output": ..., "seconds": ...,
     "timed_out": null or <stop>}
    {"event": "exec_done", "functions": [...]}
    {"id": int, "value": <wire>, "seconds": s, "seen": {function: s}} or
    {"id": int, "timed_out": <stop>}  (the child stopped the call at its limit) or
    {"id": int, "error_type": str, "error_message": str, "error_bases": ["mod.Name", ...]}
    {"id": int, "error_type": "UnreadableResult", "error_message": <reason code>,
     "error_bases": ["rikingrade.UnreadableResult"]}  (it returned; the value cannot be read)

Time limits (``Watch``): each call gets ``limit`` seconds, a function named in ``leash``
that many wherever it is called from, and in a cell each call of an answer function gets
``limit``; a stop is {"stack": [function, ...], "function": str, "limit": s}: the notebook's
functions that were running, outermost first, and the one whose limit ran out. "seconds"
is how long the call took and "seen" how long the functions it called were seen running
(for the grader's short limits). Seconds are counted by ``busy_clock``: wall-clock time
less the time the process waited for a processor, so a busy machine changes no limit.

Cells run in IPython's own InteractiveShell (``GradingShell``), made in the zygote and
inherited by every child, as a Jupyter kernel runs them.

Nothing here decides a score: values go back as JSON (never pickle) and the grader compares.
Wire format: JSON plus one-key marker objects: {"$float": "nan"|"inf"|"-inf"},
{"$complex": [re, im]}, {"$dict": [[key, value], ...]} (a dict with a "$" key),
{"$tuple": [...]} and {"$ndarray": {"dtype", "shape", "data"}} (grader -> child only).

Standard library only at import time; numpy is used when present. Keep this file
self-contained: it is bind-mounted alone into the sandbox.
"""

import builtins
import contextlib
import io
import json
import math
import os
import resource
import shutil
import signal
import socket
import sys
import traceback

# Bind the builtins this file uses as module globals, so a notebook that monkeypatches
# builtins (isinstance = lambda *a: True, ...) cannot change how results are encoded.
from builtins import (  # noqa: E402,A004,UP029
    BaseException,
    Exception,
    any,
    callable,
    complex,
    dict,
    float,
    getattr,
    hasattr,
    int,
    isinstance,
    len,
    list,
    max,
    reversed,
    round,
    set,
    sorted,
    str,
    tuple,
    type,
)

PROTOCOL = 1
MIB = 1024 * 1024
MAX_DEPTH = 64
MAX_ELEMENTS = 1_000_000
MAX_STR = 1_000_000
MAX_ERROR_CHARS = 2000
SCRATCH_KEEP = (".mpl",)  # entries of /scratch the zygote owns (font cache)

_dumps = json.dumps
_loads = json.loads
_write = os.write
_getpid = os.getpid
_exit = os._exit
_monotonic = __import__("time").monotonic
_sleep = __import__("time").sleep

np = None  # numpy, once preloaded


class EncodeError(Exception):
    """A return value the grader cannot read.

    The message is a reason code, not prose: ``elements``, ``depth``, ``bigint``,
    ``string``, ``symbols``, ``dictkey:<type>``, ``dtype:<dtype>`` or ``type:<type>``.
    The grader composes the student's text from it (``rikingrade.wire.unreadable_text``),
    naming the type only when it is a well-known one.
    """


UNREADABLE = "UnreadableResult"
UNREADABLE_BASES = ["rikingrade.UnreadableResult"]


def _type_name(obj):
    t = type(obj)
    return f"{getattr(t, '__module__', '') or ''}.{getattr(t, '__qualname__', '?')}"[:120]


# ----------------------------------------------------------------------------- wire format
def _enc_float(x):
    if math.isfinite(x):
        return x
    return {"$float": "nan" if x != x else ("inf" if x > 0 else "-inf")}


def encode(obj, depth=0, budget=None):
    """Plain JSON-able data for ``obj``; raises EncodeError (a reason code) otherwise.

    Reads what the visible checks read with ``numpy.asarray``: numbers of any kind
    (Python, numpy of any width, longdouble and clongdouble included, sympy, Fraction,
    Decimal; integers of any size that a float holds), lists, tuples, numpy arrays and
    their subclasses, sympy matrices, and anything with ``__array__``.
    """
    if budget is None:
        budget = [MAX_ELEMENTS]
    budget[0] -= 1
    if budget[0] < 0:
        raise EncodeError("elements")
    if depth > MAX_DEPTH:
        raise EncodeError("depth")
    t = type(obj)
    if obj is None or t is bool:
        return obj
    if t is int:
        return _enc_int(obj)
    if t is float:
        return _enc_float(obj)
    if t is str:
        if len(obj) > MAX_STR:
            raise EncodeError("string")
        return obj
    if t is complex:
        return {"$complex": [_enc_float(obj.real), _enc_float(obj.imag)]}
    if t in (list, tuple):
        return [encode(x, depth + 1, budget) for x in obj]
    if t is dict:
        return _enc_dict(obj, depth, budget)
    if np is not None:
        if isinstance(obj, np.ndarray):
            return _enc_array(obj, depth, budget)
        if isinstance(obj, np.generic):
            return _enc_scalar(obj, depth, budget)
    # bool/int/float subclasses (e.g. IntEnum), sympy numbers, Fraction, Decimal
    if isinstance(obj, bool):
        return bool(obj)
    if isinstance(obj, int):
        return _enc_int(int(obj))
    if isinstance(obj, float):
        return _enc_float(float(obj))
    if isinstance(obj, (list, tuple)):
        return [encode(x, depth + 1, budget) for x in obj]
    if (type(obj).__module__ or "").startswith("sympy"):
        return _enc_sympy(obj, depth, budget)
    if hasattr(obj, "__array__") and np is not None:
        try:
            arr = np.asarray(obj)
        except Exception:
            arr = None
        if arr is not None and arr.dtype.kind in "biufcO":
            return encode(arr, depth, budget)
    return _enc_number(obj)


def _enc_sympy(obj, depth, budget):
    """A sympy object: a matrix as nested lists, a number without free symbols as a float
    (or a complex when its imaginary part is not zero)."""
    if getattr(obj, "is_Matrix", False) and hasattr(obj, "tolist"):
        return encode(obj.tolist(), depth + 1, budget)
    free = getattr(obj, "free_symbols", None)
    if free:
        raise EncodeError("symbols")
    try:
        z = complex(obj)
    except Exception:
        raise EncodeError(f"type:{_type_name(obj)}") from None
    return _enc_float(z.real) if z.imag == 0 else encode(z, depth, budget)


def _enc_int(x):
    """An int on the wire: as it is within int64, else as the float numpy would make."""
    if -(2**63) <= x < 2**63:
        return x
    try:
        return float(x)
    except OverflowError:
        raise EncodeError("bigint") from None


def _enc_number(obj):
    """Anything else that Python turns into a float or a complex (Fraction, Decimal, mpf)."""
    if hasattr(obj, "__float__") and not hasattr(obj, "__len__"):
        try:
            return _enc_float(float(obj))
        except OverflowError:
            raise EncodeError("bigint") from None
        except Exception:
            pass
    if hasattr(obj, "__complex__") and not hasattr(obj, "__len__"):
        try:
            z = complex(obj)
            return {"$complex": [_enc_float(z.real), _enc_float(z.imag)]}
        except Exception:
            pass
    raise EncodeError(f"type:{_type_name(obj)}")


def _enc_dict(obj, depth, budget):
    out = {}
    for k, v in obj.items():
        if type(k) in (int, float, bool) or (np is not None and isinstance(k, np.generic)):
            k = str(k.item() if hasattr(k, "item") else k)
        elif type(k) is not str:
            raise EncodeError(f"dictkey:{_type_name(k)}")
        out[k] = encode(v, depth + 1, budget)
    if any(k.startswith("$") for k in out):
        return {"$dict": [[k, v] for k, v in out.items()]}
    return out


def _enc_array(obj, depth, budget):
    """A numpy array (any subclass) as nested lists of Python numbers."""
    assert np is not None  # only numpy makes an array
    if obj.size > MAX_ELEMENTS:
        raise EncodeError("elements")
    kind = obj.dtype.kind
    if kind not in "biufcUSO":
        raise EncodeError(f"dtype:{str(obj.dtype)[:40]}")
    budget[0] -= int(obj.size)
    arr = np.asarray(obj)
    if kind == "f" and arr.dtype.itemsize > 8:  # longdouble: tolist() keeps longdoubles
        arr = arr.astype(np.float64)
    elif kind == "c" and arr.dtype.itemsize > 16:  # clongdouble
        arr = arr.astype(np.complex128)
    return encode(np.ndarray.tolist(arr), depth, budget)


def _enc_scalar(obj, depth, budget):
    """A numpy scalar: ``item()`` gives a Python number, except for longdouble and
    clongdouble (an item of those is the same numpy type again)."""
    assert np is not None  # only numpy makes a numpy scalar
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.integer):
        return _enc_int(int(obj))
    if isinstance(obj, np.floating):
        return _enc_float(float(obj))
    if isinstance(obj, np.complexfloating):
        z = complex(obj)
        return {"$complex": [_enc_float(z.real), _enc_float(z.imag)]}
    item = obj.item()
    if isinstance(item, np.generic):
        raise EncodeError(f"type:{_type_name(obj)}")
    return encode(item, depth, budget)


def decode(obj):
    """Python values for wire data sent by the grader (numpy arrays where marked)."""
    if type(obj) is list:
        return [decode(x) for x in obj]
    if type(obj) is dict:
        if len(obj) == 1:
            ((k, v),) = obj.items()
            if k == "$float":
                return float(v)
            if k == "$complex":
                return complex(decode(v[0]), decode(v[1]))
            if k == "$dict":
                return {kk: decode(vv) for kk, vv in v}
            if k == "$tuple":
                return tuple(decode(x) for x in v)
            if k == "$ndarray":
                data = decode(v["data"])
                if np is None:
                    return data
                return np.array(data, dtype=v["dtype"]).reshape(v["shape"])
        return {k: decode(v) for k, v in obj.items()}
    return obj


# ----------------------------------------------------------------------------- output capture
class CappedText(io.TextIOBase):
    """A text sink that keeps the first ``limit`` characters and counts the rest."""

    def __init__(self, limit):
        self.limit = limit
        self.parts = []
        self.kept = 0
        self.dropped = 0

    def writable(self):
        return True

    def write(self, s):
        if not isinstance(s, str):
            s = str(s)
        n = len(s)
        room = self.limit - self.kept
        if room > 0:
            piece = s[:room]
            self.parts.append(piece)
            self.kept += len(piece)
        self.dropped += max(0, n - max(room, 0))
        return n

    def flush(self):
        pass

    def isatty(self):
        return False

    def text(self):
        out = "".join(self.parts)
        if self.dropped:
            out += f"\n... [{self.dropped} more characters of output truncated]"
        return out


def _no_input(*args, **kwargs):
    raise RuntimeError(
        "input() is not available while grading: the notebook must not wait for typing; "
        "set the value in the code instead"
    )


# ----------------------------------------------------------------------------- IPython
SHELL = None  # IPython's InteractiveShell, made once in the zygote (None: IPython missing)
#: Characters of a failed shell command a note shows (the note, reason included, must fit
#: the grader's limit on a note, rikingrade.runner.MAX_NOTE).
MAX_SHOWN_COMMAND = 60
#: Shell commands that need the network (``!pip install``, ``%pip``, ``!wget`` ...).
NETWORK_WORDS = ("pip", "conda", "mamba", "wget", "curl", "git", "apt", "apt-get", "uv")


def _leading_empty_lines(lines):
    for i, line in enumerate(lines):
        if line and not line.isspace():
            return lines[i:]
    return lines


class _Screenless:
    """What ``GradingShell`` does instead of drawing: the matplotlib magic keeps the Agg
    backend, no GUI event loop, no traceback printed (the grader reports the exception),
    ``exit`` raises SystemExit as a stopping kernel would, and no output is kept for
    ``%history``."""

    def enable_gui(self, gui=None):
        pass

    def enable_matplotlib(self, gui=None):
        mpl = sys.modules.get("matplotlib")
        backend = mpl.get_backend() if mpl is not None else "agg"
        return (gui or "inline", backend)

    def ask_exit(self):  # ``exit`` / ``quit`` in a cell: the kernel would stop
        raise SystemExit(None)

    def showtraceback(self, *args, **kwargs):
        pass

    def showsyntaxerror(self, *args, **kwargs):
        pass

    def showindentationerror(self, *args, **kwargs):
        pass

    def _format_exception_for_storage(self, exception, *args, **kwargs):
        return {"ename": type(exception).__name__, "evalue": "", "traceback": []}

    @contextlib.contextmanager
    def _tee(self, channel):  # IPython 9 keeps every output in memory for %history
        yield


def _warm_cells(shell, compiler, sources):
    """Parse and compile, once in the zygote, cells that most notebooks share (the
    exercise's setup and checks): a child that runs one of them uses the code made here,
    as IPython would have compiled it (one code object per statement, the last expression
    in "single" mode), marked on each statement for ``compiler``'s class. Returns how many
    cells were added to ``shell._warm``."""
    import ast

    flag = getattr(ast, "PyCF_ALLOW_TOP_LEVEL_AWAIT", 0) if shell.autoawait else 0
    added = 0
    for raw in sources[:MAX_WARM]:
        text = shell._lines(raw) if isinstance(raw, str) else None
        if text is None or text in shell._warm or len(shell._warm) >= MAX_WARM:
            continue
        try:
            tree = compiler.ast_parse(text)
            nodes = tree.body
            if any(isinstance(n, ast.ImportFrom) and n.module == "__future__" for n in nodes):
                continue  # it would change how later cells compile
            with compiler.extra_flags(flag):
                for k, node in enumerate(nodes):
                    single = k == len(nodes) - 1 and isinstance(node, ast.Expr)
                    mode = "single" if single else "exec"
                    mod = ast.Interactive([node]) if single else ast.Module([node], [])
                    node._graded_code = (mode, compiler.flags, compiler(mod, "<c>", mode))
        except Exception:  # noqa: BLE001 - not plain Python after all: not kept
            continue
        shell._warm[text] = (text, tree)
        added += 1
    return added


def _run_command(shell, cmd):
    """A ``!`` line or ``%pip`` run as IPython runs it; a failure is noted on the
    shell's runner (and raised when ``system_raise_on_error`` is set)."""
    if cmd.rstrip().endswith("&"):
        raise OSError("Background processes not supported.")
    from IPython.utils.process import system

    expanded = shell.var_expand(cmd, depth=2)
    code = system(expanded)
    shell.user_ns["_exit_code"] = code
    if code and shell.runner is not None:
        shell.runner.note_command(expanded, code)
    if getattr(shell, "system_raise_on_error", False) and code != 0:
        from subprocess import CalledProcessError

        raise CalledProcessError(code, cmd)


def _shell_class():
    """``GradingShell``: IPython's own InteractiveShell, as a Jupyter kernel's, minus a screen.

    Cells run through ``run_cell`` (input transformers, line and cell magics, ``!``
    commands, top-level ``await``, the displayhook); what differs only concerns drawing
    and speed: the matplotlib magic keeps the Agg backend (no figure is shown), a
    traceback is not printed (the grader reports the exception), and a cell that is plain
    Python of several lines is parsed once instead of tokenized by the transformers, which
    leave such a cell as it is.
    """
    from IPython.core.compilerop import CachingCompiler
    from IPython.core.interactiveshell import InteractiveShell
    from traitlets import Type

    class WarmCompiler(CachingCompiler):
        """IPython's compiler, which returns a statement's code compiled in the zygote
        (``GradingShell.warm``) when it meets that statement again, under the cell's name."""

        def __call__(self, source, filename, symbol, **kwargs):
            body = getattr(source, "body", None)
            if type(body) is list and len(body) == 1 and not kwargs:
                done = getattr(body[0], "_graded_code", None)
                if done is not None and done[0] == symbol and done[1] == self.flags:
                    return _renamed(done[2], filename)
            return CachingCompiler.__call__(self, source, filename, symbol, **kwargs)

    class GradingShell(_Screenless, InteractiveShell):
        runner = None  # the Runner whose cell is running (its name, its notes)
        compiler_class = Type(WarmCompiler)
        #: cell text -> (text, AST with compiled statements), made in the zygote
        _warm: dict[str, tuple] = {}

        def _lines(self, raw_cell):
            """The cell as IPython runs it if it may be plain Python of several lines, not
            indented (the transformers leave such a cell as it is; a single line may be an
            automagic and goes through IPython), else None."""
            cell = raw_cell if raw_cell.endswith("\n") else raw_cell + "\n"
            lines = _leading_empty_lines(cell.splitlines(True))
            if len(lines) > 1 and not lines[0][:1].isspace() and not self.input_transformers_post:
                return "".join(lines)
            return None

        def transform_cell(self, raw_cell):
            text = self._lines(raw_cell)
            if text is not None:
                warm = self._warm.get(text) if not self.ast_transformers else None
                if warm is not None:  # parsed and compiled in the zygote
                    self._parsed = warm
                    return warm[0]
                try:
                    tree = self.compile.ast_parse(text)
                except Exception:
                    pass
                else:
                    self._parsed = (text, tree)
                    return text
            return InteractiveShell.transform_cell(self, raw_cell)

        def warm(self, sources):
            """Compile, in the zygote, cells most notebooks share (see ``_warm_cells``)."""
            return _warm_cells(self, WarmCompiler(), sources)

        def should_run_async(self, raw_cell, **kwargs):
            cell = kwargs.get("transformed_cell") or raw_cell
            if "await" not in cell and "async" not in cell:
                return False  # no top-level await without those words
            return InteractiveShell.should_run_async(self, raw_cell, **kwargs)

        def system_piped(self, cmd):
            """A ``!`` line or ``%pip``: run as IPython runs it, noting a failure."""
            return _run_command(self, cmd)

        system = system_piped

    return GradingShell


#: Cells the zygote compiles ahead for its children (see GradingShell.warm).
MAX_WARM = 64
_CodeType = type(_leading_empty_lines.__code__)


def _renamed(code, filename):
    """``code`` and the code objects in it, with ``filename`` as their file name."""
    consts = code.co_consts
    if any(type(c) is _CodeType for c in consts):
        consts = tuple(_renamed(c, filename) if type(c) is _CodeType else c for c in consts)
        return code.replace(co_filename=filename, co_consts=consts)
    return code.replace(co_filename=filename)


def make_shell(scratch, errors):
    """The shell every child inherits, made before forking (IPython's profile folder is
    made in ``scratch`` and removed again: nothing of the shell stays writable there)."""
    global SHELL
    ipdir = os.path.join(scratch, ".ipython-zygote")
    os.environ["IPYTHONDIR"] = ipdir
    try:
        from traitlets.config import Config

        cfg = Config()
        cfg.HistoryManager.enabled = False  # no SQLite history file
        cfg.InteractiveShell.autocall = 0
        shell = _shell_class().instance(config=cfg)
        shell.display_formatter.active_types = ["text/plain"]  # no figure is rendered
        parse = shell.compile.ast_parse

        def ast_parse(source, filename="<unknown>", symbol="exec"):
            done, shell._parsed = shell._parsed, None
            if done is not None and done[0] is source and symbol == "exec":
                return done[1]
            return parse(source, filename, symbol)

        shell._parsed = None
        shell._warm = {}
        shell.compile.ast_parse = ast_parse
        shell.compile.get_code_name = lambda raw, transformed, number: (
            shell.runner.cell_name if shell.runner is not None else f"<cell {number}>"
        )
        shell.run_cell("pass\npass\n", store_history=False)  # the first run's imports
        SHELL = shell
    except Exception as exc:  # noqa: BLE001 - cells then run as plain Python
        errors.append(f"IPython shell: {type(exc).__name__}: {exc}")
    finally:
        _remove(ipdir)
        os.environ.pop("IPYTHONDIR", None)


def _notebook_path():
    """``sys.path`` as a Jupyter kernel has it: '' (the working folder) before the first
    site-packages, and not the folder of this script."""
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path[:] = [p for p in sys.path if p and os.path.abspath(p) != here]
    for i, p in enumerate(sys.path):
        if os.path.basename(p) in ("site-packages", "dist-packages"):
            sys.path.insert(i, "")
            return
    sys.path.insert(0, "")


# ----------------------------------------------------------------------------- child process
_PRISTINE_BUILTINS = dict(builtins.__dict__)


class _CleanBuiltins:
    """Run the engine's own code with the builtins as they were before any student code.

    json's Python layer looks names up in ``builtins``; a notebook that replaced
    ``builtins.isinstance`` must not break (or steer) how its results are sent.
    """

    def __enter__(self):
        self.saved = dict(builtins.__dict__)
        builtins.__dict__.update(_PRISTINE_BUILTINS)

    def __exit__(self, *exc):
        builtins.__dict__.clear()
        builtins.__dict__.update(self.saved)
        return False


class Channel:
    """JSON lines over the child's socket."""

    def __init__(self, fd):
        self.fd = fd
        self.buf = bytearray()
        self.scanned = 0  # bytes of buf known to hold no newline
        self.fds = []  # file descriptors the grader sent (a worker's channel)
        self.sock: socket.socket | None = None
        try:  # a socket object, to receive them
            self.sock = socket.socket(fileno=os.dup(fd))
        except OSError:
            self.sock = None

    def _read(self):
        if self.sock is not None:
            data, fds, _flags, _addr = socket.recv_fds(self.sock, 1 << 20, 2)
            self.fds.extend(fds)
            return data
        return os.read(self.fd, 1 << 20)

    def close(self):
        if self.sock is not None:
            self.sock.close()
            self.sock = None

    def send(self, msg):
        with _CleanBuiltins():
            data = (_dumps(msg, allow_nan=False, separators=(",", ":")) + "\n").encode()
        view = memoryview(data)
        while view:
            n = _write(self.fd, view)
            view = view[n:]

    def recv(self):
        # a bytearray grows in place and each byte is scanned once: a 95 MiB cell arrives
        # in linear time (``bytes +=`` copied the whole buffer for every chunk)
        while True:
            nl = self.buf.find(b"\n", self.scanned)
            if nl >= 0:
                break
            self.scanned = len(self.buf)
            chunk = self._read()
            if not chunk:
                return None
            self.buf += chunk
        line = bytes(self.buf[:nl])
        del self.buf[: nl + 1]
        self.scanned = 0
        return _loads(line)


#: File names of the code a notebook's cells compile (its cells; IPython's %time, %timeit).
CELL_FILES = ("<cell", "<timed exec>", "<timed eval>", "<magic-timeit>")


def _short_error(exc, cell_name, roots=CELL_FILES):
    tb = traceback.TracebackException.from_exception(exc, limit=-8)
    frames = [f for f in tb.stack if f.filename.startswith(roots)]
    lines = []
    for f in frames[-4:]:
        where = f.filename.strip("<>")
        if not f.filename.startswith("<"):
            where = os.path.basename(f.filename)  # a module a cell wrote: its file name
        lines.append(
            f"  {where}, line {f.lineno}" + (f", in {f.name}" if f.name != "<module>" else "")
        )
        if f.line:
            lines.append(f"    {f.line.strip()}")
    msg = str(exc)
    if isinstance(exc, SyntaxError) and exc.lineno:
        msg = f"{exc.msg} (line {exc.lineno})"
    return {
        "type": type(exc).__name__,
        "message": msg[:MAX_ERROR_CHARS],
        "traceback": "\n".join(lines)[:MAX_ERROR_CHARS],
    }


def _bad_source(source):
    """A SyntaxError for a cell that is not valid Unicode (a lone surrogate), else None."""
    try:
        source.encode("utf-8")
        return None
    except UnicodeEncodeError as exc:
        line = source.count("\n", 0, exc.start) + 1
        bad = f"U+{ord(source[exc.start]):04X}" if exc.start < len(source) else "?"
        err = SyntaxError(
            f"the cell contains a character that is not valid Unicode ({bad}, a lone "
            f"surrogate) at line {line}: retype that line"
        )
        err.lineno = None
        return err


def _fresh_imports(roots):
    """Forget what the import system cached about the folders a notebook can write to
    (``roots``), so a module a cell has just written (``%%writefile helper.py``,
    ``open(...)``) is found by the next import even when the folder changed within its
    timestamp's resolution. The library folders' caches stay: relisting them costs ms."""
    for path, finder in list(sys.path_importer_cache.items()):
        if isinstance(path, str) and path.startswith(roots) and finder is not None:
            invalidate = getattr(finder, "invalidate_caches", None)  # optional for a finder
            try:
                if invalidate is not None:
                    invalidate()
            except Exception:
                pass


def _class_path(cls):
    """An exception class and its bases as "module.Name" (a notebook's own: "__main__.X")."""
    try:
        return [f"{c.__module__}.{c.__qualname__}"[:200] for c in cls.__mro__[:20]]
    except Exception:
        return []


def _close_figures():
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        try:
            plt.close("all")
        except Exception:
            pass


# ----------------------------------------------------------------------------- time limits
TICK = 0.02  # seconds between two looks at what a student's call is running
MAX_FRAMES = 2000  # frames looked at per look (a deeper recursion is cut)
MAX_NAMES = 50  # function names reported per call
_FunctionType = type(lambda: None)
_setitimer = signal.setitimer
_ITIMER_REAL = signal.ITIMER_REAL
_SIGALRM = signal.SIGALRM


_os_open, _os_pread, _os_close, _O_RDONLY = os.open, os.pread, os.close, os.O_RDONLY
_schedstat = [0, -1]  # [pid, fd] of this process's /proc/thread-self/schedstat
_waited = [0.0, 0.0]  # [seconds waited for a processor, monotonic time], as last read


def _read_waited():
    """Seconds this thread has waited for a processor (Linux schedstat), or None."""
    pid = _getpid()
    for attempt in (0, 1):
        if _schedstat[0] != pid or _schedstat[1] < 0 or attempt:
            try:  # opened once per process: a forked child has a thread of its own
                fd = _os_open("/proc/thread-self/schedstat", _O_RDONLY)
            except OSError:
                return None
            _schedstat[:] = [pid, fd]
        try:
            return int(_os_pread(_schedstat[1], 128, 0).split()[1]) / 1e9
        except (OSError, ValueError, IndexError):
            _schedstat[1] = -1  # closed or replaced by the notebook: open it again
    return None


def busy_clock():
    """Seconds, like ``time.monotonic``, minus the time this thread spent waiting for a
    processor (Linux's /proc/thread-self/schedstat): wall-clock time as on an idle
    machine. Running and sleeping count; being ready to run while the machine is busy
    with other work (the grader's other workers, other users) does not. Where the file
    cannot be read this is the wall clock; it never runs backwards or jumps (a wait
    longer than the time since the last reading is not believed).
    """
    now = _monotonic()
    waited = _read_waited()
    last, then = _waited
    if waited is not None and last <= waited <= last + (now - then) + 0.01:
        _waited[0] = waited
    elif waited is not None and waited < last:  # another process's count: start afresh
        _waited[0] = waited
    _waited[1] = now
    return now - _waited[0]


class CallTimedOut(BaseException):
    """Raised in a student's function that ran past its time limit.

    Not an Exception, so ``except Exception`` in the notebook does not swallow it.
    """


class Watch:
    """Time limits per function, enforced inside the child by looking at its stack.

    While a student's call (or a cell) runs, SIGALRM fires every TICK and the handler walks
    the main thread's frames; the frames of the notebook's functions are remembered with
    the time each was first seen. The handler raises CallTimedOut in the student's code:

    * in a call, when the call has run ``limit`` seconds;
    * anywhere, when a function with a short limit (``leash``: the grader gives one to a
      function that already ran out of time) has been running that long;
    * in a cell, when an answer function has been running ``limit`` seconds.

    It records which functions were on the stack then (outermost first: none of them
    returned in time) and, for each function seen running that then finished, how long it
    was seen (a lower bound of its time, from which the grader derives short limits). It
    raises again at every tick while the notebook's code runs until the call ends, so a
    notebook that swallows it only reaches the grader's own wall-clock limit, which stays
    behind this one. Seconds are :func:`busy_clock`'s: time spent waiting for a processor
    on a busy machine is not counted, so a call's fate does not depend on the load.
    """

    def __init__(self):
        self.running = False
        self.fired = None
        self.seen = {}
        self.finished = {}

    def start(self, ns, limit, leash, answers=(), call="", roots=CELL_FILES):
        """Watch the code about to run; ``call``: the function called (a call), else a cell.

        ``roots``: how the file names of the notebook's own code start.
        """
        self.ns = ns
        self.roots = roots
        #: code object -> the notebook's name for it (made when needed)
        self.names: dict[object, str] | None = None
        self.limit = limit
        self.leash = leash
        self.answers = answers
        self.call = call
        self.fired = None
        self.seen = {}
        self.finished = {}
        self.t0 = busy_clock()
        try:
            self.previous = signal.signal(_SIGALRM, self._tick)
            signal.siginterrupt(_SIGALRM, False)  # C-level system calls resume (SA_RESTART)
            _setitimer(_ITIMER_REAL, TICK, TICK)
        except (OSError, ValueError):
            self.previous = None
        self.running = True

    def stop(self):
        """Stop watching; the functions seen finishing, with their seen seconds."""
        self.running = False
        try:
            _setitimer(_ITIMER_REAL, 0, 0)
            if self.previous is not None:
                signal.signal(_SIGALRM, self.previous)
        except (OSError, ValueError, TypeError):
            pass
        for name, first, last in self.seen.values():
            self._finish(name, last - first)
        self.seen = {}
        return self.finished

    def _finish(self, name, seconds):
        if name in self.finished or len(self.finished) < MAX_NAMES:
            self.finished[name] = max(self.finished.get(name, 0.0), round(seconds, 4))

    def _name(self, code):
        names = self.names
        if names is None:
            names = {}
            for k, v in list(self.ns.items()):
                if type(k) is str and type(v) is _FunctionType:
                    names.setdefault(v.__code__, k)
                    inner = v.__dict__.get("__wrapped__")  # functools.wraps: the real body
                    if inner is not None and type(inner) is _FunctionType:
                        names.setdefault(inner.__code__, k)
            self.names = names
        return names.get(code) or code.co_name

    def _tick(self, signum, frame):
        if not self.running:
            return
        now = busy_clock()
        roots = self.roots
        stack = []  # the notebook's function frames, innermost first
        mine = False  # the notebook's code (a function or a cell's own lines) is running
        f, k = frame, 0
        while f is not None and k < MAX_FRAMES:
            code = f.f_code
            if code.co_filename.startswith(roots):
                mine = True
                if not code.co_name.startswith("<"):
                    stack.append(f)
            f, k = f.f_back, k + 1
        if self.fired is not None:
            if mine:  # it swallowed the stop: again (IPython's own code is left alone)
                raise CallTimedOut(self.fired["message"])
            return
        live = set(stack)
        for fr in [fr for fr in self.seen if fr not in live]:
            name, first, last = self.seen.pop(fr)
            self._finish(name, last - first)
        over = None
        if self.call and now - self.t0 >= self.limit:
            over = (self.call, self.limit)
        names: list[str] = []
        for fr in reversed(stack):  # outermost first
            rec = self.seen.get(fr)
            if rec is None:
                rec = self.seen[fr] = [self._name(fr.f_code), now, now]
            rec[2] = now
            if not names or names[-1] != rec[0]:
                names.append(rec[0])
            limit = self.leash.get(rec[0])
            if limit is None and not self.call and rec[0] in self.answers:
                limit = self.limit
            if over is None and limit is not None and now - rec[1] >= limit:
                over = (rec[0], limit)
        if over is None:
            return
        name, limit = over
        if self.call and self.call not in names:
            names.insert(0, self.call)
        self.fired = {
            "stack": [n[:200] for n in names[:MAX_NAMES]],
            "function": name[:200],
            "limit": limit,
            "message": f"{name[:200]} did not return within {limit:.3g} s "
            "(the time limit of a call while grading)",
        }
        raise CallTimedOut(self.fired["message"])


class Runner:
    def __init__(self, chan, mypid):
        self.chan = chan
        self.mypid = mypid
        self.shell = SHELL
        if SHELL is not None:
            self.ns = SHELL.user_ns
            SHELL.runner = self
        else:  # IPython could not be loaded (the zygote said so): plain Python
            self.ns = {"__name__": "__main__", "__builtins__": builtins}
        self.cell_name = "<cell>"
        self.notes = []
        self.output_limit = 10_000
        self.output_left = 100_000  # characters of output this submission may still send
        self.watch = Watch()
        self.limit = None  # seconds per call of an answer function (from the grader)
        self.leash = {}  # function name -> its short limit (seconds), from the grader
        self._want = ()
        # where the notebook's own code comes from: its cells, what IPython's %time and
        # %timeit compile, and the files it writes (a helper module written by a cell)
        self.roots = (*CELL_FILES, os.path.dirname(os.getcwd()) + os.sep)

    def _guard_fork(self):
        # A process the student forked must never answer for the child.
        if _getpid() != self.mypid:
            _exit(0)

    def _captured(self, func, limit=None):
        cap = CappedText(self.output_limit if limit is None else limit)
        old = sys.stdout, sys.stderr
        sys.stdout = sys.stderr = cap
        try:
            return func(), None, cap
        except BaseException as exc:  # noqa: BLE001 - student code may raise anything
            return None, exc, cap
        finally:
            self._guard_fork()
            sys.stdout, sys.stderr = old
            builtins.input = _no_input

    def note_command(self, cmd, code):
        """A ``!`` command (or ``%pip``) of the running cell exited with status ``code``."""
        words = str(cmd).split()
        first = os.path.basename(words[0]) if words else ""
        if first.startswith("python") and words[1:3] == ["-m", "pip"]:
            first = "pip"
            if words[0].strip("'\"") == sys.executable:  # what %pip runs: shown as written
                words = ["%pip", *words[3:]]
        shown = " ".join(words)
        if len(shown) > MAX_SHOWN_COMMAND:
            shown = shown[: MAX_SHOWN_COMMAND - 3] + "..."
        why = (
            ": grading runs offline, so nothing can be downloaded or installed (the grader "
            "has numpy, sympy, matplotlib and rikin)"
            if first in NETWORK_WORDS
            else ""
        )
        if len(self.notes) < 10:
            self.notes.append(f'the shell command "{shown}" exited with status {code}{why}')

    def run_cells(self, cells, want=()):
        self._want = want
        for index, source in cells:
            self.chan.send({"event": "cell_start", "cell": index})
            self.cell_name = f"<cell {index}>"
            self.notes = []
            _fresh_imports(self.roots[-1:])
            run = self._cell(source)
            t0 = _monotonic()
            _, exc, cap = self._captured(run, min(self.output_limit, self.output_left))
            with _CleanBuiltins():
                fired = self.watch.fired if isinstance(exc, CallTimedOut) else None
                self.watch.fired = None
                self._after_cell(index, exc, cap, _monotonic() - t0, fired)
            self.output_left = max(0, self.output_left - cap.kept)
        with _CleanBuiltins():
            self._done(want)

    def _cell(self, source):
        """A function that runs the cell and raises what it raised (IPython keeps it)."""
        bad = _bad_source(source)
        watch, want = self.watch, self._want

        def run():
            if bad is not None:
                raise bad
            watching = self.limit is not None or bool(self.leash)
            if watching:
                watch.start(self.ns, self.limit, self.leash, want, roots=self.roots)
            try:
                if self.shell is None:
                    exec(compile(source, self.cell_name, "exec"), self.ns)
                    return
                result = self.shell.run_cell(source, store_history=True)
            finally:
                if watching:
                    watch.stop()
            exc = result.error_before_exec or result.error_in_exec
            if exc is not None:
                raise exc

        return run

    def _after_cell(self, index, exc, cap, seconds, fired=None):
        name = f"<cell {index}>"
        _close_figures()
        err = None
        if exc is not None:
            try:
                err = _short_error(exc, name, self.roots)
            except Exception:
                err = {"type": type(exc).__name__, "message": "", "traceback": ""}
            if isinstance(exc, SystemExit):
                err["message"] = f"sys.exit({exc.code!r}) was called"
        self.chan.send(
            {
                "event": "cell_end",
                "cell": index,
                "error": err,
                "output": cap.text()[: self.output_limit + 200],
                "notes": [str(n) for n in self.notes[:10]],
                "seconds": round(seconds, 4),
                "timed_out": fired,
            }
        )

    def _done(self, want=()):
        """Tell which functions exist: the ones the tests want first, then up to 500 more.

        However many callables a notebook makes, the answer functions are always named.
        """
        ns = self.ns
        found = [w for w in want if isinstance(w, str) and callable(ns.get(w))]
        hidden = getattr(self.shell, "user_ns_hidden", {})
        others: list[str] = []
        for k, v in list(ns.items()):
            if len(others) >= 500:
                break
            if (
                isinstance(k, str)
                and k not in found
                and callable(v)
                and not isinstance(v, type(sys))
                and not k.startswith("__")
                and not (k in hidden and hidden[k] is v)  # IPython's exit, open, get_ipython
                and k != "get_ipython"
            ):
                others.append(k[:200])
        self.chan.send({"event": "exec_done", "functions": found + sorted(others)})

    def call(self, msg):
        cid = msg.get("id")
        name = msg.get("function")
        fn = self.ns.get(name)
        if not callable(fn):
            self.chan.send(
                {
                    "id": cid,
                    "error_type": "NameError",
                    "error_message": f"function {name} not found",
                }
            )
            return
        try:
            with _CleanBuiltins():
                args = decode(msg.get("args") or [])
                kwargs = decode(msg.get("kwargs") or {})
        except Exception as bad:
            self.chan.send(
                {
                    "id": cid,
                    "error_type": "GraderError",
                    "error_message": f"could not decode the test input: {bad}",
                }
            )
            return
        watch = self.watch
        limit = self.leash.get(name, self.limit)

        def run():
            if limit is None:
                return fn(*args, **kwargs)
            watch.start(self.ns, limit, self.leash, call=name, roots=self.roots)
            try:
                return fn(*args, **kwargs)
            finally:
                watch.stop()

        t0 = busy_clock()
        value, exc, _ = self._captured(run)
        took = round(max(0.0, busy_clock() - t0), 4)  # the call's time, as the limit counts it
        _close_figures()
        if watch.fired is not None:  # raised in its code, swallowed or not: it ran out
            with _CleanBuiltins():
                fired = {k: v for k, v in watch.fired.items() if k != "message"}
                self.chan.send({"id": cid, "timed_out": fired})
            watch.fired = None
            return
        seen = {k: v for k, v in watch.finished.items() if k != name}
        watch.finished = {}
        self._answer(cid, value, exc, took, seen)

    def _answer(self, cid, value, exc, took, seen):
        """Send a returned call's answer: the exception it raised, or its value on the wire
        (UnreadableResult when the value cannot be encoded). ``seen``: how long the
        functions it called were seen running."""
        if exc is not None:
            msg = str(exc)
            if isinstance(exc, SystemExit):
                msg = f"sys.exit({exc.code!r}) was called"
            reply = {
                "id": cid,
                "error_type": type(exc).__name__,
                "error_message": msg[:MAX_ERROR_CHARS],
                "error_bases": _class_path(type(exc)),
                "seconds": took,
            }
            if seen:
                reply["seen"] = seen
            self.chan.send(reply)
            return
        try:
            with _CleanBuiltins():
                wire = encode(value)
            reply = {"id": cid, "value": wire, "seconds": took}
            if seen:
                reply["seen"] = seen
            self.chan.send(reply)
        except (RecursionError, EncodeError) as unread:
            why = str(unread) if isinstance(unread, EncodeError) else "depth"
            self.chan.send(
                {
                    "id": cid,
                    "error_type": UNREADABLE,
                    "error_message": why[:200],
                    "error_bases": UNREADABLE_BASES,
                }
            )

    def serve(self):
        while True:
            with _CleanBuiltins():
                msg = self.chan.recv()
            if msg is None or msg.get("op") == "bye":
                _exit(0)
            op = msg.get("op")
            if op in ("exec", "calls"):
                with _CleanBuiltins():
                    self._limits(msg)
            if op == "exec":
                with _CleanBuiltins():
                    _write_files(msg.get("files"))
                self.output_limit = int(msg.get("output_limit", self.output_limit))
                self.output_left = int(msg.get("output_total", self.output_left))
                self.run_cells(msg["cells"], msg.get("want") or ())
            elif op == "call":
                self.call(msg)
            elif op == "calls":  # a batch: each answer is sent as soon as it is ready
                calls = msg.get("calls")
                for one in calls if isinstance(calls, list) else []:
                    if isinstance(one, dict):
                        self.call(one)
            elif op == "fork":
                self.fork_worker()

    def _limits(self, msg):
        """The time limits the grader sent: per call, and short ones per function."""
        limit = msg.get("limit")
        self.limit = float(limit) if isinstance(limit, (int, float)) and limit > 0 else None
        leash = msg.get("leash")
        self.leash = {
            k: float(v)
            for k, v in (leash.items() if isinstance(leash, dict) else ())
            if isinstance(k, str) and isinstance(v, (int, float)) and v > 0
        }

    def fork_worker(self):
        """Fork a worker that serves calls on the socket the grader sent, from this state.

        This process (the cells already run) stays as the template: a worker that hangs
        or dies is replaced by another fork, not by running every cell again. The worker
        is forked twice, so it is the zygote's (the PID namespace's init) to reap.
        """
        fds, self.chan.fds = self.chan.fds, []
        for extra in fds[1:]:
            os.close(extra)
        if not fds:
            self.chan.send({"event": "forked", "ok": False, "error": "no socket received"})
            return
        fd = fds[0]
        try:
            pid = os.fork()
        except OSError as exc:
            os.close(fd)
            self.chan.send({"event": "forked", "ok": False, "error": str(exc)})
            return
        if pid == 0:
            try:
                if os.fork() != 0:
                    _exit(0)
            except OSError:
                _exit(71)
            os.dup2(fd, 3)
            os.close(fd)
            self.chan.close()
            self.chan = Channel(3)
            self.mypid = _getpid()
            self.chan.send({"event": "worker", "pid": self.mypid})
            return
        os.close(fd)
        try:
            os.waitpid(pid, 0)
        except OSError:
            pass
        self.chan.send({"event": "forked", "ok": True})


def _write_files(files):
    """The student's own files (``[name, base64]``: what they handed in beside the
    notebook) into the working folder, before the first cell runs, as a kernel started in
    the notebook's folder finds them. Names are relative (the grader checked them); an
    entry already there (a link the student cannot have made yet) is not replaced."""
    import base64

    for item in files if isinstance(files, list) else ():
        try:
            name, data = item
            parts = name.split("/")
            if name.startswith("/") or any(p in ("", ".", "..") for p in parts):
                continue
            if len(parts) > 1:
                os.makedirs(os.path.join(*parts[:-1]), exist_ok=True)
            fd = os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
            with os.fdopen(fd, "wb") as f:
                f.write(base64.b64decode(data))
        except (OSError, ValueError, TypeError, AttributeError):
            continue


def set_limits(limits):
    """Resource limits of one child, set before any student code runs."""

    def lim(which, value):
        if value is None:
            return
        value = int(value)
        try:
            resource.setrlimit(which, (value, value))
        except (ValueError, OSError):
            soft, hard = resource.getrlimit(which)
            if hard == resource.RLIM_INFINITY or value <= hard:
                resource.setrlimit(which, (value, hard))

    lim(resource.RLIMIT_CORE, 0)
    nproc = limits.get("max_processes")
    if limits.get("memory_mb") is not None:
        per_process = _vm_size() + int(limits["memory_mb"]) * MIB
        lim(resource.RLIMIT_AS, per_process)
        share = limits.get("share_mb")
        if share is not None and nproc is not None:  # no memory cgroup: bound the product
            nproc = max(1, min(int(nproc), int(share) * MIB // per_process))
    lim(resource.RLIMIT_CPU, limits.get("cpu_seconds"))
    lim(resource.RLIMIT_NPROC, nproc)
    if limits.get("max_file_mb") is not None:
        lim(resource.RLIMIT_FSIZE, int(limits["max_file_mb"]) * MIB)
    lim(resource.RLIMIT_NOFILE, limits.get("max_open_files"))


def _vm_size():
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 512 * MIB


def child_main(chan_fd, ctl_fd, limits, workdir):
    try:
        os.close(ctl_fd)
        os.setsid()
        try:  # die with the zygote (PR_SET_PDEATHSIG = 1)
            import ctypes

            ctypes.CDLL(None).prctl(1, signal.SIGKILL, 0, 0, 0)
        except Exception:
            pass
        try:  # under a memory cgroup the kernel's OOM killer picks a child, not the zygote
            with open("/proc/self/oom_score_adj", "w") as f:
                f.write("1000")
        except OSError:
            pass
        devnull = os.open(os.devnull, os.O_RDWR)
        for fd in (0, 1, 2):
            os.dup2(devnull, fd)
        if chan_fd != 3:
            os.dup2(chan_fd, 3)
            chan_fd = 3
        os.closerange(4, 65536)
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        os.makedirs(workdir, exist_ok=True)
        os.chdir(workdir)
        os.environ["HOME"] = workdir
        os.environ["TMPDIR"] = workdir
        # as in a kernel: ``!python``, ``!pip`` are the kernel's own; pip fails at once
        # offline instead of retrying
        bindir = os.path.dirname(sys.executable)
        os.environ["PATH"] = bindir + os.pathsep + os.environ.get("PATH", "/usr/bin:/bin")
        os.environ.update({"PIP_RETRIES": "0", "PIP_DISABLE_PIP_VERSION_CHECK": "1"})
        os.environ["PIP_NO_INPUT"] = "1"
        _notebook_path()
        if SHELL is not None and isinstance(SHELL.user_ns.get("_dh"), list):
            SHELL.user_ns["_dh"][:] = [workdir]  # %cd's history starts here
        set_limits(limits)
        builtins.input = _no_input
        sys.stdin = io.StringIO("")
        sys.argv = ["notebook"]
        runner = Runner(Channel(chan_fd), _getpid())
        runner.serve()
    except BaseException:  # noqa: BLE001
        pass
    _exit(70)


# ----------------------------------------------------------------------------- zygote
def preload(modules, scratch):
    """Import what every notebook needs once and make IPython's shell, before forking;
    returns failures."""
    global np
    errors = []
    os.environ.setdefault("MPLBACKEND", "Agg")
    for name in modules:
        try:
            __import__(name)
        except Exception as exc:  # a missing optional library is reported, not fatal
            errors.append(f"{name}: {type(exc).__name__}: {exc}")
    np = sys.modules.get("numpy")
    mpl = sys.modules.get("matplotlib")
    if mpl is not None:
        try:
            mpl.use("Agg")
            import matplotlib.pyplot  # noqa: F401
        except Exception as exc:
            errors.append(f"matplotlib.pyplot: {exc}")
    make_shell(scratch, errors)
    _warm_up(errors)
    return errors


def _warm_up(errors):
    """Exercise the lazy first-use paths once, so each forked child starts warm."""
    try:
        if SHELL is not None:
            SHELL.transform_cell("%matplotlib inline\nx = 1\n")
            SHELL.transform_cell("x = 1\ny = [x]\n")
            SHELL._parsed = None
        if np is not None:
            np.linalg.solve(np.eye(3), np.ones(3))
            np.testing.assert_allclose(np.ones(2), np.ones(2))
        plt = sys.modules.get("matplotlib.pyplot")
        if plt is not None:
            fig, ax = plt.subplots()
            ax.plot([0.0, 1.0], [0.0, 1.0], "o-", label="warm")
            ax.set_title("warm")
            ax.legend()
            fig.canvas.draw()
            fig = plt.figure()
            ax3 = fig.add_subplot(projection="3d")  # arm drawings are often 3D
            ax3.plot([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], "o-")
            ax3.set_xlabel("x")
            fig.canvas.draw()
            plt.close("all")
        sympy = sys.modules.get("sympy")
        if sympy is not None:
            q = sympy.symbols("q1 q2")
            sympy.simplify(sympy.cos(q[0]) ** 2 + sympy.sin(q[0]) ** 2)
            sympy.Matrix(
                [[sympy.cos(q[1]), -sympy.sin(q[1])], [sympy.sin(q[1]), sympy.cos(q[1])]]
            ) * 2
        rikin = sys.modules.get("rikin")
        if rikin is not None and np is not None:
            rikin.robots.planar_2r(1.0, 1.0).fk(np.zeros(2))
    except Exception as exc:  # warming is an optimisation only
        errors.append(f"warm-up: {type(exc).__name__}: {exc}")


def _kill_hard(pid):
    """SIGKILL a child and its process group (either may already be gone)."""
    for kill in (os.killpg, os.kill):
        try:
            kill(pid, signal.SIGKILL)
        except OSError:
            pass


def describe_status(status):
    """Words for a wait status, as the feedback shows them."""
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
        why = {
            "SIGKILL": "killed (SIGKILL)",
            "SIGXCPU": "stopped at the CPU time limit (SIGXCPU)",
            "SIGXFSZ": "stopped at the file size limit (SIGXFSZ)",
            "SIGSEGV": "crashed (segmentation fault)",
            "SIGABRT": "aborted (SIGABRT)",
        }.get(name, f"killed by signal {name}")
        return why
    if os.WIFEXITED(status):
        code = os.WEXITSTATUS(status)
        return f"the process exited with code {code} (os._exit or a fatal error)"
    return f"ended with wait status {status}"


def _chmod(path, mode):
    try:
        os.chmod(path, mode)
    except OSError:
        pass


def _remove(path):
    """Remove a file or a whole tree, making each folder writable on the way down."""
    if os.path.isdir(path) and not os.path.islink(path):
        _chmod(path, 0o700)
        for root, dirs, _files in os.walk(path):
            for d in dirs:
                p = os.path.join(root, d)
                if not os.path.islink(p):
                    _chmod(p, 0o700)
        shutil.rmtree(path, ignore_errors=True)
    else:
        try:
            os.unlink(path)
        except OSError:
            pass


class Zygote:
    def __init__(self, ctl, scratch, in_pidns, by_uid=False):
        self.ctl = ctl
        self.scratch = scratch
        self.in_pidns = in_pidns
        # uid mode (no namespaces): every process of this uid is ours, so kill(-1) as it
        # ends them all, daemons included (it spares the caller)
        self.by_uid = by_uid
        self.children = {}
        self.statuses = {}
        self.counter = 0
        self.pristine = None  # /scratch as it was before the first submission

    def send(self, msg):
        self.ctl.send(_dumps(msg).encode())

    def reap(self):
        while True:
            try:
                pid, status = os.waitpid(-1, os.WNOHANG)
            except ChildProcessError:
                return
            if pid == 0:
                return
            self.statuses[pid] = status

    def kill_all(self):
        """Kill every process but this one (and the namespace's init)."""
        if self.in_pidns or self.by_uid:
            # Everything else in the namespace descends from us (we are its init), so keep
            # killing and reaping until /proc lists nobody else, zombies included.
            deadline = _monotonic() + 3.0
            while True:
                try:
                    os.kill(-1, signal.SIGKILL)
                except OSError:
                    pass
                self.reap()
                if not self._others_exist() or _monotonic() > deadline:
                    break
                _sleep(0.0005)
        else:
            for pid in list(self.children):
                _kill_hard(pid)
        for pid in list(self.children):
            try:
                _, status = os.waitpid(pid, 0)
                self.statuses[pid] = status
            except ChildProcessError:
                pass
        self.children.clear()
        self.reap()

    def kill_except(self, keep):
        """Kill every process but this one and ``keep`` (a template); True if it lives."""
        if not (self.in_pidns or self.by_uid) or keep not in self.children:
            self.kill_all()
            self.wipe_scratch()
            return False
        me = os.getpid()
        deadline = _monotonic() + 3.0
        while _monotonic() < deadline:
            try:
                pids = [int(p) for p in os.listdir("/proc") if p.isdigit()]
            except OSError:
                break
            victims = [p for p in pids if p not in (1, me, keep)]
            if not self.in_pidns:  # uid mode: the live processes of this uid are ours
                victims = [p for p in victims if self._live_ours(p)]
            for sig in (signal.SIGSTOP, signal.SIGKILL):  # stopped, nothing forks again
                for p in victims:
                    try:
                        os.kill(p, sig)
                    except OSError:
                        pass
            self.reap()
            if not victims:
                break
            _sleep(0.0005)
        if keep in self.statuses:  # the template itself ended
            self.children.pop(keep, None)
            return False
        return True

    def _live_ours(self, pid):
        """``pid`` is a live (not zombie) process of this uid."""
        try:
            with open(f"/proc/{pid}/stat") as f:
                if f.read().rsplit(")", 1)[1].split()[0] == "Z":
                    return False
            with open(f"/proc/{pid}/status") as f:
                for line in f:
                    if line.startswith("Uid:"):
                        return line.split()[1] == str(os.getuid())
        except (OSError, IndexError):
            pass
        return False

    def _others_exist(self):
        me = os.getpid()
        try:
            pids = [int(p) for p in os.listdir("/proc") if p.isdigit() and int(p) not in (1, me)]
        except OSError:
            return False
        if not self.by_uid:
            return bool(pids)
        uid = str(os.getuid())
        for pid in pids:
            try:
                with open(f"/proc/{pid}/status") as f:
                    for line in f:
                        if line.startswith("Uid:"):
                            if line.split()[1] == uid:
                                return True
                            break
            except OSError:
                continue
        return False

    def _scratch_state(self):
        """What /scratch holds before any student runs: its mode and the grader's files."""
        keep = {}
        for name in SCRATCH_KEEP:
            try:
                keep[name] = set(os.listdir(os.path.join(self.scratch, name)))
            except OSError:
                keep[name] = set()
        try:
            mode = os.stat(self.scratch).st_mode & 0o7777
        except OSError:
            mode = 0o755
        return mode, keep

    def wipe_scratch(self):
        """Leave /scratch as the first submission found it: empty but for the grader's files.

        Folders a student made read-only (chmod 500, 000) are opened up first: their owner
        is this uid, so it may; nothing a student wrote survives, in .mpl either.
        """
        if self.pristine is None:
            self.pristine = self._scratch_state()
        mode, keep = self.pristine
        _chmod(self.scratch, mode | 0o700)
        try:
            entries = os.listdir(self.scratch)
        except OSError:
            return
        for name in entries:
            path = os.path.join(self.scratch, name)
            if name in keep and os.path.isdir(path) and not os.path.islink(path):
                _chmod(path, 0o755)
                try:
                    inner = os.listdir(path)
                except OSError:
                    inner = []
                for sub in inner:
                    if sub not in keep[name]:
                        _remove(os.path.join(path, sub))
                continue
            _remove(path)
        _chmod(self.scratch, mode)

    def wait(self, pid, timeout):
        """The wait status of ``pid`` (killing it if it has not ended within ``timeout``)."""
        import time

        end = time.monotonic() + timeout
        while True:
            if pid in self.statuses:
                break
            try:
                got, status = os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:
                break
            if got:
                self.statuses[pid] = status
                break
            if time.monotonic() > end:
                _kill_hard(pid)
                end = time.monotonic() + 5
            time.sleep(0.005)
        self.children.pop(pid, None)
        status = self.statuses.pop(pid, None)
        return None if status is None else describe_status(status)

    def fork(self, msg, fds):
        self.kill_all()
        self.wipe_scratch()
        if not fds:
            self.send({"ok": False, "error": "no channel received"})
            return
        chan_fd = fds[0]
        for extra in fds[1:]:
            os.close(extra)
        self.counter += 1
        workdir = os.path.join(self.scratch, f"work-{self.counter}")
        pid = os.fork()
        if pid == 0:
            child_main(chan_fd, self.ctl.fileno(), msg.get("limits", {}), workdir)
            _exit(70)
        os.close(chan_fd)
        self.children[pid] = True
        self.send({"ok": True, "pid": pid})

    def serve(self):
        while True:
            try:
                data, fds, _flags, _addr = socket.recv_fds(self.ctl, 65536, 4)
            except InterruptedError:
                continue
            if not data:
                return
            msg = _loads(data)
            op = msg.get("op")
            if op == "fork":
                self.fork(msg, fds)
            elif op == "kill":
                self.kill_all()
                self.wipe_scratch()
                self.send({"ok": True})
            elif op == "warm":  # cells most notebooks share: compiled once, here
                cells = msg.get("cells")
                added = SHELL.warm(cells) if SHELL is not None and isinstance(cells, list) else 0
                __import__("gc").freeze()
                self.send({"ok": True, "added": added})
            elif op == "kill_except":
                self.send({"ok": True, "kept": self.kill_except(int(msg.get("keep", -1)))})
            elif op == "wait":
                self.send(
                    {
                        "ok": True,
                        "status": self.wait(int(msg["pid"]), float(msg.get("timeout", 1.0))),
                    }
                )
            elif op == "quit":
                self.kill_all()
                return
            else:
                self.send({"ok": False, "error": f"unknown op {op!r}"})


def main(argv):
    config = _loads(argv[1])
    # As the PID namespace's init, the zygote receives only signals it handles: handle none.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    ctl = socket.socket(fileno=int(config["ctl_fd"]))
    os.environ.update({k: str(v) for k, v in config.get("env", {}).items()})
    scratch = config.get("scratch", "/scratch")
    errors = preload(config.get("preload", []), scratch)
    import gc

    gc.collect()
    gc.freeze()  # what the zygote made is shared, never collected again in a child
    try:  # nobody may ptrace or read this process's memory, not even a student child
        import ctypes

        ctypes.CDLL(None).prctl(4, 0, 0, 0, 0)  # PR_SET_DUMPABLE = 4
    except Exception:
        pass
    in_pidns = bool(config.get("pidns")) and os.getpid() <= 3
    by_uid = config.get("reap") == "uid"
    if by_uid:  # orphans (daemonised grandchildren) become our children: we reap them
        try:
            import ctypes

            ctypes.CDLL(None).prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER
        except Exception:
            pass
    zygote = Zygote(ctl, scratch, in_pidns, by_uid)
    zygote.pristine = zygote._scratch_state()
    zygote.send(
        {
            "ready": True,
            "protocol": PROTOCOL,
            "pid": os.getpid(),
            "preload_errors": errors,
            "python": sys.version.split()[0],
        }
    )
    zygote.serve()


if __name__ == "__main__":
    main(sys.argv)
