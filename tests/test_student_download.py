"""What a student does: download a chapter and an exercise from the hosted book, run them.

The book is built with a test base URL (``html.baseurl`` = ``http://127.0.0.1:<port>/``),
and everything a student's side does then runs in a network namespace that has nothing but
its own loopback (bubblewrap ``--unshare-net``): ``python -m http.server`` serves
``_build/html`` on 127.0.0.1, the notebooks are downloaded from it into an empty folder and
executed there by a fresh virtual environment that has only nbclient and ipykernel. rikin
is not installed in it: the notebooks' first cell must install it from the served book, as
on Colab. Any other address is unreachable, so a notebook that tried to fetch anything else
(a package index, a CDN, a git host) fails its cell and the test.

rikin's own dependencies (numpy, sympy, matplotlib; plotly and ipywidgets, the extras the
chapters install) come from the package index, fetched
before the sandbox into a local wheelhouse that the notebook's pip is pointed at
(``PIP_NO_INDEX``, ``PIP_FIND_LINKS``); rikin's wheel is removed from that wheelhouse, so
the only rikin pip can install is the one the notebook names by URL.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402
from book_build import run_build  # noqa: E402

#: A chapter with drawings, sympy and every planar IK branch, and the chapter that reads
#: the exercise notebooks (from the book, when it is not inside the repository).
CHAPTERS = ("book/planar", "book/exercises")
EXERCISE = "scara"
#: What the student's environment has before opening a notebook: Jupyter's pieces only.
STUDENT_PACKAGES = ["nbclient>=0.8,<1", "ipykernel>=6.25,<8"]

# Run by the fresh venv's Python inside the sandbox: serve the site, download, execute.
DRIVER = r'''
import json, re, subprocess, sys, time, urllib.parse, urllib.request
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

site, base, folder = sys.argv[1:4]
links = json.loads(sys.argv[4])  # {file name: [page, regex of its link on that page]}
port = base.rstrip("/").rsplit(":", 1)[1]
server = subprocess.Popen([sys.executable, "-m", "http.server", "--bind", "127.0.0.1", port,
                           "--directory", site], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL)
try:
    for _ in range(200):
        try:
            urllib.request.urlopen(base, timeout=2).close()
            break
        except OSError:
            time.sleep(0.05)

    def get(url):
        with urllib.request.urlopen(url, timeout=60) as r:
            return r.read()

    def link(page, pattern):
        hrefs = re.findall(r'href="([^"]+)"', get(base + page).decode())
        found = [h for h in hrefs if re.search(pattern, h)]
        if not found:
            sys.exit(f"no link matching {pattern} on {page}")
        return urllib.parse.urljoin(base + page, found[0])

    wanted = {name: link(page, pattern) for name, (page, pattern) in links.items()}
    report = {}
    folder = Path(folder)
    for name, url in wanted.items():
        (folder / name).write_bytes(get(url))
        report[name] = {"url": url}
    for name in wanted:
        # each notebook on its own: a student who opens only this one has no rikin yet
        subprocess.run([sys.executable, "-m", "pip", "uninstall", "--yes", "--quiet", "rikin"],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        path = folder / name
        nb = nbformat.read(path, as_version=4)
        client = NotebookClient(nb, timeout=600, kernel_name="python3",
                                resources={"metadata": {"path": str(folder)}})
        t0 = time.monotonic()
        try:
            client.execute()
            report[name]["error"] = None
        except CellExecutionError as exc:
            report[name]["error"] = str(exc)[-3000:]
        report[name]["seconds"] = round(time.monotonic() - t0, 1)
        nbformat.write(nb, folder / ("executed-" + name))
    print("REPORT " + json.dumps(report))
finally:
    server.terminate()
    server.wait()
'''


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _run(cmd: list, **kw) -> subprocess.CompletedProcess:
    t0 = time.monotonic()
    proc = subprocess.run(
        [str(c) for c in cmd], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw
    )
    print(f"{time.monotonic() - t0:6.1f} s  {' '.join(str(c) for c in cmd[:4])} ...")
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{proc.stdout[-6000:]}"
    return proc


def _build_book(base: str, out: Path) -> Path:
    """Build the book as an instructor would, with ``base`` as its html.baseurl."""
    config = (ROOT / "_config.yml").read_text(encoding="utf-8")
    config, n = re.subn(r'(?m)^(\s+baseurl:\s*).*$', rf'\g<1>"{base}"', config)
    assert n == 1, "_config.yml must have exactly one html.baseurl line"
    # next to _config.yml: jupyter-book resolves local_extensions relative to the config's folder
    cfg = ROOT / f"_config.student-{os.getpid()}.yml"
    cfg.write_text(config, encoding="utf-8")
    assert rikin_site.read_base_url(cfg) == base
    env = dict(os.environ, PYTHONHASHSEED="0", JUPYTER_PREFER_ENV_PATH="1")
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    try:
        proc = run_build(
            [Path(sys.executable).parent / "jupyter-book", "build", ROOT, "--path-output", out,
             "--config", cfg, "--all"],
            cwd=out, env=env,
        )
        assert proc.returncode == 0, f"book build failed:\n{proc.stdout[-6000:]}"
    finally:
        cfg.unlink()
    return out / "_build" / "html"


def _student_env(home: Path, wheelhouse: Path) -> dict[str, str]:
    """A student's environment: no repository on any path, pip sees only the wheelhouse."""
    env = {
        k: v
        for k, v in os.environ.items()
        if not k.startswith(("PIP_", "PYTHON", "JUPYTER", "VIRTUAL_ENV", "MPL", "IPYTHON"))
    }
    env.update(
        HOME=str(home),
        PYTHONNOUSERSITE="1",
        PIP_CONFIG_FILE=os.devnull,  # no pip.conf: no index, no find-links of this machine
        PIP_NO_INDEX="1",
        PIP_FIND_LINKS=str(wheelhouse),
        PIP_DISABLE_PIP_VERSION_CHECK="1",
    )
    return env


