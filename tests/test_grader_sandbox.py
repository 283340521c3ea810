"""The sandbox itself: what a notebook can see and do, and isolation between submissions."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import time
from pathlib import Path

import pytest
import rikingrade
from grader_fixtures.helpers import ASSIGNMENT, FAST, SOLUTION, require_bwrap
from rikingrade import check_sandbox, grade
from rikingrade.notebook import SubmissionsError
from rikingrade.sandbox import SandboxUnavailable

COURSE = Path(rikingrade.__file__).resolve().parent.parent.parent


def _nb_with(*sources: str) -> str:
    nb = json.loads(SOLUTION.read_text())
    for src in sources:
        nb["cells"].append(
            {
                "cell_type": "code",
                "metadata": {},
                "outputs": [],
                "execution_count": None,
                "source": src,
            }
        )
    return json.dumps(nb)


def test_probe_sees_no_course_no_network_no_writable_dirs():
    require_bwrap()
    info = check_sandbox(paths=[str(ASSIGNMENT), str(SOLUTION)])
    probe = info["probe"]
    assert info["ok"], probe
    assert probe["uid"] == 65534 and probe["gid"] == 65534
    assert probe["visible"] == []
    assert probe["network"] is False
    assert probe["writable"] == []
    assert probe["cwd"].startswith("/scratch/")
    assert "scratch" in probe["root"] and "usr" in probe["root"]
    _only_what_python_needs(info["command"])
    # The sandbox's real uid on the host is never root (root is exempt from RLIMIT_NPROC):
    # a root grader drops to nobody before starting bubblewrap.
    assert info["sandbox_host_uid"] not in (0, None)
    if os.geteuid() == 0:
        assert info["sandbox_host_uid"] == 65534


def _only_what_python_needs(cmd: list[str]) -> None:
    """The bubblewrap command binds Python's files, never the course around them."""
    dests = [cmd[i + 2] for i, a in enumerate(cmd) if a == "--ro-bind"]
    for forbidden in (COURSE, COURSE / "grader", COURSE / "solutions", COURSE / "tests"):
        assert str(forbidden) not in dests
    # rikin is bound alone (its package directory), never the repository around it
    rikin_dir = Path(__import__("rikin").__file__).resolve().parent
    assert any(d == str(rikin_dir) or rikin_dir.is_relative_to(d) for d in dests)
    for d in dests:
        assert not COURSE.is_relative_to(d) or d in ("/",), d
    assert "--unshare-all" in cmd and "--as-pid-1" in cmd and "--disable-userns" in cmd


def test_no_trace_of_one_submission_in_the_next(tmp_path):
    """A submission's files, /scratch entries and background processes are gone for the next."""
    require_bwrap()
    writer = _nb_with(
        "import os, time\n"
        "open('/scratch/answers.txt', 'w').write('42')\n"
        "open('left_in_cwd.txt', 'w').write('42')\n"
        "if os.fork() == 0:\n"
        "    os.setsid()\n"
        "    if os.fork() == 0:\n"
        "        while True:\n"
        "            time.sleep(0.01)\n"
        "    os._exit(0)\n"
    )
    reader = _nb_with(
        "import os\n"
        "me = os.getpid()\n"
        "others = [p for p in os.listdir('/proc') if p.isdigit() and int(p) not in (1, me)]\n"
        "leftovers = [n for n in os.listdir('/scratch') if n not in ('.mpl', os.path.basename(os.getcwd()))]\n"  # noqa: E501
        "seen = others + leftovers + [n for n in os.listdir('.')]\n"
        "def add(a, b):\n"
        "    return a + b if not seen else -999\n"
    )
    cls = tmp_path / "class"
    cls.mkdir()
    (cls / "a_writer.ipynb").write_text(writer)
    (cls / "b_reader.ipynb").write_text(reader)
    report = grade(ASSIGNMENT, [cls], tmp_path / "out", workers=1, **FAST)
    res = report.by_student()
    assert res["a_writer"].score == 5
    assert res["b_reader"].score == 5, res["b_reader"].tests


