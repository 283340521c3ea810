"""In the uid sandbox every submission starts from the same clean state, whatever ran before.

Without namespaces the machine's world-writable folders (/tmp, /var/tmp, /dev/shm, ...) are
shared, and one worker's zygote runs its submissions one after another under one uid. What
a submission leaves there (answers in /tmp, a /dev/shm file, a chmod 000 folder, a file in
a world-writable subfolder of someone else's) must be gone before the next one of that
worker starts, as bubblewrap's private /scratch is; nothing the uid does not own is touched.

Three notebooks, graded with ``--workers 1`` (one zygote, one uid): each first looks for
files of its uid in those folders and for the others' answers, then leaves its own. add()
answers wrong when anything was found, so a leak costs points (5 -> 3).

Runs as root under the Docker-like seccomp filter, through the Gradescope bundle's setup
(the ``gs`` fixture of test_grader_gradescope_uid); where it cannot run it fails, saying why.
"""

from __future__ import annotations

import json
import os
import shutil
import sqlite3
import subprocess
import tempfile

from grader_fixtures import corpus
from grader_fixtures.helpers import ASSIGNMENT
from test_grader_gradescope_uid import NOUSERNS, _sandbox_processes, gs  # noqa: F401

NAMES = ("a_first", "b_second", "c_third")


def _notebook(name: str, tag: str, shared: str) -> bytes:
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


def test_no_submission_sees_what_the_one_before_left_in_the_shared_folders(gs):  # noqa: F811
    tag = f"rikin-clean-{os.getpid()}"
    # a world-writable folder of root's (the sweep walks into it; it is not the uid's)
    shared = tempfile.mkdtemp(prefix=f"{tag}-ww-", dir="/tmp")
    os.chmod(shared, 0o1777)
    theirs = os.path.join(shared, "not-the-sandbox's")
    with open(theirs, "w") as f:
        f.write("root's")
    os.chmod(theirs, 0o666)  # writable by the sandbox, owned by root: must stay
    private = gs["base"] / "clean"
    try:
        private.mkdir(mode=0o700)
        shutil.copyfile(ASSIGNMENT, private / "fake2r.py")
        (private / "class").mkdir()
        for name in NAMES:
            (private / "class" / f"{name}.ipynb").write_bytes(_notebook(name, tag, shared))
        env = dict(gs["env"], PYTHONPATH=str(gs["base"] / "grader" / "lib"))
        out = private / "out"
        r = subprocess.run(
            [
                *NOUSERNS,
                str(gs["base"] / "venv" / "bin" / "python"),
                "-m",
                "rikingrade.cli",
                str(private / "fake2r.py"),
                str(private / "class"),
                "--out",
                str(out),
                "--workers",
                "1",  # one zygote, one uid: the three run one after another in it
                "--sandbox",
                "uid",
                "--memory-mb",
                "512",
                "--cpu-seconds",
                "60",
                "--quiet",
            ],
            capture_output=True,
            text=True,
            env=env,
            timeout=900,
        )
        assert "sandbox: uid" in (out / "grading.log").read_text(), r.stderr[-3000:]
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
        assert sorted(scores) == sorted(NAMES), (scores, r.stderr[-3000:])
        # none found anything of the one before it ...
        assert scores == {n: 5 for n in NAMES}, said
        assert all("FOUND []" in " ".join(said[n]) for n in NAMES), said
        # ... each could make the same files (none was in its way) ...
        assert not [ln for n in NAMES for ln in said[n] if ln.startswith("FAILED")], said
        # ... and each did leave its files (so a leak could be seen)
        for name in NAMES:
            assert any(f"{tag}-locked" in ln for ln in said[name] if "LEFT" in ln), said
        # nothing that is not the sandbox's was removed; nothing of it is left afterwards
        assert os.path.isdir(shared) and open(theirs).read().startswith("root's")
        assert not [p for p in os.listdir("/tmp") if p.startswith(tag) and "-ww-" not in p]
        assert sorted(os.listdir(shared)) == ["not-the-sandbox's"]
        assert not [p for p in os.listdir("/dev/shm") if p.startswith(tag)]
        assert not _sandbox_processes()
    finally:
        shutil.rmtree(shared, ignore_errors=True)
        shutil.rmtree(private, ignore_errors=True)
