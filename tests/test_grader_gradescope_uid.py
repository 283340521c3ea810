"""The Gradescope bundle where user namespaces are refused: the uid sandbox, end to end.

The bundle's own ``setup.sh`` and ``run_autograder`` run under a seccomp filter like
Docker's default profile (``grader_fixtures/nouserns.py``: no unshare, setns or
namespace clones, so bubblewrap cannot start), as root, exactly as Gradescope runs them.
setup.sh must pick the uid mode and install the grader root-only; then hostile notebooks
must get no false pass, read none of the grader's files, forge no results and leave no
process behind. A batch of the whole hostile corpus is graded the same way.

These tests need root (the uid sandbox switches uids) and network access to PyPI and the
Debian archive (setup.sh installs what Gradescope's image lacks). Where they cannot run
they fail, saying why: they never skip.
"""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import pytest
from grader_fixtures import corpus
from grader_fixtures.helpers import ASSIGNMENT, SOLUTION
from rikingrade.gradescope import gradescope_bundle
from rikingrade.sandbox import uidmode
from rikingrade.sandbox.config import reachable_tmpdir
from rikingrade.sandbox.uidmode import candidate_uids, processes_of

NOUSERNS = [sys.executable, str(Path(__file__).parent / "grader_fixtures" / "nouserns.py")]
SEED = 7


def _sandbox_processes() -> dict[int, list[int]]:
    """Processes of sandbox uids that no grader holds any more (there must be none).

    A uid leased by a grader still running (another test run on this machine) is locked;
    every other one must own no process once its grader has finished. Zombies whose parent
    is PID 1 are left out: dead already, they wait for init (which reaps late here, and on
    Docker without --init never), and come from graders that other tests kill on purpose
    (a killed grader's file reader ends when the grader does). A zombie of any other
    parent counts: that parent is alive and does not reap.
    """
    lock_dir = uidmode._lock_dir()
    left = {}
    for uid in candidate_uids()[:32]:
        fd = os.open(lock_dir / f"uid-{uid}.lock", os.O_RDWR | os.O_CREAT, 0o600)
        try:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                continue  # in use by a grader that is still running
            if pids := [p for p in processes_of(uid) if not _zombie_of_init(p)]:
                left[uid] = pids
        finally:
            os.close(fd)
    return left


def _zombie_of_init(pid: int) -> bool:
    gone = not os.path.exists(f"/proc/{pid}")
    return gone or (uidmode._zombie(pid) and uidmode._parent(pid) == 1)


@pytest.fixture(scope="module")
def gs():
    """A Gradescope-like layout in a world-traversable folder, set up by the bundle's setup.sh."""
    if os.geteuid() != 0:
        pytest.fail(
            "the uid sandbox test must run as root (Gradescope runs setup.sh and run_autograder "
            "as root; the sandbox switches to its own uids): run the suite as root, as CI does",
            pytrace=False,
        )
    r = subprocess.run(
        [*NOUSERNS, "bwrap", "--unshare-all", "--ro-bind", "/", "/", "true"],
        capture_output=True,
        text=True,
    )
    assert r.returncode != 0, "the seccomp filter must make bubblewrap fail, as in Docker"
    base = Path(tempfile.mkdtemp(prefix="rikin-gs-uid-", dir=reachable_tmpdir()))
    os.chmod(base, 0o755)  # like /: every user can traverse it; setup.sh must lock things down
    try:
        root = base / "autograder"
        (root / "source").mkdir(parents=True)
        (root / "submission").mkdir()
        for d in (root, root / "source", root / "submission"):
            os.chmod(d, 0o755)
        bundle = gradescope_bundle(
            ASSIGNMENT, base / "bundle.zip", seed=SEED, cell_timeout=5, memory_mb=512
        )
        with zipfile.ZipFile(bundle) as z:
            z.extractall(root / "source")
        for p in (root / "source").rglob("*"):  # zip extraction keeps no modes: as unzip does
            os.chmod(p, 0o755 if p.is_dir() or p.name in ("setup.sh", "run_autograder") else 0o644)
        env = dict(
            os.environ,
            AUTOGRADER_ROOT=str(root),
            RIKIN_GRADE_VENV=str(base / "venv"),
            RIKIN_GRADE_HOME=str(base / "grader"),
        )
        env.pop("PYTHONPATH", None)
        setup = subprocess.run(
            [*NOUSERNS, "bash", str(root / "source" / "setup.sh")],
            capture_output=True,
            text=True,
            env=env,
            timeout=1500,
        )
        assert setup.returncode == 0, setup.stdout[-3000:] + setup.stderr[-3000:]
        yield {"base": base, "root": root, "env": env, "setup": setup}
    finally:
        shutil.rmtree(base, ignore_errors=True)