def test_student_code_never_runs_in_the_grader(tmp_path):
    marker = tmp_path / "ran-here"
    nb = _nb_with(f"open({str(marker)!r}, 'w').write('student code ran on the host')")
    (tmp_path / "s.ipynb").write_text(nb)
    require_bwrap()
    report = grade(ASSIGNMENT, [tmp_path / "s.ipynb"], tmp_path / "out", workers=1, **FAST)
    res = report.results[0]
    assert res.score == 5
    assert not marker.exists()
    assert any(
        "FileNotFoundError" in p or "Read-only" in p or "PermissionError" in p for p in res.problems
    )


def test_endless_loops_cost_their_timeouts_only(tmp_path):
    require_bwrap()
    nb = _nb_with(
        "def fk_2r(l1, l2, q1, q2):\n    while True:\n        pass",
        "def fk_2r_batch(l1, l2, q):\n    while True:\n        pass",
    )
    (tmp_path / "loops.ipynb").write_text(nb)
    report = grade(ASSIGNMENT, [tmp_path], tmp_path / "out", workers=1, timeout=0.5, **FAST)
    res = report.results[0]
    assert res.score == 2  # add only
    assert res.status == "timeout"
    # two tests time out once each (0.5 s); each costs a fresh child (cells re-run)
    assert res.elapsed < 2.0 + 2 * 0.5 + 3.0
    assert [t.timed_out for t in res.tests] == [False, False, True, True]


def test_the_timeout_is_per_call_not_per_test(tmp_path):
    # fk_2r answers each call in 0.2 s: four calls take 0.8 s, each within its 0.6 s.
    require_bwrap()
    nb = _nb_with(
        "import time\n_slow_fk = fk_2r\n"
        "def fk_2r(l1, l2, q1, q2):\n    time.sleep(0.2)\n    return _slow_fk(l1, l2, q1, q2)"
    )
    (tmp_path / "slow.ipynb").write_text(nb)
    report = grade(ASSIGNMENT, [tmp_path], tmp_path / "out", workers=1, timeout=0.6, **FAST)
    res = report.results[0]
    fk = next(t for t in res.tests if t.name.startswith("fk") and "batch" not in t.name)
    assert (fk.fraction, fk.timed_out) == (1.0, False), (fk.feedback, res.problems)
    assert res.score == 5


def test_the_graders_own_output_folder_is_not_a_submission(tmp_path):
    """``--out`` inside the class folder (this run's, and an earlier run's under another
    name) is skipped with a note: never a student refused as "no notebook"; the class
    folder itself cannot be the output folder."""
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    shutil.copy(SOLUTION, cls / "zoe.ipynb")  # sorts after "out": results[0] is zoe
    first = grade(ASSIGNMENT, [cls], cls / "out", workers=1, **FAST)
    assert [r.student for r in first.results] == ["zoe"], first.notes
    second = grade(ASSIGNMENT, [cls], cls / "regraded", workers=1, **FAST)
    assert [r.student for r in second.results] == ["zoe"], second.notes
    assert second.results[0].score == first.results[0].score == 5  # the fixture's full marks
    assert second.summary["refused"] == 0
    skipped = [n for n in second.notes if "the grader's own output folder, skipped" in n]
    # the first run's folder, and this run's own (marked before the class is read)
    assert [n.split(":")[0] for n in skipped] == [str(cls / "out"), str(cls / "regraded")]
    summary = json.loads((cls / "regraded" / "summary.json").read_text())
    assert summary["refused"] == 0
    with pytest.raises(SubmissionsError, match="both the output folder"):
        grade(ASSIGNMENT, [cls], cls, workers=1, **FAST)


