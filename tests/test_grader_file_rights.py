"""A root grader reads submissions with no more rights than whoever handed them in.

A hard link is a regular file: linked into a class folder (a tar extracted by the
instructor, a student folder prepared on a shared machine), a root-only file would be read
by a grader running as root. Each file is read by a helper that has dropped to the
folder owner's uid (or, in a folder of root's, a uid of the grader's own), relative to the
submissions folder's fd with no link followed. A refused file is reported with the reason
and the batch exits 1; its contents appear in no output. Downloads unzipped as root or as
the instructor's own user grade as before.

These tests need root (that is the case under test; CI runs as root): elsewhere they fail.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from grader_fixtures.helpers import ASSIGNMENT, FAST, SOLUTION, require_bwrap
from rikingrade import grade
from rikingrade.notebook import FileRefused, discover
from rikingrade.studentfiles import StudentFiles

SECRET = "TOPSECRET-7f3a9c"
#: A uid and gid with no account here, standing for an instructor or a student.
USER = 4242


def _root() -> None:
    if os.geteuid() != 0:
        pytest.fail(
            "reading submissions without root's rights is tested as root (run the suite as "
            "root, as CI does)",
            pytrace=False,
        )


def _notebook(extra: str = "") -> str:
    nb = json.loads(SOLUTION.read_text())
    if extra:
        nb["cells"].append({"cell_type": "code", "metadata": {}, "outputs": [], "source": extra})
    return json.dumps(nb)


def _secret_file(tmp_path: Path, name: str = "instructor") -> Path:
    """A root-only (0600) notebook that prints a marker: correct code, so read it scores."""
    d = tmp_path / "private"
    d.mkdir(mode=0o700, exist_ok=True)
    p = d / f"{name}.ipynb"
    p.write_text(_notebook(f"print({SECRET!r})\n# {SECRET}"))
    os.chmod(p, 0o600)
    return p


def _everything(out: Path, *texts: str) -> bytes:
    blob = b"".join(t.encode() for t in texts)
    for p in out.rglob("*"):
        if p.is_file():
            blob += p.read_bytes()
    return blob


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "rikingrade.cli", *args],
        capture_output=True,
        text=True,
        timeout=300,
    )


FAST_CLI = ["--memory-mb", "512", "--cell-timeout", "5", "--cpu-seconds", "30"]


def test_a_hard_link_to_a_root_only_file_is_refused_and_never_read(tmp_path):
    _root()
    require_bwrap()
    cls = tmp_path / "class"
    cls.mkdir()
    os.chmod(cls, 0o1777)  # a drop folder every student may write (as /tmp is)
    (cls / "alice.ipynb").write_text(_notebook())
    # a hard link whose original is gone: one name, so the link count gives nothing away
    secret = _secret_file(tmp_path, "a")
    os.link(secret, cls / "trudy.ipynb")
    secret.unlink()
    assert os.stat(cls / "trudy.ipynb").st_nlink == 1
    # the same in a student folder owned by a user (a shared machine)
    eve = cls / "eve"
    eve.mkdir()
    os.chown(eve, USER, USER)
    secret = _secret_file(tmp_path, "b")
    os.link(secret, eve / "scara.ipynb")
    secret.unlink()
    # and a hard link that keeps its other name (in the instructor's private folder)
    os.link(_secret_file(tmp_path, "c"), cls / "bob.ipynb")
    out = tmp_path / "out"
    r = _cli("grade", str(ASSIGNMENT), str(cls), "--out", str(out), *FAST_CLI)
    assert r.returncode == 1, r.stdout + r.stderr  # refused files: the instructor must look
    grades = {
        row["student"]: row
        for row in __import__("csv").DictReader(open(out / "grades.csv", encoding="utf-8"))
    }
    assert grades["alice"]["score"] == "5" and grades["alice"]["status"] == "ok"
    for who in ("trudy", "eve", "bob"):
        assert (grades[who]["score"], grades[who]["status"]) == ("0", "invalid"), who
    summary = json.loads((out / "summary.json").read_text())
    assert summary["refused"] == 3 and summary["graded"] == 1
    assert "REFUSED 3" in r.stdout
    # the reason is given, to the instructor and in the student's feedback
    assert "trudy.ipynb (mode 0600, owner uid 0) cannot be read by an unprivileged user" in r.stderr
    assert f"cannot be read by the folder's owner uid {USER}" in r.stderr
    fb = (out / "feedback" / "trudy.md").read_text()
    assert "not graded" in fb and "cannot be read by an unprivileged user" in fb
    assert "hard link" in (out / "feedback" / "bob.md").read_text()
    # what the file holds appears nowhere: not in any output file, the gradebook, the log
    assert SECRET.encode() not in _everything(out, r.stdout, r.stderr)


def test_a_download_unzipped_as_root_or_as_the_instructor_grades(tmp_path):
    _root()
    require_bwrap()
    z = tmp_path / "submissions.zip"
    names = [f"{who}_{100 + i}_{200 + i}_scara.ipynb" for i, who in enumerate(["ann", "ben"])]
    with zipfile.ZipFile(z, "w") as f:
        for i, n in enumerate(names):
            info = zipfile.ZipInfo(n)
            if i == 1:
                info.create_system = 0  # no Unix modes stored: unzip applies the umask
            else:
                info.external_attr = 0o600 << 16  # root-only once unzipped as root
            f.writestr(info, _notebook())
    layouts = {}
    # 1. unzipped by root into a folder unzip makes (everything root's)
    layouts["root"] = tmp_path / "as-root"
    # 2. unzipped by root (sudo) into a folder the instructor made: files root's, folder theirs
    layouts["sudo"] = tmp_path / "sudo" / "class"
    layouts["sudo"].mkdir(parents=True)
    os.chown(layouts["sudo"], USER, USER)
    # 3. unzipped by the instructor as their own user: everything theirs
    layouts["user"] = tmp_path / "as-user"
    for name, dest in layouts.items():
        subprocess.run(
            ["unzip", "-q", str(z), "-d", str(dest)],
            check=True,
            preexec_fn=lambda: os.umask(0o022),
        )
        if name == "user":
            for p in [dest, *dest.rglob("*")]:
                os.chown(p, USER, USER)
    for name, dest in layouts.items():
        report = grade(ASSIGNMENT, dest, tmp_path / f"out-{name}", workers=1, **FAST)
        got = {r.student: (r.status, r.score) for r in report.results}
        assert got == {"ann_100": ("ok", 5.0), "ben_101": ("ok", 5.0)}, (name, got)
        assert report.summary["refused"] == 0


def test_student_folders_owned_by_their_students_are_read_as_them(tmp_path):
    """A shared machine: /srv/hw/<student>/ owned by each student, mode 0700."""
    _root()
    cls = tmp_path / "hw"
    cls.mkdir()
    for i, who in enumerate(["ann", "ben"]):
        d = cls / who
        d.mkdir(mode=0o700)
        (d / "scara.ipynb").write_text(_notebook())
        os.chmod(d / "scara.ipynb", 0o600)
        for p in (d, d / "scara.ipynb"):
            os.chown(p, USER + i, USER + i)
    # ben puts a root-only file of one name in his folder (as root could, by mistake)
    secret = _secret_file(tmp_path)
    os.replace(secret, cls / "ben" / "notes.ipynb")
    with StudentFiles() as files:
        subs, _ = discover([cls], "scara.ipynb", files)
        assert [s.load().cells[0][0] for s in subs] == [1, 1]  # both read, as their owners
        (cls / "ben" / "scara.ipynb").unlink()
        os.replace(cls / "ben" / "notes.ipynb", cls / "ben" / "scara.ipynb")
        ben = [s for s in subs if s.student == "ben"][0]
        with pytest.raises(
            FileRefused, match=f"cannot be read by the folder's owner uid {USER + 1}"
        ):
            ben.load()


def test_a_folder_swapped_for_a_link_after_discovery_is_not_followed(tmp_path):
    """Discovery saw a real folder; by the time the file is read it is a link to secrets."""
    _root()
    cls = tmp_path / "class"
    (cls / "carol").mkdir(parents=True)
    (cls / "carol" / "scara.ipynb").write_text(_notebook())
    (cls / "dave").mkdir()
    (cls / "dave" / "scara.ipynb").write_text(_notebook())
    course = tmp_path / "course"
    course.mkdir()
    (course / "scara.ipynb").write_text(_notebook(f"# {SECRET}"))  # readable by all
    with StudentFiles() as files:
        subs, _ = discover([cls], "scara.ipynb", files)
        shutil.rmtree(cls / "carol")
        (cls / "carol").symlink_to(course, target_is_directory=True)
        carol = [s for s in subs if s.student == "carol"][0]
        with pytest.raises(FileRefused, match="symbolic link"):
            carol.load()
        dave = [s for s in subs if s.student == "dave"][0]
        assert dave.load().cells
        # the same after discovery: a hard link to a root-only file swapped in
        (cls / "dave" / "scara.ipynb").unlink()
        os.link(_secret_file(tmp_path), cls / "dave" / "scara.ipynb")
        with pytest.raises(FileRefused, match="hard link"):
            dave.load()