def test_setup_picks_the_uid_mode_and_says_so(gs):
    err = gs["setup"].stderr
    assert "bwrap mode unavailable: bubblewrap could not create its namespaces" in err
    assert "sandbox OK: mode uid" in err
    info = json.loads(gs["setup"].stdout[gs["setup"].stdout.index("{\n") :])
    assert info["mode"] == "uid" and info["ok"]
    assert info["probe"]["network"] is False and info["launcher"]["seccomp"] is True
    assert info["sandbox_host_uid"] in candidate_uids()
    # the grader is root-only; the sandbox's Python is readable by all
    for private in (gs["root"] / "source", gs["base"] / "grader"):
        assert os.stat(private).st_mode & 0o077 == 0, private
    assert os.stat(gs["base"] / "venv").st_mode & 0o005 == 0o005


def _run(gs, nb: bytes) -> tuple[subprocess.CompletedProcess[str], dict | None]:
    sub = gs["root"] / "submission"
    shutil.rmtree(sub)
    sub.mkdir()
    (sub / "fake2r.ipynb").write_bytes(nb)
    results = gs["root"] / "results" / "results.json"
    results.unlink(missing_ok=True)
    r = subprocess.run(
        [*NOUSERNS, "bash", str(gs["root"] / "source" / "run_autograder")],
        capture_output=True,
        text=True,
        env=gs["env"],
        timeout=600,
    )
    data = json.loads(results.read_text()) if results.exists() else None
    return r, data


def _probe_notebook(paths: list[str]) -> bytes:
    """add() returns -999 when any of ``paths`` could be read or written."""
    return corpus._dump(
        corpus._append(
            corpus.solution(),
            "import os\n"
            f"PATHS = {paths!r}\n"
            "found = []\n"
            "for p in PATHS:\n"
            "    for attempt in (lambda: os.listdir(p), lambda: open(p, 'rb').read(1),\n"
            "                    lambda: open(os.path.join(p, 'results.json'), 'w').write('{}')):\n"
            "        try:\n"
            "            attempt()\n"
            "            found.append(p)\n"
            "        except OSError:\n"
            "            pass\n"
            "def add(a, b):\n"
            "    return a + b if not found else -999\n",
        )
    )


def test_a_solution_gets_full_marks_in_the_uid_sandbox(gs):
    r, data = _run(gs, SOLUTION.read_bytes())
    assert r.returncode == 0, r.stdout + r.stderr
    assert "student code ran in the uid sandbox" in r.stdout
    assert data["score"] == 5
    assert not _sandbox_processes()


def test_no_read_of_the_grader_files(gs):
    root, base = gs["root"], gs["base"]
    grader = base / "grader" / "lib" / "rikingrade"
    secrets = [
        str(p)
        for p in (
            root / "source",
            root / "source" / "assignment.py",
            root / "source" / "packages" / "rikingrade" / "rikingrade" / "hidden" / "_common.py",
            root / "results",
            root / "submission",
            root / "submission" / "fake2r.ipynb",
            base / "grader",
            grader,
            grader / "hidden",
            grader / "reference" / "_common.py",
            "/root",
            "/proc/1/environ",
        )
    ]
    assert all(os.path.exists(p) for p in secrets)  # so the probe could find them
    r, data = _run(gs, _probe_notebook(secrets))
    assert r.returncode == 0, r.stdout + r.stderr
    assert data["score"] == 5, data
    # ... and the probe does find what is readable: the check above could fail
    r, data = _run(gs, _probe_notebook([str(base / "venv")]))
    assert data["score"] == 3, data