def test_a_call_that_hangs_keeps_the_answers_before_it(tmp_path):
    # The third fk_2r call never returns: calls 1-2 count, 3 times out, 4 is not run,
    # and the next test starts in a fresh child (cells re-run) and passes.
    require_bwrap()
    nb = _nb_with(
        "_calls = [0]\n_good_fk = fk_2r\n"
        "def fk_2r(l1, l2, q1, q2):\n"
        "    _calls[0] += 1\n"
        "    while _calls[0] == 3:\n        pass\n"
        "    return _good_fk(l1, l2, q1, q2)"
    )
    (tmp_path / "hang.ipynb").write_text(nb)
    report = grade(ASSIGNMENT, [tmp_path], tmp_path / "out", workers=1, timeout=0.5, **FAST)
    res = report.results[0]
    names = [t.name for t in res.tests]
    fk = res.tests[2]
    assert "fk" in names[2] and "batch" in names[3]
    assert (fk.fraction, fk.timed_out) == (0.5, True)
    assert res.tests[3].fraction == 1.0 and not res.tests[3].timed_out
    assert res.status == "timeout"


def test_missing_bubblewrap_fails_loudly(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    (tmp_path / "s.ipynb").write_bytes(SOLUTION.read_bytes())
    with pytest.raises(SandboxUnavailable, match="apt-get install -y bubblewrap"):
        grade(ASSIGNMENT, [tmp_path / "s.ipynb"], tmp_path / "out", **FAST)
    with pytest.raises(SandboxUnavailable, match="unsafe-no-sandbox"):
        check_sandbox()


def test_unsafe_mode_grades_without_bubblewrap(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", os.pathsep.join([str(tmp_path), "/usr/bin", "/bin"]))
    monkeypatch.setattr("shutil.which", lambda name, *a, **k: None)
    (tmp_path / "s.ipynb").write_bytes(SOLUTION.read_bytes())
    report = grade(
        ASSIGNMENT, [tmp_path / "s.ipynb"], tmp_path / "out", unsafe_no_sandbox=True, **FAST
    )
    assert report.results[0].score == 5
    assert "UNSAFE" in (tmp_path / "out" / "grading.log").read_text()


def test_paths_inside_bound_directories_can_be_masked():
    """An installed (non-editable) rikingrade sits in site-packages: it must be masked."""
    require_bwrap()
    import nbformat

    pkg = Path(nbformat.__file__).resolve().parent  # stands in for site-packages/rikingrade
    single = Path(pytest.__file__).resolve()  # a single file in a bound directory
    seen = check_sandbox(paths=[str(pkg)])  # not masked: visible (so the check below can fail)
    assert seen["probe"]["visible"] == [str(pkg)] and not seen["ok"]
    masked = check_sandbox(hidden=[pkg, pkg / "sign.py", single])
    assert masked["ok"], masked["probe"]
    assert masked["probe"]["visible"] == []


def test_a_submission_has_a_wall_clock_budget(tmp_path):
    """Ten cells of 1.5 s each (under the 2 s cell limit) stop at the 6 s budget."""
    require_bwrap()
    nb = _nb_with(*["import time\ntime.sleep(1.5)"] * 10)
    (tmp_path / "slow.ipynb").write_text(nb)
    report = grade(
        ASSIGNMENT, [tmp_path / "slow.ipynb"], tmp_path / "out", workers=1, time_budget=6, **FAST
    )
    res = report.results[0]
    assert res.elapsed < 6 + 2.0
    assert res.status == "timeout" and "time budget (6 s)" in res.reason
    assert res.score == 0
    assert all(t.timed_out and "time budget" in t.feedback for t in res.tests)


def test_each_submission_gets_an_empty_writable_full_scratch(tmp_path):
    """Files in /scratch/.mpl, read-only folders, a full /scratch: none reach the next one."""
    require_bwrap()
    writer = _nb_with(
        "import os\n"
        "open('/scratch/.mpl/leak.txt', 'w').write('42')\n"
        "os.makedirs('/scratch/locked/inner')\n"
        "open('/scratch/locked/inner/answers.txt', 'w').write('42')\n"
        "try:\n"
        "    with open('/scratch/locked/inner/fill', 'wb') as f:\n"
        "        while True:\n"
        "            f.write(b'x' * 2**20)\n"
        "except OSError:\n"
        "    pass\n"
        "os.chmod('/scratch/locked/inner', 0o500)\n"
        "os.chmod('/scratch/locked', 0o000)\n"
        "os.chmod('/scratch/.mpl', 0o500)\n"
        "os.chmod('/scratch', 0o500)\n"
    )
    reader = _nb_with(
        "import os\n"
        "seen = [n for n in os.listdir('/scratch') if n not in ('.mpl', os.path.basename(os.getcwd()))]\n"  # noqa: E501
        "seen += [n for n in os.listdir('/scratch/.mpl') if not n.startswith('fontlist-')]\n"
        "open('/scratch/.mpl/mine.txt', 'w').write('ok')\n"
        "open('result.bin', 'wb').write(b'y' * 15_000)\n"
        "st = os.statvfs('/scratch')\n"
        "free_mb = st.f_bavail * st.f_frsize / 2**20\n"
        "def add(a, b):\n"
        "    return a + b if not seen and free_mb > 60 else -999\n"
    )
    cls = tmp_path / "class"
    cls.mkdir()
    (cls / "a_writer.ipynb").write_text(writer)
    (cls / "b_reader.ipynb").write_text(reader)
    report = grade(ASSIGNMENT, [cls], tmp_path / "out", workers=1, **FAST)
    res = report.by_student()
    assert res["a_writer"].score == 5
    assert res["b_reader"].score == 5, (res["b_reader"].tests, res["b_reader"].problems)
    assert res["b_reader"].status == "ok", res["b_reader"].problems


def test_a_failure_writing_one_result_costs_that_submission_only(tmp_path, monkeypatch):
    """Every submission reaches the gradebook; the failed one as grader-error (exit 1)."""
    require_bwrap()
    import rikingrade.api as api

    real = api.write_student

    def flaky(out, res, exercise, *rest):
        if res.student.startswith("broken"):
            raise UnicodeEncodeError("utf-8", "\udcff", 0, 1, "surrogates not allowed")
        real(out, res, exercise, *rest)

    monkeypatch.setattr(api, "write_student", flaky)
    cls = tmp_path / "class"
    cls.mkdir()
    for name in ("broken1", "broken2", "c", "d", "e"):
        (cls / f"{name}.ipynb").write_bytes(SOLUTION.read_bytes())
    report = grade(ASSIGNMENT, [cls], tmp_path / "out", workers=2, **FAST)
    res = report.by_student()
    assert sorted(res) == ["broken1", "broken2", "c", "d", "e"]
    assert [res[s].status for s in ("broken1", "broken2")] == ["grader-error"] * 2
    assert all(res[s].score == 5 for s in ("c", "d", "e"))
    assert report.summary["grader_errors"] == 2
    rows = (tmp_path / "out" / "grades.csv").read_text().splitlines()
    assert len(rows) == 6


def _recv_seconds(lines: list[bytes]) -> float:
    """CPU seconds the child's Channel (this thread) spends reading ``lines`` written to its
    socket: the copying that grew quadratically, counted without the time this thread waits
    for the writer or for a CPU on a busy machine."""
    import socket
    import threading
    import time

    from rikingrade.sandbox import child

    a, b = socket.socketpair()
    chan = child.Channel(b.fileno())
    writer = threading.Thread(target=lambda: [a.sendall(x) for x in lines], daemon=True)
    t0 = time.thread_time()  # the reading thread's CPU: no other process's share of the CPUs
    writer.start()
    for _ in lines:
        assert chan.recv() is not None
    dt = time.thread_time() - t0
    writer.join()
    a.close()
    b.close()
    return dt


def test_the_child_reads_a_long_message_in_linear_time():
    """A 40 MiB message costs about 4 times a 10 MiB one, not 16 (it was quadratic: a
    95 MiB code cell took 17-31 s to arrive and once timed out a correct notebook)."""

    def one(mib: int) -> bytes:
        return b'"' + b"z" * (mib * 2**20 - 3) + b'"\n'

    small = min(_recv_seconds([one(10)]) for _ in range(2))
    big = min(_recv_seconds([one(40)]) for _ in range(2))
    assert big < 8 * small + 0.5, (big, small)


HOG = (
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
    "end = time.time() + 25  # writing 350 MiB takes 1-3 s on a loaded machine\n"
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
    "print(json.dumps({'held': held, 'forks_failed': forks_failed,\n"
    "                  'nproc': lim['Max processes'], 'as': lim['Max address space']}))\n"
    "for p in alive:\n"
    "    os.kill(p, 9)\n"
)


def test_a_private_tmpdir_does_not_stop_the_sandbox(tmp_path, monkeypatch):
    """TMPDIR inside a 0700 folder: a root grader stages where its sandbox user can reach."""
    require_bwrap()
    private = tmp_path / "home-like"
    (private / "tmp").mkdir(parents=True)
    os.chmod(private, 0o700)
    monkeypatch.setenv("TMPDIR", str(private / "tmp"))
    monkeypatch.setattr("tempfile.tempdir", None)  # re-read TMPDIR
    info = check_sandbox()
    assert info["ok"], info
    (tmp_path / "s.ipynb").write_bytes(SOLUTION.read_bytes())
    report = grade(ASSIGNMENT, [tmp_path / "s.ipynb"], tmp_path / "out", workers=1, **FAST)
    assert report.results[0].score == 5


def test_bubblewrap_errors_say_what_failed_not_install_bubblewrap():
    from rikingrade.sandbox.config import bwrap_failure

    staged = bwrap_failure(
        "bwrap: Can't find source path /root/private/tmp/rikingrade-stage-x1/s0: Permission denied"
    )
    assert "cannot reach a folder" in staged and "TMPDIR=/tmp" in staged
    assert "apt-get install" not in staged
    ns = bwrap_failure("bwrap: No permissions to create new namespace, likely because ...")
    assert "user namespaces" in ns and "--sandbox uid" in ns and "apt-get" not in ns


def test_a_checkout_under_home_shows_nothing_around_what_python_needs(tmp_path):
    """Folders above a bound directory (/home, /home/<user>, the checkout) cannot be listed."""
    require_bwrap()
    from rikingrade.sandbox import Limits, Sandbox, SandboxConfig, prepare_workdir
    from rikingrade.sandbox.config import sandbox_workdir

    home = Path(tempfile.mkdtemp(prefix="rikin-test-user-", dir="/home"))
    try:
        pkg = home / "checkout" / "pkgdir"
        pkg.mkdir(parents=True)
        (pkg / "ok.txt").write_text("bound")
        (home / "checkout" / "secret.txt").write_text("the course")
        for d in (home, home / "checkout", pkg):
            os.chmod(d, 0o755)
        os.chmod(pkg / "ok.txt", 0o644)
        config = SandboxConfig(extra_ro_binds=[pkg])
        workdir = sandbox_workdir()
        prepare_workdir(workdir, True)
        box = Sandbox(config, workdir)
        try:
            child = box.spawn(Limits())
            deadline = time.monotonic() + 30
            code = (
                "import os\n"
                "def look(paths):\n"
                "    out = {}\n"
                "    for p in paths:\n"
                "        try:\n"
                "            isdir = os.path.isdir(p)\n"
                "            out[p] = sorted(os.listdir(p)) if isdir else open(p).read()\n"
                "        except OSError as e:\n"
                "            out[p] = type(e).__name__\n"
                "    return out\n"
            )
            child.send({"op": "exec", "cells": [[1, code]], "output_limit": 1000}, deadline)
            while child.recv(deadline).get("event") != "exec_done":
                pass
            paths = ["/home", str(home), str(home / "checkout"), str(pkg), str(pkg / "ok.txt")]
            child.send(
                {"op": "call", "id": 1, "function": "look", "kwargs": {"paths": paths}}, deadline
            )
            seen = child.recv(deadline)["value"]
            child.close()
        finally:
            box.close()
            shutil.rmtree(workdir, ignore_errors=True)
    finally:
        shutil.rmtree(home, ignore_errors=True)
    assert seen["/home"] == seen[str(home)] == seen[str(home / "checkout")] == "PermissionError"
    assert seen[str(pkg)] == ["ok.txt"] and seen[str(pkg / "ok.txt")] == "bound"


def _hog(tmp_path, **kw):
    (tmp_path / "hog.ipynb").write_text(_nb_with(HOG))
    report = grade(
        ASSIGNMENT,
        [tmp_path / "hog.ipynb"],
        tmp_path / "out",
        workers=1,
        **{**FAST, "cell_timeout": 40.0, **kw},
    )
    res = report.results[0]
    out = [c.output for c in res.cells if '"held"' in c.output]
    assert res.score == 5 and out, res.problems
    return json.loads(out[0].strip().splitlines()[-1])


def test_memory_is_limited_per_sandbox_not_per_process(tmp_path):
    """Four forks of 350 MiB each under memory_mb=512: the sandbox never holds two (with a
    cgroup), or the process limit keeps them within the machine's share (without one)."""
    require_bwrap()
    from rikingrade.sandbox.cgroup import MemoryGroup, machine_memory_mb

    probe = MemoryGroup.create(f"rikingrade-test-{os.getpid()}")
    if probe is not None:
        probe.close()
    found = _hog(tmp_path)
    if probe is not None:
        assert found["held"] <= 1, found  # 2 x 350 MiB > 512 MiB + /scratch + slack
    else:  # no cgroup here (not root, or a read-only cgroupfs): the fallback must hold
        share = machine_memory_mb() * 0.9
        assert int(found["nproc"]) * int(found["as"]) <= share * 2**20, found


def test_without_a_cgroup_processes_times_memory_fit_the_machine(tmp_path, monkeypatch):
    """No cgroup: the process limit keeps nproc x per-process memory within the share."""
    require_bwrap()
    import rikingrade.api as api
    import rikingrade.sandbox.zygote as zygote

    monkeypatch.setattr(zygote.MemoryGroup, "create", classmethod(lambda cls, name: None))
    monkeypatch.setattr(api, "machine_memory_mb", lambda: 6000)  # a small machine
    share = int(6000 * 0.9)  # one worker
    found = _hog(tmp_path)
    per_process = int(found["as"])
    assert int(found["nproc"]) * per_process <= share * 2**20, found
    assert found["held"] * 350 <= share, found


def test_a_hung_call_does_not_run_the_cells_again(tmp_path):
    """Three slow cells (3 x 1 s) and functions that hang on their first call in every
    process: the cells run once, each test then costs its own timeout only."""
    require_bwrap()
    nb = _nb_with(
        *["import time\ntime.sleep(1.0)\nRUNS = globals().get('RUNS', 0) + 1"] * 3,
        "_hung = set()\n_real = (add, fk_2r, fk_2r_batch)\n"
        "def _once(f):\n"
        "    def g(*a, **k):\n"
        "        if f.__name__ not in _hung:\n"
        "            _hung.add(f.__name__)\n"
        "            while True:\n"
        "                pass\n"
        "        return f(*a, **k)\n"
        "    return g\n"
        "add, fk_2r, fk_2r_batch = (_once(f) for f in _real)\n",
    )
    (tmp_path / "hang.ipynb").write_text(nb)
    report = grade(ASSIGNMENT, [tmp_path], tmp_path / "out", workers=1, timeout=0.5, **FAST)
    res = report.results[0]
    assert [t.timed_out for t in res.tests] == [True] * 4
    # cells once (3 s), four timeouts (4 x 0.5 s), forks and the fixture's own cells: the
    # cells run again after each hang took 4 x 3 s more
    assert res.elapsed < 3.0 + 4 * 0.5 + 4.0, res.elapsed
    assert res.status == "timeout"