@pytest.mark.book
@pytest.mark.slow
def test_downloaded_chapter_and_exercise_run_in_a_fresh_environment(tmp_path: Path) -> None:
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        pytest.fail("bubblewrap (bwrap) is needed to cut the student's side off the network "
                    "(Debian: apt-get install bubblewrap; python3 tools/dev.py test does)")
    base = f"http://127.0.0.1:{_free_port()}/"
    (tmp_path / "build").mkdir()
    site = _build_book(base, tmp_path / "build")
    manifest = json.loads((site / rikin_site.DIST_PATH / rikin_site.MANIFEST).read_text())
    wheel = site / rikin_site.DIST_PATH / manifest["wheel"]["file"]
    assert rikin_site.sha256_of(wheel) == manifest["wheel"]["sha256"]

    # The student's fresh environment: only Jupyter's pieces, no rikin.
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", venv])
    py = venv / "bin" / "python"
    _run([py, "-m", "pip", "install", "--quiet", *STUDENT_PACKAGES], timeout=900)
    probe = subprocess.run([py, "-c", "import rikin"], capture_output=True, text=True)
    assert probe.returncode != 0, "the fresh venv must not have rikin"
    # rikin's dependencies, as the package index has them (fetched now, used offline below)
    wheelhouse = tmp_path / "wheelhouse"
    extras = ",".join(rikin_site.CHAPTER_EXTRAS)
    _run([py, "-m", "pip", "download", "--quiet", "--dest", wheelhouse,
          f"rikin[{extras}] @ {wheel.as_uri()}"], timeout=900)
    for w in wheelhouse.glob("rikin-*"):
        w.unlink()

    home = tmp_path / "home"
    home.mkdir()
    student = tmp_path / "student"  # the empty folder the notebooks are saved to
    student.mkdir()
    driver = tmp_path / "driver.py"
    driver.write_text(DRIVER, encoding="utf-8")
    links = {f"{Path(c).name}.ipynb": [f"{c}.html", r"_sources/.*\.ipynb$"] for c in CHAPTERS}
    links[f"{EXERCISE}.ipynb"] = ["book/exercises.html", rf"_downloads/.*/{EXERCISE}\.ipynb$"]
    proc = _run(
        [bwrap, "--dev-bind", "/", "/", "--unshare-net", "--die-with-parent", "--chdir", student,
         py, driver, site, base, student, json.dumps(links)],
        env=_student_env(home, wheelhouse), timeout=1500,
    )
    print(proc.stdout[-3000:])
    report = json.loads(proc.stdout.split("REPORT ", 1)[1].splitlines()[0])
    assert set(report) == set(links)
    for chapter in CHAPTERS:
        assert report[f"{Path(chapter).name}.ipynb"]["url"] == f"{base}_sources/{chapter}.ipynb"
    for name, r in report.items():
        assert r["url"].startswith(base)
        assert r["error"] is None, f"{name} failed in the student's environment:\n{r['error']}"

    # rikin came from the book, pinned: pip recorded the URL and the hash it checked
    direct = subprocess.run(
        [py, "-c", "import importlib.metadata as m; print(m.distribution('rikin')"
         ".read_text('direct_url.json'))"], capture_output=True, text=True, check=True,
        cwd=student, env=_student_env(home, wheelhouse),
    )
    info = json.loads(direct.stdout)
    assert info["url"] == f"{base}{rikin_site.DIST_PATH}/{manifest['wheel']['file']}", info
    assert info["archive_info"]["hashes"]["sha256"] == manifest["wheel"]["sha256"], info

    import nbformat

    # The chapters: the first cell installed rikin from the book; then every cell ran, and
    # what they show is what the book shows.
    def shown(nb) -> list[tuple]:
        """What each output shows: its kind, mime types, and any text (images: the type).

        Consecutive stream outputs of one cell to the same stream are one text: how the
        kernel cuts printed text into messages depends on timing (CI once saw one print
        of a cell arrive as two outputs in the book and as one in the student's run)."""
        out = []
        for c in nb.cells[1:]:
            if c.cell_type != "code":
                continue
            last_stream = None
            for o in c.outputs:
                if o.output_type == "stream" and o.get("name") == last_stream:
                    kind, types, text = out[-1]
                    out[-1] = (kind, types, text + o.get("text", ""))
                    continue
                last_stream = o.get("name") if o.output_type == "stream" else None
                data = o.get("data", {})
                text = o.get("text", "") or (
                    data.get("text/plain", "") + data.get("text/markdown", "")
                )
                out.append((o.output_type, tuple(sorted(data)), text))
        return out

    for chapter in CHAPTERS:
        name = f"{Path(chapter).name}.ipynb"
        ran = nbformat.read(student / f"executed-{name}", as_version=4)
        published = nbformat.read(site / "_sources" / f"{chapter}.ipynb", as_version=4)
        first = ran.cells[0]
        assert rikin_site.INSTALL_TAG in first.metadata["tags"]
        said = "".join(o.get("text", "") for o in first.outputs)
        assert f"installing it from {base}{rikin_site.DIST_PATH}/" in said, (name, said)
        assert f"rikin {manifest['version']} installed" in said, (name, said)
        assert shown(ran) == shown(published), name
        assert shown(ran), f"{name} showed nothing"
        assert "is not next to this copy" not in str(shown(ran)), name
    ran = nbformat.read(student / "executed-planar.ipynb", as_version=4)
    assert any(o.output_type == "display_data" and "image/png" in o.data
               for c in ran.cells if c.cell_type == "code" for o in c.outputs), \
        "the chapter drew nothing"

    # The exercise (run with rikin uninstalled again): its first cell installed rikin, every
    # cell ran, and the only errors are the unfinished tasks' NotImplementedError.
    ran = nbformat.read(student / f"executed-{EXERCISE}.ipynb", as_version=4)
    said = "".join(o.get("text", "") for o in ran.cells[0].outputs)
    assert rikin_site.INSTALL_TAG in ran.cells[0].metadata["tags"]
    assert f"rikin {manifest['version']} installed" in said, said
    errors = [(i, o.ename) for i, c in enumerate(ran.cells) if c.cell_type == "code"
              for o in c.outputs if o.output_type == "error"]
    expected = [i for i, c in enumerate(ran.cells)
                if "raises-exception" in c.metadata.get("tags", [])]
    assert errors, "the exercise's unfinished tasks raised nothing"
    assert {i for i, _ in errors} <= set(expected)
    assert {e for _, e in errors} == {"NotImplementedError"}, errors