def test_a_daemon_forging_results_is_killed_and_forges_nothing(gs):
    """The original attack: a detached process rewriting results.json to 100 after grading."""
    marker = gs["base"] / "daemon-alive"
    marker.write_text("")
    os.chmod(marker, 0o666)
    results = gs["root"] / "results" / "results.json"
    nb = corpus._dump(
        corpus._append(
            corpus.solution(),
            "import os, time, json, signal\n"
            "if os.fork() == 0:\n"
            "    os.setsid()\n"
            "    if os.fork() == 0:\n"
            "        for s in (signal.SIGTERM, signal.SIGHUP, signal.SIGINT):\n"
            "            signal.signal(s, signal.SIG_IGN)\n"
            "        for _ in range(600):\n"
            "            try:\n"
            f"                open({str(results)!r}, 'w').write(json.dumps({{'score': 100}}))\n"
            "            except OSError:\n"
            "                pass\n"
            f"            open({str(marker)!r}, 'a').write('alive\\n')\n"
            "            time.sleep(0.1)\n"
            "        os._exit(0)\n"
            "    os._exit(0)\n"
            "time.sleep(0.5)\n",
        )
    )
    r, data = _run(gs, nb)
    assert r.returncode == 0, r.stdout + r.stderr
    assert marker.read_text().startswith("alive")  # the daemon did run
    assert data["score"] == 5
    assert not _sandbox_processes()
    size = marker.stat().st_size
    time.sleep(1.0)
    assert marker.stat().st_size == size, "a daemon survived the submission"
    assert json.loads(results.read_text())["score"] == 5


def test_readable_grader_files_stop_the_uid_sandbox_and_nothing_is_scored(gs):
    """If the grader's files become readable, the uid sandbox refuses to start, and the
    submission is marked not graded (no results.json: Gradescope shows an autograder
    failure with no score), never 0."""
    grader = gs["base"] / "grader"
    subprocess.run(["chmod", "-R", "o+rX", str(grader)], check=True)
    try:
        r, data = _run(gs, SOLUTION.read_bytes())
    finally:
        subprocess.run(["chmod", "-R", "go-rwx", str(grader)], check=True)
    assert r.returncode == 1 and data is None, r.stdout + r.stderr
    assert "NOT GRADED" in r.stdout and "no score (not a 0)" in r.stdout
    assert "can read the grader's files" in r.stdout and str(grader) in r.stdout
    assert not _sandbox_processes()


# Where the uid mode scores a hostile case lower than bubblewrap does (never higher):
UID_MODE_LOWER = {
    # world-readable host files (/etc/passwd, /home, this checkout) are visible without a
    # private filesystem view: the probe finds them and its add() sabotages itself
    "read_files": 3,
}
# The zygote is not a PID 1 here: a notebook can kill it (its own uid), and its process
# dies with it; how far it got first varies (kill_zygote 4 or 5, kill_everything 1 or 2
# points seen). Never more than with bubblewrap.
UID_MODE_AT_MOST = {"kill_zygote", "kill_everything"}
# /dev/shm is writable for the sandbox's uid (wiped afterwards): the cell does not raise
UID_MODE_STATUS = {"fill_dev_shm": "ok"}


