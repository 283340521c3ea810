"""Hostile and broken submissions made from the fake exercise's solution notebook.

Each :class:`Case` builds the bytes of one submission and states the exact score (out of
5) and status it must get. ``write_corpus(folder)`` writes them all as ``<name>.ipynb``.
Used by ``tests/test_grader_corpus.py`` and by ``benchmarks/bench_grade.py``.

Scores are derived from the fake exercise (``fake2r.py``): add_int 1, add_float 1,
fk_2r 2 (four calls, the first with q2 = 0), fk_2r_batch 1.
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOLUTION = HERE / "fake2r_solution.ipynb"
ASSIGNMENT = HERE / "fake2r.py"
MAX = 5.0


def solution() -> dict:
    return json.loads(SOLUTION.read_text())


def _dump(nb: dict) -> bytes:
    return json.dumps(nb, indent=1).encode()


def _code(src: str, cid: str | None = None) -> dict:
    cell = {
        "cell_type": "code",
        "execution_count": None,
        "metadata": {},
        "outputs": [],
        "source": src,
    }
    if cid is not None:
        cell["id"] = cid
    return cell


def _find(nb: dict, needle: str) -> int:
    for i, c in enumerate(nb["cells"]):
        src = c["source"] if isinstance(c["source"], str) else "".join(c["source"])
        if needle in src:
            return i
    raise KeyError(needle)


def _replace(nb: dict, needle: str, src: str) -> dict:
    nb = copy.deepcopy(nb)
    nb["cells"][_find(nb, needle)]["source"] = src
    return nb


def _insert(nb: dict, after_needle: str, src: str) -> dict:
    nb = copy.deepcopy(nb)
    nb["cells"].insert(_find(nb, after_needle) + 1, _code(src, "inserted"))
    return nb


def _append(nb: dict, src: str) -> dict:
    nb = copy.deepcopy(nb)
    nb["cells"].append(_code(src, "appended"))
    return nb


def _edit_add(body: str) -> Callable[[dict], bytes]:
    return lambda nb: _dump(_replace(nb, "def add(", "def add(a, b):\n" + body))


def _edit_fk(body: str) -> Callable[[dict], bytes]:
    return lambda nb: _dump(
        _replace(nb, "def fk_2r(", "import numpy as np\ndef fk_2r(l1, l2, q1, q2):\n" + body)
    )


@dataclass
class Case:
    """One submission of the corpus and what it must get."""

    name: str
    build: Callable[[dict], bytes]
    score: float
    status: str
    says: list[str] = field(default_factory=list)  # substrings the student's feedback must contain
    why: str = ""


# ----------------------------------------------------------------------------- builders
def _lab4(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    nb["nbformat_minor"] = 5
    nb["metadata"] = {
        "kernelspec": {
            "display_name": "Python 3 (ipykernel)",
            "language": "python",
            "name": "python3",
        },
        "language_info": {
            "codemirror_mode": {"name": "ipython", "version": 3},
            "name": "python",
            "version": "3.11.7",
            "pygments_lexer": "ipython3",
        },
        "widgets": {"application/vnd.jupyter.widget-state+json": {"state": {}, "version_major": 2}},
    }
    for i, c in enumerate(nb["cells"]):
        c["id"] = f"{i:08x}-lab4"
        c["source"] = c["source"].splitlines(True) if isinstance(c["source"], str) else c["source"]
        if c["cell_type"] == "code":
            c["execution_count"] = i + 1
            c["metadata"] = {"tags": [], "scrolled": True, "jp-MarkdownHeadingCollapsed": True}
    return _dump(nb)


def _nb7_old_minor(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    nb["nbformat_minor"] = 4
    for c in nb["cells"]:
        c.pop("id", None)
        if c["cell_type"] == "code":
            c["outputs"] = [
                {"name": "stdout", "output_type": "stream", "text": ["All tests passed!\n"]}
            ]
    nb["metadata"]["notebook7"] = {"trusted": True}
    return _dump(nb)


def _colab(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    nb["nbformat_minor"] = 0
    nb["metadata"] = {
        "colab": {"provenance": [], "name": "fake2r.ipynb", "toc_visible": True},
        "kernelspec": {"name": "python3", "display_name": "Python 3"},
        "language_info": {"name": "python"},
        "accelerator": "GPU",
    }
    for i, c in enumerate(nb["cells"]):
        c.pop("id", None)
        c["metadata"] = {
            "id": f"colabcell{i}",
            "colab": {"base_uri": "https://localhost:8080/"},
            "outputId": f"out{i}",
        }
    nb["cells"].insert(
        0,
        # Colab's usual first cell; a shell command that cannot work offline fails as
        # it would, and the cell goes on (pip itself: tests/test_grader_ipython.py)
        _code("!nvidia-smi\nfrom google.colab import drive\ndrive.mount('/content/drive')"),
    )
    nb["cells"][0].pop("id", None)
    return _dump(nb)


def _duplicate_ids(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    for c in nb["cells"]:
        c["id"] = "same-id"
    return _dump(nb)


def _missing_ids(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    nb["nbformat_minor"] = 5
    for c in nb["cells"]:
        c.pop("id", None)
    return _dump(nb)


def _nbformat3(nb: dict) -> bytes:
    cells = []
    for c in nb["cells"]:
        src = c["source"] if isinstance(c["source"], str) else "".join(c["source"])
        if c["cell_type"] == "code":
            cells.append(
                {
                    "cell_type": "code",
                    "input": src.splitlines(True),
                    "language": "python",
                    "metadata": {},
                    "outputs": [],
                    "collapsed": False,
                }
            )
        else:
            cells.append({"cell_type": "markdown", "source": src, "metadata": {}})
    return _dump(
        {
            "nbformat": 3,
            "nbformat_minor": 0,
            "metadata": {"name": ""},
            "worksheets": [{"cells": cells, "metadata": {}}],
        }
    )


def _delete_fk(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    del nb["cells"][_find(nb, "def fk_2r(")]
    return _dump(nb)


def _rename_fk(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    for c in nb["cells"]:
        src = c["source"] if isinstance(c["source"], str) else "".join(c["source"])
        c["source"] = src.replace("fk_2r(", "forward_2r(")
    return _dump(nb)


def _reorder(nb: dict) -> bytes:
    nb = copy.deepcopy(nb)
    check = nb["cells"].pop(_find(nb, "visible checks passed"))
    fk = nb["cells"].pop(_find(nb, "def fk_2r("))
    nb["cells"].insert(0, fk)  # before the imports: defining it still works
    nb["cells"].insert(0, check)  # uses names not defined yet: raises, later cells still run
    return _dump(nb)


def _memory_bomb_cell(nb: dict) -> bytes:
    return _dump(_insert(nb, "import numpy", "big = bytearray(64 * 2**30)"))


def _memory_grow_cell(nb: dict) -> bytes:
    return _dump(
        _insert(nb, "import numpy", "hog = []\nwhile True:\n    hog.append(bytearray(10**7))")
    )


def _secrets_probe(paths: list[str]) -> str:
    return (
        "import os\n"
        f"SECRETS = {paths!r}\n"
        "found = []\n"
        "for p in SECRETS:\n"
        "    try:\n"
        "        if os.path.isdir(p):\n"
        "            os.listdir(p)\n"
        "        else:\n"
        "            open(p, 'rb').read(10)\n"
        "        found.append(p)\n"
        "    except OSError:\n"
        "        pass\n"
        "# walk up the tree from the working directory looking for the course\n"
        "d = os.getcwd()\n"
        "for _ in range(10):\n"
        "    try:\n"
        "        names = os.listdir(d)\n"
        "    except OSError:\n"
        "        names = []\n"
        "    for n in names:\n"
        "        if n in ('solutions', 'grader', 'hidden', 'rikingrade', 'grader_fixtures', '.git'):\n"  # noqa: E501
        "            found.append(os.path.join(d, n))\n"
        "    d = os.path.dirname(d)\n"
        "# nothing seen so far: search the whole tree it can see (not when something was\n"
        "# found: then the walk would only decide whether the cell ends within the time\n"
        "# limit, by how many files the machine has)\n"
        "for root, dirs, files in (os.walk('/') if not found else ()):\n"
        "    if root.startswith(('/proc', '/sys', '/dev', '/usr')) or 'site-packages' in root or '.pyenv' in root:\n"  # noqa: E501
        "        dirs[:] = []\n"
        "        continue\n"
        "    for f in files:\n"
        "        if f in ('fake2r.py', 'fake2r_solution.ipynb', 'spec.py', 'grades.csv', 'corpus.py'):\n"  # noqa: E501
        "            found.append(os.path.join(root, f))\n"
        "def add(a, b):\n"
        "    return a + b if not found else -999\n"
    )


def secret_paths() -> list[str]:
    """Files and folders a notebook must never see (the course and this fixture)."""
    import rikingrade

    course = Path(rikingrade.__file__).resolve().parent.parent.parent
    return [
        str(p)
        for p in (
            ASSIGNMENT,
            SOLUTION,
            HERE,
            course / "grader",
            course / "grader" / "rikingrade" / "spec.py",
            course / "grader" / "rikingrade" / "hidden",
            course / "solutions",
            course / "exercises",
            course / "tests",
            course / ".git",
            course / "README.md",
            Path(rikingrade.__file__).parent,
            Path("/etc/passwd"),
            Path("/etc/shadow"),
            Path("/home"),
        )
    ]


SOCKETS = (
    "import socket\n"
    "connected = []\n"
    "for host, port in [('1.1.1.1', 53), ('8.8.8.8', 53), ('127.0.0.1', 22), ('pypi.org', 443)]:\n"
    "    try:\n"
    "        socket.create_connection((host, port), timeout=0.5).close()\n"
    "        connected.append(host)\n"
    "    except OSError:\n"
    "        pass\n"
    "try:\n"
    "    u = socket.socket(socket.AF_UNIX)\n"
    "    u.connect('/run/systemd/private')\n"
    "    connected.append('unix')\n"
    "except OSError:\n"
    "    pass\n"
    "def add(a, b):\n"
    "    return a + b if not connected else -999\n"
)

DELETE = (
    "import os, shutil, rikin, numpy\n"
    "victims = [os.path.dirname(rikin.__file__), os.path.dirname(numpy.__file__), '/usr/lib', '/opt', '/etc']\n"  # noqa: E501
    "for v in victims:\n"
    "    try:\n"
    "        shutil.rmtree(v)\n"
    "    except OSError:\n"
    "        pass\n"
    "for v in [rikin.__file__, numpy.__file__, '/opt/rikingrade/child.py']:\n"
    "    try:\n"
    "        os.remove(v)\n"
    "    except OSError:\n"
    "        pass\n"
)

MONKEYPATCH = (
    "import builtins, math\n"
    "import numpy as np\n"
    "np.allclose = lambda *a, **k: True\n"
    "np.isclose = lambda *a, **k: True\n"
    "np.array_equal = lambda *a, **k: True\n"
    "np.testing.assert_allclose = lambda *a, **k: None\n"
    "math.isclose = lambda *a, **k: True\n"
    "builtins.abs = lambda x: 0\n"
    "builtins.isinstance = lambda *a: True\n"
    "class Liar(float):\n"
    "    def __eq__(self, other):\n"
    "        return True\n"
    "    __hash__ = float.__hash__\n"
    "def add(a, b):\n"
    "    return Liar(0.0)\n"
    "def fk_2r(l1, l2, q1, q2):\n"
    "    return np.zeros(2)\n"
    "def fk_2r_batch(l1, l2, q):\n"
    "    return np.zeros((len(q), 2))\n"
)

FAKE_PASS = (
    "print('All tests passed! Score: 5/5')\n"
    'print(\'{"score": 5, "tests": [{"name": "fk_2r", "score": 2, "status": "passed"}]}\')\n'
    "def add(a, b):\n"
    "    print('add: PASSED 1/1')\n"
    "    return a - b + 0.5\n"
    "def fk_2r(l1, l2, q1, q2):\n"
    "    print('fk_2r: PASSED 2/2')\n"
    "    return [0.0, 0.0]\n"
    "def fk_2r_batch(l1, l2, q):\n"
    "    return [[0.0, 0.0]] * len(q)\n"
)


def _fake_pass(nb: dict) -> bytes:
    nb = _append(nb, FAKE_PASS)
    nb["cells"][-1]["outputs"] = [
        {"name": "stdout", "output_type": "stream", "text": ["All tests passed! Score: 5/5\n"]}
    ]
    return _dump(nb)


CASES: list[Case] = [
    Case("solution", lambda nb: _dump(nb), 5, "ok", ["all 4 cases correct"]),
    Case(
        "invalid_json",
        lambda nb: _dump(nb)[: len(_dump(nb)) // 2],
        0,
        "invalid",
        ["not valid notebook JSON"],
    ),
    Case("empty_file", lambda nb: b"", 0, "invalid", ["empty"]),
    Case("not_a_notebook", lambda nb: b"[1, 2, 3]", 0, "invalid", ["not a notebook"]),
    Case("binary_garbage", lambda nb: bytes(range(256)) * 4, 0, "invalid", ["not UTF-8"]),
    # issue 26: a 5,000-digit number put the whole class in grader-error (exit 1); JSON
    # that is not a notebook got status ok and "did you rename it?"
    Case(
        "five_thousand_digits",
        lambda nb: _dump({**nb, "metadata": {"n": 0}}).replace(b'"n": 0', b'"n": ' + b"9" * 5000),
        0,
        "invalid",
        ["JSON that Jupyter cannot open"],
    ),
    Case(
        "source_is_a_number",
        lambda nb: _dump({**nb, "cells": [{**nb["cells"][0], "source": 5}, *nb["cells"][1:]]}),
        0,
        "invalid",
        ["not a notebook: the source of cell 1 is a number"],
    ),
    Case(
        "metadata_is_a_list",
        lambda nb: _dump({**nb, "metadata": [nb["metadata"]]}),
        0,
        "invalid",
        ["not a notebook: its 'metadata' is a list"],
    ),
    Case("jupyterlab4", _lab4, 5, "ok"),
    Case("notebook7_minor4_no_ids", _nb7_old_minor, 5, "ok"),
    Case(
        "colab",
        _colab,
        5,
        "cell-errors",
        [
            "code cell 1 raised ModuleNotFoundError",
            'the shell command "nvidia-smi" exited with status 127',
        ],
    ),
    Case("duplicate_ids", _duplicate_ids, 5, "ok", ["duplicated cell id"]),
    Case("missing_ids", _missing_ids, 5, "ok"),
    Case("nbformat3", _nbformat3, 5, "ok", ["nbformat 3"]),
    Case(
        "deleted_fk_cell",
        _delete_fk,
        3,
        "ok",
        ["function fk_2r not found: did you rename it?"],
    ),
    Case(
        "renamed_fk",
        _rename_fk,
        3,
        "ok",
        ["function fk_2r not found: did you rename it?", "forward_2r"],
    ),
    # the visible checks moved first would raise NameError, but they only call the answer
    # functions, so grading does not run them (see rikingrade.cellplan)
    Case("reordered_cells", _reorder, 5, "ok"),
    Case(
        "raising_cell",
        lambda nb: _dump(_insert(nb, "import numpy", "raise RuntimeError('oops')")),
        5,
        "cell-errors",
        ["RuntimeError: oops", "later cells still ran"],
    ),
    # a name of its own: in the uid sandbox /dev/shm is the machine's, and a grader running
    # beside this one (another class, another suite) may be writing its own hog there
    Case(
        "fill_dev_shm",
        lambda nb: _dump(
            _insert(
                nb,
                "import numpy",
                "import os\nopen(f'/dev/shm/hog-{os.getpid()}', 'wb').write(b'x' * 10**7)",
            )
        ),
        5,
        "cell-errors",
        ["Read-only file system"],
    ),
    Case(
        "html_in_error_message",
        lambda nb: _dump(
            _insert(nb, "import numpy", "raise ValueError('<script>alert(1)</script> **bold**')")
        ),
        5,
        "cell-errors",
        ["\\<script\\>alert(1)\\</script\\> \\*\\*bold\\*\\*"],  # Markdown-escaped, not HTML
    ),
    Case(
        "sys_exit_cell",
        lambda nb: _dump(_insert(nb, "import numpy", "import sys\nsys.exit('bye')")),
        5,
        "cell-errors",
        ["SystemExit"],
    ),
    Case(
        "input_cell",
        lambda nb: _dump(_insert(nb, "import numpy", "name = input('Your name: ')")),
        5,
        "cell-errors",
        ["input() is not available while grading"],
    ),
    Case(
        "input_in_add",
        _edit_add("    n = input('press enter')\n    return a + b"),
        3,
        "ok",
        ["input() is not available"],
    ),
    Case(
        "huge_output_cell",
        lambda nb: _dump(
            _insert(
                nb,
                "import numpy",
                "print('x' * 5_000_000)\nfor i in range(100_000):\n    print(i)",
            )
        ),
        5,
        "ok",
    ),
    Case("huge_output_in_add", _edit_add("    print('y' * 2_000_000)\n    return a + b"), 5, "ok"),
    Case(
        "os_exit_cell",
        lambda nb: _dump(_insert(nb, "def fk_2r_batch(", "import os\nos._exit(0)")),
        5,
        "crashed",
        ["stopped the notebook's process"],
    ),
    Case(
        "os_exit_in_add",
        _edit_add("    import os\n    os._exit(3)"),
        3,
        "crashed",
        ["the notebook's process stopped"],
    ),
    Case(
        "fork_bomb_cell",
        lambda nb: _dump(_insert(nb, "import numpy", "import os\nwhile True:\n    os.fork()")),
        5,
        "cell-errors",
        ["BlockingIOError"],
    ),
    Case(
        "fork_bomb_swallowed_in_fk",
        _edit_fk(
            "    import os\n    while True:\n        try:\n            os.fork()\n        except OSError:\n            pass"  # noqa: E501
        ),
        3,
        "timeout",
        ["did not return in time"],
    ),
    Case(
        "thread_bomb_cell",
        lambda nb: _dump(
            _insert(
                nb,
                "import numpy",
                "import threading, time\nts = [threading.Thread(target=time.sleep, args=(30,), daemon=True) "  # noqa: E501
                "for _ in range(500)]\nfor t in ts:\n    t.start()",
            )
        ),
        5,
        "cell-errors",
        ["RuntimeError"],
    ),
    Case("memory_bomb_cell", _memory_bomb_cell, 5, "cell-errors", ["MemoryError"]),
    Case("memory_grow_cell", _memory_grow_cell, 5, "cell-errors", ["MemoryError"]),
    Case(
        "memory_bomb_in_add",
        _edit_add("    junk = [0] * (4 * 10**9)\n    return a + b"),
        3,
        "ok",
        ["MemoryError"],
    ),
    Case(
        "infinite_loop_fk",
        _edit_fk("    while True:\n        pass"),
        3,
        "timeout",
        ["did not return in time"],
    ),
    Case(
        "sleep_cell",
        lambda nb: _dump(_insert(nb, "import numpy", "import time\ntime.sleep(600)")),
        5,
        "timeout",
        ["did not finish within"],
    ),
    Case("delete_files", lambda nb: _dump(_insert(nb, "import numpy", DELETE)), 5, "ok"),
    Case("read_files", lambda nb: _dump(_append(nb, _secrets_probe(secret_paths()))), 5, "ok"),
    Case("sockets", lambda nb: _dump(_append(nb, SOCKETS)), 5, "ok"),
    Case("monkeypatch_numpy_builtins", lambda nb: _dump(_append(nb, MONKEYPATCH)), 0, "ok"),
    Case("fake_all_passed_output", _fake_pass, 0, "ok"),
    Case(
        "wrong_fk_swapped",
        lambda nb: _dump(
            _replace(
                _replace(
                    nb,
                    "def fk_2r(",
                    "def fk_2r(l1, l2, q1, q2):\n    return np.array([l1*np.sin(q1) + l2*np.sin(q1+q2), "  # noqa: E501
                    "l1*np.cos(q1) + l2*np.cos(q1+q2)])",
                ),
                "def fk_2r_batch(",
                "def fk_2r_batch(l1, l2, q):\n    return np.array([fk_2r(l1, l2, a, b) for a, b in q])[:, ::-1] * 0",  # noqa: E501
            )
        ),
        2,
        "ok",
    ),
    Case(
        "partial_fk_ignores_q2",
        _edit_fk("    return np.array([(l1 + l2) * np.cos(q1), (l1 + l2) * np.sin(q1)])"),
        3.5,
        "ok",
        ["1 of 4 cases correct"],
    ),
    Case("empty_notebook", lambda nb: _dump({**nb, "cells": []}), 0, "ok", ["no code cells"]),
    Case(
        "magics",
        lambda nb: _dump(
            _replace(
                _insert(
                    nb,
                    "import numpy",
                    "%matplotlib inline\n%load_ext autoreload\n%autoreload 2\n%precision 3\n"
                    "!echo $HOME > home.txt",
                ),
                "def add(",
                "%%time\ndef add(a, b):\n    return a + b",
            )
        ),
        5,
        "ok",
    ),
    Case(
        "unsupported_return",
        _edit_add("    return (x for x in [a + b])"),
        3,
        "ok",
        ["cannot read"],
    ),
    Case("nan_return", _edit_add("    return float('nan')"), 3, "ok"),
    Case(
        "deep_return",
        _edit_add("    r = a + b\n    for _ in range(5000):\n        r = [r]\n    return r"),
        3,
        "ok",
    ),
    Case(
        "huge_return",
        _edit_add("    import numpy as np\n    return np.zeros(3_000_000) + a + b"),
        3,
        "ok",
        ["more than"],
    ),
    # The zygote is the sandbox's PID 1: SIGKILL/SIGSTOP from inside do not reach it, and
    # kill(-1) spares the caller and PID 1.
    Case(
        "kill_zygote",
        lambda nb: _dump(_insert(nb, "def fk_2r_batch(", "import os\nos.kill(os.getppid(), 9)")),
        5,
        "ok",
    ),
    Case(
        "kill_everything",
        lambda nb: _dump(
            _insert(
                nb,
                "def fk_2r_batch(",
                "import os, signal\nfor s in (signal.SIGTERM, signal.SIGINT, signal.SIGKILL):\n"
                "    try:\n        os.kill(-1, s)\n    except OSError:\n        pass",
            )
        ),
        5,
        "ok",
    ),
    Case(
        "stop_zygote",
        lambda nb: _dump(
            _insert(
                nb, "def fk_2r_batch(", "import os, signal\nos.kill(os.getppid(), signal.SIGSTOP)"
            )
        ),
        5,
        "ok",
    ),
    Case(
        "garbage_on_channel",
        lambda nb: _dump(
            _insert(nb, "def fk_2r_batch(", "import os\nos.write(3, b'this is not json\\n')")
        ),
        5,
        "crashed",
    ),
    Case(
        "forged_cell_end_then_hang",
        lambda nb: _dump(
            _insert(
                nb,
                "import numpy",
                "import os, time\n"
                'os.write(3, b\'{"event": "cell_end", "cell": 2, "error": null}\\n\')\n'
                "time.sleep(600)",
            )
        ),
        5,
        "timeout",
        ["code cell 2 did not finish within"],
    ),
    Case(
        "close_channel",
        lambda nb: _dump(_insert(nb, "def fk_2r_batch(", "import os\nos.closerange(3, 1000)")),
        5,
        "crashed",
    ),
]


# ----------------------------------------------------------------------------- issue 15
# Forged channel events: nothing a notebook writes on its own channel (fd 3) moves the
# grader's deadlines (a per-cell clock reset every 0.5 s stalled the whole batch).
FORGE_START_LOOP = (
    "import os, time, json\n"
    "while True:\n"
    "    os.write(3, (json.dumps({'event': 'cell_start', 'cell': 2}) + '\\n').encode())\n"
    "    time.sleep(0.5)"
)
FORGE_NEXT_CELLS = (  # claims the next cells started and ended, then hangs
    "import os, time, json\n"
    "for n in range(3, 60):\n"
    "    for ev in ({'event': 'cell_end', 'cell': n - 1, 'error': None},\n"
    "               {'event': 'cell_start', 'cell': n}):\n"
    "        os.write(3, (json.dumps(ev) + '\\n').encode())\n"
    "    time.sleep(0.5)\n"
    "time.sleep(600)"
)
FORGE_ANSWERS = (  # answers for calls never asked, while the real call sleeps
    "    import os, time, json\n"
    "    for i in range(1000):\n"
    "        os.write(3, (json.dumps({'id': 10**6 + i, 'value': a + b}) + '\\n').encode())\n"
    "        time.sleep(0.2)\n"
    "    return a + b"
)
# Lone surrogates: valid JSON escapes that no file, log or terminal can take.
SURROGATE_CELL = "print('caf\\udcff')\nraise ValueError('\\udcff bad \\ud800')"
TERMINAL_ESCAPES = (
    "print('\\x1b[2J\\x1b[31mcleared\\r\\x07')\n"
    "!printf '\\033[1;31mshell\\033[0m\\n'\n"
    "raise ValueError('\\x1b[31mred\\x1b[0m \\x1b]0;title\\x07 bell\\x07\\x9b')"
)
MANY_CALLABLES = (  # names sorting before every answer function
    "for _i in range(3000):\n    globals()[f'a{_i:04d}'] = lambda: 0"
)


def _surrogate_source(nb: dict) -> bytes:
    # the notebook's JSON holds "\udcff" in a cell's source (json.dumps escapes it)
    return _dump(_insert(nb, "import numpy", "greeting = 'hi \udcff'\nx = 1"))


def _many_failing_cells(n: int) -> Callable[[dict], bytes]:
    def build(nb: dict) -> bytes:
        nb = copy.deepcopy(nb)
        for i in range(n):
            nb["cells"].append(
                _code(f"print('o' * 3000)\nraise ValueError('cell {i} ' + 'm' * 3000)")
            )
        return _dump(nb)

    return build


CASES += [
    Case(
        "forged_cell_start_every_half_second",
        lambda nb: _dump(_insert(nb, "import numpy", FORGE_START_LOOP)),
        5,
        "timeout",
        ["code cell 2 did not finish within 2 s"],
    ),
    # It can only fool the grader about itself: the cells it claims to be are blamed and
    # skipped in turn (each within 2 s), so it loses its own answers and nothing else.
    Case(
        "forged_next_cells_then_hang",
        lambda nb: _dump(_insert(nb, "import numpy", FORGE_NEXT_CELLS)),
        0,
        "timeout",
        ["did not finish within 2 s"],
    ),
    Case(
        "forged_answers_during_a_call",
        _edit_add(FORGE_ANSWERS),
        3,
        "timeout",
        ["did not return in time"],
    ),
    Case(
        "surrogate_in_exception",
        _edit_add("    raise ValueError('\\udcff')"),
        3,
        "ok",
        ["raised ValueError: ?"],
    ),
    Case(
        "surrogate_in_cell_output_and_error",
        lambda nb: _dump(_insert(nb, "import numpy", SURROGATE_CELL)),
        5,
        "cell-errors",
        ["code cell 2 raised ValueError: ? bad ?"],
    ),
    Case(
        "surrogate_returned",
        _edit_add("    return 'x\\udcff'"),
        3,
        "ok",
    ),
    Case(
        "surrogate_in_cell_source",
        _surrogate_source,
        5,
        "cell-errors",
        ["code cell 2 raised SyntaxError", "not valid Unicode (U+DCFF"],
    ),
    # issue 26: terminal escapes in a student's message and output reached grades.csv,
    # grading.log, the report and the feedback raw (cat grades.csv recoloured the terminal)
    Case(
        "terminal_escapes",
        lambda nb: _dump(_insert(nb, "import numpy", TERMINAL_ESCAPES)),
        5,
        "cell-errors",
        ["code cell 2 raised ValueError: red bell"],
    ),
    Case(
        "many_callables_before_the_answers",
        lambda nb: _dump(_append(nb, MANY_CALLABLES)),
        5,
        "ok",
    ),
    Case(
        "many_failing_cells",
        _many_failing_cells(2000),
        5,
        "cell-errors",
        ["more problems in code cells (not listed)"],
    ),
]


def write_corpus(folder: Path, cases: list[Case] | None = None) -> dict[str, Case]:
    """Write every case as ``<name>.ipynb`` in ``folder``; returns the cases by name."""
    folder.mkdir(parents=True, exist_ok=True)
    base = solution()
    out = {}
    for case in cases or CASES:
        (folder / f"{case.name}.ipynb").write_bytes(case.build(base))
        out[case.name] = case
    return out


if __name__ == "__main__":  # python tests/grader_fixtures/corpus.py OUTDIR
    import sys

    write_corpus(Path(sys.argv[1]))
    print(f"wrote {len(CASES)} notebooks to {sys.argv[1]}", file=sys.stderr)
    os._exit(0)