@pytest.fixture(scope="module")
def batch(gs):
    """The whole hostile corpus graded in one batch (2 workers) in the uid sandbox."""
    base = gs["base"]
    private = base / "batch"
    private.mkdir(mode=0o700)
    shutil.copyfile(ASSIGNMENT, private / "fake2r.py")  # the tests' copy is world-readable
    corpus.write_corpus(private / "class")
    env = dict(gs["env"], PYTHONPATH=str(base / "grader" / "lib"))
    r = subprocess.run(
        [
            *NOUSERNS,
            str(base / "venv" / "bin" / "python"),
            "-m",
            "rikingrade.cli",
            str(private / "fake2r.py"),
            str(private / "class"),
            "--out",
            str(private / "out"),
            "--workers",
            "2",
            "--seed",
            str(SEED),
            "--sandbox",
            "uid",
            "--memory-mb",
            "512",
            "--cell-timeout",
            "2",
            "--cpu-seconds",
            "30",
            "--quiet",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=1200,
    )
    return r, private / "out"


def test_hostile_corpus_in_the_uid_sandbox(batch):
    r, out = batch
    # the corpus holds files that are not notebooks (empty, cut short, not JSON): refused,
    # so the run exits 1 as the instructor's guide says; never a grader error
    summary = json.loads((out / "summary.json").read_text())
    refused = sum(c.status == "invalid" for c in corpus.CASES)
    assert (summary["refused"], summary["grader_errors"]) == (refused, 0), summary
    assert r.returncode == 1, r.stdout + r.stderr
    assert "sandbox: uid" in (out / "grading.log").read_text()
    got = {}
    for case in corpus.CASES:
        data = json.loads((out / "results" / f"{case.name}.json").read_text())
        got[case.name] = data["score"]
    expected = {c.name: c.score for c in corpus.CASES}
    false_pass = {n: s for n, s in got.items() if s > expected[n] + 1e-9}
    assert not false_pass
    want = {
        c.name: UID_MODE_LOWER.get(c.name, c.score)
        for c in corpus.CASES
        if c.name not in UID_MODE_AT_MOST
    }
    off = [n for n in want if abs(got[n] - want[n]) > 1e-9]
    why = {n: (out / "feedback" / f"{n}.md").read_text()[:3000] for n in off}
    assert {n: got[n] for n in want} == pytest.approx(want, abs=1e-9), why
    rows = {
        line.split(",")[0]: line.split(",")[1]
        for line in (out / "grades.csv").read_text().splitlines()[1:]
    }
    for case in corpus.CASES:
        if case.name not in UID_MODE_AT_MOST:  # their status varies as their score does
            assert rows[case.name] == UID_MODE_STATUS.get(case.name, case.status), case.name
    assert not _sandbox_processes()


def _grade_uid(
    gs, name: str, nb: bytes, *options: str
) -> tuple[subprocess.CompletedProcess[str], Path]:
    """One notebook graded by the CLI in the uid sandbox, under the seccomp filter."""
    return _grade_class_uid(gs, name, {name: nb}, *options)


def _grade_class_uid(
    gs, name: str, notebooks: dict[str, bytes], *options: str
) -> tuple[subprocess.CompletedProcess[str], Path]:
    """A class of notebooks (student -> notebook) graded by the CLI in the uid sandbox with
    one worker (one zygote, one uid: one after another, in the order of their names)."""
    private = gs["base"] / name
    private.mkdir(mode=0o700)
    shutil.copyfile(ASSIGNMENT, private / "fake2r.py")
    (private / "class").mkdir()
    for student, nb in notebooks.items():
        (private / "class" / f"{student}.ipynb").write_bytes(nb)
    env = dict(gs["env"], PYTHONPATH=str(gs["base"] / "grader" / "lib"))
    r = subprocess.run(
        [
            *NOUSERNS,
            str(gs["base"] / "venv" / "bin" / "python"),
            "-m",
            "rikingrade.cli",
            str(private / "fake2r.py"),
            str(private / "class"),
            "--out",
            str(private / "out"),
            "--workers",
            "1",
            "--sandbox",
            "uid",
            "--memory-mb",
            "512",
            "--cpu-seconds",
            "60",
            "--quiet",
            *options,
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=900,
    )
    assert "sandbox: uid" in (private / "out" / "grading.log").read_text(), r.stderr
    return r, private / "out"


def _result(out: Path) -> dict:
    import sqlite3

    with sqlite3.connect(out / "gradebook.sqlite") as db:
        (row,) = db.execute("SELECT result FROM results ORDER BY id DESC LIMIT 1").fetchall()
    return json.loads(row[0])


def test_a_hung_call_keeps_the_template_in_the_uid_sandbox(gs):
    """A slow cell, then add() hangs once (the first call ever): the next tests run in
    forks of the process that ran the cells, so the cells run once. Run again they would
    count 2, and every function here then answers wrong on purpose."""
    runs = f"/tmp/rikin-uid-template-{os.getpid()}"
    nb = corpus._dump(
        corpus._append(
            corpus.solution(),
            "import os, time\n"
            "time.sleep(0.6)  # slow cells: worth keeping as a template\n"
            f"RUNS = {runs!r}\n"
            "with open(RUNS, 'a') as f:\n"
            "    f.write('x')\n"
            "def _once():\n"
            "    return len(open(RUNS).read()) == 1\n"
            "_add, _fk, _fkb = add, fk_2r, fk_2r_batch\n"
            "def add(a, b):\n"
            "    if not os.path.exists(RUNS + '.hung'):\n"
            "        open(RUNS + '.hung', 'w').close()\n"
            "        while True:\n"
            "            pass\n"
            "    return _add(a, b) if _once() else -999\n"
            "def fk_2r(*a, **k):\n"
            "    return _fk(*a, **k) if _once() else _fk(*a, **k) + 1\n"
            "def fk_2r_batch(*a, **k):\n"
            "    return _fkb(*a, **k) if _once() else _fkb(*a, **k) + 1\n",
        )
    )
    r, out = _grade_uid(gs, "template", nb, "--cell-timeout", "10")
    res = _result(out)
    points = {t["name"]: t["weight"] * t["fraction"] for t in res["tests"]}
    print(f"uid mode, a hung call with a template kept: {res['elapsed']:.1f} s")
    # add_int hung (0); the rest ran in forks of the template, the cells never again
    assert points == {"add_int": 0.0, "add_float": 1.0, "fk_2r": 2.0, "fk_2r_batch": 1.0}, (
        res["tests"],
        r.stderr[-2000:],
    )
    assert not _sandbox_processes()


HOG_UID = (
    "import json, os, time\n"
    "r, w = os.pipe()\n"
    "kids, forks_failed = [], 0\n"
    "for _ in range(4):\n"
    "    try:\n"
    "        pid = os.fork()\n"
    "    except OSError:\n"
    "        forks_failed += 1\n"
    "        continue\n"
    "    if pid == 0:\n"
    "        try:\n"
    "            junk = b'x' * (350 * 2**20)  # written, so really held\n"
    "            os.write(w, b'%d\\n' % os.getpid())\n"
    "            time.sleep(30)\n"
    "        finally:\n"
    "            os._exit(0)\n"
    "    kids.append(pid)\n"
    "os.set_blocking(r, False)\n"
    "got, dead = b'', set()\n"
    "end = time.time() + 25\n"
    "while time.time() < end and len(got.split()) + len(dead) < len(kids):\n"
    "    try:\n"
    "        got += os.read(r, 100)\n"
    "    except BlockingIOError:\n"
    "        time.sleep(0.05)\n"
    "    dead |= {p for p in kids if p not in dead and os.waitpid(p, os.WNOHANG)[0]}\n"
    "time.sleep(0.5)  # an OOM kill may follow the last write\n"
    "alive = {p for p in kids if p not in dead and os.waitpid(p, os.WNOHANG) == (0, 0)}\n"
    "held = len({int(x) for x in got.split()} & alive)\n"
    "lim = {l[:26].strip(): l[26:].split()[0] for l in open('/proc/self/limits') if l[:3] == 'Max'}\n"  # noqa: E501
    "print(json.dumps({'held': held, 'nproc': lim['Max processes'], 'as': lim['Max address space']}))\n"  # noqa: E501
    "for p in alive:\n"
    "    os.kill(p, 9)\n"
)


def test_memory_is_limited_per_sandbox_in_the_uid_sandbox(gs):
    """Four forks of 350 MiB under memory_mb=512: with a memory cgroup (a root grader where
    the cgroup fs is writable, as here) the sandbox never holds two; without one the
    process limit keeps processes x per-process memory within the machine's share."""
    from rikingrade.sandbox.cgroup import MemoryGroup, machine_memory_mb

    probe = MemoryGroup.create(f"rikingrade-test-{os.getpid()}")
    if probe is not None:
        probe.close()
    r, out = _grade_uid(
        gs, "hog", corpus._dump(corpus._append(corpus.solution(), HOG_UID)), "--cell-timeout", "40"
    )
    res = _result(out)
    found = [c["output"] for c in res["cells"] if '"held"' in c["output"]]
    assert res["status"] == "ok" and found, (res["status"], res["problems"], r.stderr[-2000:])
    found = json.loads(found[0].strip().splitlines()[-1])
    print(f"uid mode, four forks of 350 MiB: {found} in {res['elapsed']:.1f} s")
    if probe is not None:
        assert found["held"] <= 1, found
    else:  # a read-only cgroup fs (most containers): the fallback must hold
        assert int(found["nproc"]) * int(found["as"]) <= machine_memory_mb() * 0.9 * 2**20, found
    assert not _sandbox_processes()


# ------------------------------------------------ a clean state for every submission
# In the uid sandbox every submission starts from the same clean state, whatever ran before.
#
# Without namespaces the machine's world-writable folders (/tmp, /var/tmp, /dev/shm, ...) are
# shared, and one worker's zygote runs its submissions one after another under one uid. What
# a submission leaves there (answers in /tmp, a /dev/shm file, a chmod 000 folder, a file in
# a world-writable subfolder of someone else's) must be gone before the next one of that
# worker starts, as bubblewrap's private /scratch is; nothing the uid does not own is touched.
#
# Three notebooks, graded with ``--workers 1`` (one zygote, one uid): each first looks for
# files of its uid in those folders and for the others' answers, then leaves its own. add()
# answers wrong when anything was found, so a leak costs points (5 -> 3).
#
# (Here, beside the other uid tests, so that one setup.sh serves them all: two at once
# collide on apt's lock.)
CLEAN_NAMES = ("a_first", "b_second", "c_third")


def _clean_state_notebook(name: str, tag: str, shared: str) -> bytes:
    """Looks for what an earlier submission left, then leaves the same for a later one."""
    code = (
        f"# {name}\n"
        "import json, os\n"
        f"TAG, SHARED = {tag!r}, {shared!r}\n"
        "ROOTS = ('/tmp', '/var/tmp', '/dev/shm', SHARED)\n"
        "me = os.getuid()\n"
        "found = []\n"
        "for d in ROOTS:\n"
        "    for e in os.scandir(d):\n"
        "        try:\n"
        "            if e.stat(follow_symlinks=False).st_uid == me:\n"
        "                found.append(e.path)\n"
        "        except OSError:\n"
        "            pass\n"
        "for p in (f'/tmp/{TAG}-answers', f'/dev/shm/{TAG}-shm', f'{SHARED}/answers'):\n"
        "    try:\n"
        "        found.append(p + ': ' + open(p).read(20))\n"
        "    except OSError:\n"
        "        pass\n"
        "print('FOUND ' + json.dumps(found))\n"
        "_add = add\n"
        "def add(a, b):\n"
        "    return -999 if found else _add(a, b)\n"
        "# now leave some state behind (each step on its own: one that fails is said)\n"
        "def shm():\n"
        "    with open(f'/dev/shm/{TAG}-shm', 'wb') as f:\n"
        "        f.write(b'shm' + bytes(2**20))  # 1 MiB of the machine's memory\n"
        "    os.chmod(f'/dev/shm/{TAG}-shm', 0o644)\n"
        "def answers(d):\n"
        "    with open(f'{d}/{TAG}-answers', 'w') as f:\n"
        "        f.write('add = lambda a, b: a + b')\n"
        "    os.chmod(f'{d}/{TAG}-answers', 0o644)\n"
        "def locked():\n"
        "    d = f'/tmp/{TAG}-locked'\n"
        "    os.makedirs(d + '/inner')\n"
        "    open(d + '/inner/x', 'w').write('x')\n"
        "    os.chmod(d + '/inner', 0)\n"
        "    os.chmod(d, 0)\n"
        "def in_shared():\n"
        "    with open(f'{SHARED}/answers', 'w') as f:\n"
        "        f.write('from the first')\n"
        "    os.chmod(f'{SHARED}/answers', 0o644)\n"
        "    os.mkfifo(f'{SHARED}/fifo')\n"
        "steps = [lambda: answers('/tmp'), lambda: answers('/var/tmp'), shm, locked, in_shared,\n"
        "         lambda: os.symlink('/etc/hostname', f'/tmp/{TAG}-link')]\n"
        "for step in steps:\n"
        "    try:\n"
        "        step()\n"
        "    except OSError as exc:\n"
        "        print('FAILED ' + str(exc))\n"
        "left = sorted(p for p in os.listdir('/tmp') if p.startswith(TAG))\n"
        "print('LEFT ' + json.dumps(left))\n"
    )
    return corpus._dump(corpus._append(corpus.solution(), code))


def test_no_submission_sees_what_the_one_before_left_in_the_shared_folders(gs):
    tag = f"rikin-clean-{os.getpid()}"
    # a world-writable folder of root's (the sweep walks into it; it is not the uid's)
    shared = tempfile.mkdtemp(prefix=f"{tag}-ww-", dir="/tmp")
    os.chmod(shared, 0o1777)
    theirs = os.path.join(shared, "not-the-sandbox's")
    with open(theirs, "w") as f:
        f.write("root's")
    os.chmod(theirs, 0o666)  # writable by the sandbox, owned by root: must stay
    notebooks = {name: _clean_state_notebook(name, tag, shared) for name in CLEAN_NAMES}
    try:
        r, out = _grade_class_uid(gs, "clean", notebooks)
        scores, said = {}, {}
        with sqlite3.connect(out / "gradebook.sqlite") as db:
            rows = db.execute("SELECT student, score, result FROM results").fetchall()
        for student, score, result in rows:
            scores[student] = score
            cells = json.loads(result)["cells"]
            text = "\n".join(c["output"] for c in cells)
            keep = ("FOUND", "LEFT", "FAILED")
            said[student] = [ln for ln in text.splitlines() if ln.split(" ")[0] in keep]
            said[student] += [c["message"] for c in cells if c.get("message")]
        assert sorted(scores) == sorted(CLEAN_NAMES), (scores, r.stderr[-3000:])
        # none found anything of the one before it ...
        assert scores == {n: 5 for n in CLEAN_NAMES}, said
        assert all("FOUND []" in " ".join(said[n]) for n in CLEAN_NAMES), said
        # ... each could make the same files (none was in its way) ...
        assert not [ln for n in CLEAN_NAMES for ln in said[n] if ln.startswith("FAILED")], said
        # ... and each did leave its files (so a leak could be seen)
        for name in CLEAN_NAMES:
            assert any(f"{tag}-locked" in ln for ln in said[name] if "LEFT" in ln), said
        # nothing that is not the sandbox's was removed; nothing of it is left afterwards
        assert os.path.isdir(shared) and open(theirs).read().startswith("root's")
        assert not [p for p in os.listdir("/tmp") if p.startswith(tag) and "-ww-" not in p]
        assert sorted(os.listdir(shared)) == ["not-the-sandbox's"]
        assert not [p for p in os.listdir("/dev/shm") if p.startswith(tag)]
        assert not _sandbox_processes()
    finally:
        shutil.rmtree(shared, ignore_errors=True)
        shutil.rmtree(gs["base"] / "clean", ignore_errors=True)
