"""What a student does: download a chapter and an exercise from the hosted book, run them.

The book is built with a test base URL (``html.baseurl`` = ``http://127.0.0.1:<port>/``;
the test session's one build, tests/book_build.py),
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

import html
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402
from book_build import LAUNCH_REPOSITORY, Site  # noqa: E402

#: A chapter with drawings, sympy and every planar IK branch, and the chapter that reads
#: the exercise notebooks (from the book, when it is not inside the repository).
CHAPTERS = ("book/planar", "book/exercises")
EXERCISE = "scara"
#: What the student's environment has before opening a notebook: Jupyter's pieces only.
STUDENT_PACKAGES = ["nbclient>=0.8,<1", "ipykernel>=6.25,<8"]
#: JupyterLab's own pieces and nothing else, as `pip install jupyterlab` gives them.
LAB_PACKAGES = ["jupyterlab>=4.0,<5"]

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


def _run(cmd: list, **kw) -> subprocess.CompletedProcess:
    t0 = time.monotonic()
    proc = subprocess.run(
        [str(c) for c in cmd], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw
    )
    print(f"{time.monotonic() - t0:6.1f} s  {' '.join(str(c) for c in cmd[:4])} ...")
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{proc.stdout[-6000:]}"
    return proc


def _built_site(build: Site) -> Path:
    """The session's build of the book (tests/book_build.py): made as an instructor would,
    with a loopback html.baseurl and the launch key set."""
    assert build.returncode == 0, f"book build failed:\n{build.log[-6000:]}"
    assert build.launch_repository == LAUNCH_REPOSITORY
    site = Path(build.html)
    cell = json.loads((site / rikin_site.EXERCISES_PATH / f"{EXERCISE}.ipynb").read_text())
    assert f"RIKIN_BOOK = '{build.base}'" in "".join(cell["cells"][0]["source"])
    return site


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


@dataclass
class Published:
    """The book built for ``base`` (an address on 127.0.0.1), and rikin's dependencies."""

    base: str
    site: Path
    manifest: dict
    wheelhouse: Path


class Background:
    """Commands run one after the other in a thread, started now, waited for later."""

    def __init__(self, *cmds: list) -> None:
        self.error: BaseException | None = None
        self.thread = threading.Thread(target=self._run_all, args=(cmds,), daemon=True)
        self.thread.start()

    def _run_all(self, cmds: tuple[list, ...]) -> None:
        try:
            for cmd in cmds:
                _run(cmd, timeout=1200)
        except BaseException as exc:  # noqa: BLE001 - re-raised by wait()
            self.error = exc

    def wait(self) -> None:
        self.thread.join(timeout=1500)
        assert not self.thread.is_alive(), "the background commands did not finish"
        if self.error is not None:
            raise self.error


@pytest.fixture(scope="module")
def lab_venv(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Background]:
    """The student's fresh venv with only JupyterLab, made while the book builds."""
    venv = tmp_path_factory.mktemp("lab") / "venv"
    return venv, Background(
        [sys.executable, "-m", "venv", venv],
        [venv / "bin" / "python", "-m", "pip", "install", "--quiet", "--no-compile",
         *LAB_PACKAGES])


@pytest.fixture(scope="module")
def published(tmp_path_factory: pytest.TempPathFactory, lab_venv: tuple[Path, Background],
              request: pytest.FixtureRequest) -> Published:
    """Build the book as an instructor would, for a local base URL, and fetch rikin's
    dependencies from the package index into a wheelhouse (without rikin itself)."""
    given = os.environ.get("RIKIN_STUDENT_SITE")  # a site this fixture built before
    if given:
        site = Path(given)
        cell = json.loads((site / rikin_site.EXERCISES_PATH / f"{EXERCISE}.ipynb").read_text())
        base = re.search(r"RIKIN_BOOK = '([^']+)'", "".join(cell["cells"][0]["source"]))[1]
    else:
        build: Site = request.getfixturevalue("book_site")  # the session's one build
        base, site = build.base, _built_site(build)
    manifest = json.loads((site / rikin_site.DIST_PATH / rikin_site.MANIFEST).read_text())
    wheel = site / rikin_site.DIST_PATH / manifest["wheel"]["file"]
    assert rikin_site.sha256_of(wheel) == manifest["wheel"]["sha256"]
    wheelhouse = tmp_path_factory.mktemp("wheelhouse")
    extras = ",".join(rikin_site.CHAPTER_EXTRAS)
    _run([sys.executable, "-m", "pip", "download", "--quiet", "--dest", wheelhouse,
          f"rikin[{extras}] @ {wheel.as_uri()}"], timeout=900)
    for w in wheelhouse.glob("rikin-*"):
        w.unlink()
    return Published(base, site, manifest, wheelhouse)


@pytest.mark.book
@pytest.mark.slow
def test_downloaded_chapter_and_exercise_run_in_a_fresh_environment(
        published: Published, tmp_path: Path) -> None:
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        pytest.fail("bubblewrap (bwrap) is needed to cut the student's side off the network "
                    "(Debian: apt-get install bubblewrap; python3 tools/dev.py test does)")
    base, site, manifest = published.base, published.site, published.manifest
    wheelhouse = published.wheelhouse

    # The student's fresh environment: only Jupyter's pieces, no rikin.
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", venv])
    py = venv / "bin" / "python"
    _run([py, "-m", "pip", "install", "--quiet", *STUDENT_PACKAGES], timeout=900)
    probe = subprocess.run([py, "-c", "import rikin"], capture_output=True, text=True)
    assert probe.returncode != 0, "the fresh venv must not have rikin"

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
    assert any(o.output_type == "display_data" and {"image/png", "image/svg+xml"} & set(o.data)
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


# ------------------------------------------------------------------ plain Jupyter Markdown
def _published_notebooks(site: Path) -> list[Path]:
    return sorted([*(site / "_sources").rglob("*.ipynb"),
                   *(site / rikin_site.EXERCISES_PATH).glob("*.ipynb"),
                   *(site / "_downloads").rglob("*.ipynb")])


@pytest.mark.book
@pytest.mark.slow
def test_published_notebooks_are_plain_jupyter_markdown(published: Published) -> None:
    """No MyST left in any notebook the book publishes, and every link to the book lands
    on a page of it and an anchor that page has (issue 28 item 3)."""
    import nbformat
    import rikin_markdown

    site, base = published.site, published.base
    notebooks = _published_notebooks(site)
    assert len(notebooks) >= 10, notebooks
    left, broken = [], []
    for path in notebooks:
        nb = nbformat.read(path, as_version=4)
        for cell in nb.cells:
            if cell.cell_type != "markdown":
                continue
            left += [f"{path.name}: {x}" for x in rikin_markdown.myst_left(cell.source)]
            for url in re.findall(r"\]\((" + re.escape(base) + r"[^)\s]*)\)", cell.source):
                page, _, anchor = url[len(base):].partition("#")
                target = site / page
                if not target.is_file():
                    broken.append(f"{path.name}: {url} (no such file)")
                elif anchor and f'id="{anchor}"' not in target.read_text(encoding="utf-8"):
                    broken.append(f"{path.name}: {url} (no such anchor)")
    assert not left, "MyST left in published notebooks:\n" + "\n".join(left[:40])
    assert not broken, "links to the book that land nowhere:\n" + "\n".join(broken[:40])


# ------------------------------------------------------------------ a real JupyterLab
#: The chapter the JupyterLab test runs: a rotatable figure and the two live panels.
LAB_CHAPTER = "book/angular"


def _lab_env(home: Path, wheelhouse: Path, venv: Path) -> dict[str, str]:
    """The student's JupyterLab: a fresh HOME, the venv first on PATH, pip offline."""
    env = _student_env(home, wheelhouse)
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    env["VIRTUAL_ENV"] = str(venv)
    return env


def _download(base: str, page: str, pattern: str, dest: Path) -> str:
    """Save the file a page links to (its first href matching ``pattern``) into ``dest``."""
    import urllib.parse
    import urllib.request

    with urllib.request.urlopen(base + page, timeout=60) as r:
        hrefs = re.findall(r'href="([^"]+)"', r.read().decode())
    found = [h for h in hrefs if re.search(pattern, h)]
    assert found, f"no link matching {pattern} on {page}"
    url = urllib.parse.urljoin(base + page, found[0])
    with urllib.request.urlopen(url, timeout=60) as r:
        dest.write_bytes(r.read())
    return url


@pytest.fixture
def site_server(published: Published):
    """The built site served at its base URL on 127.0.0.1."""
    import functools
    import http.server
    import threading

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, format: str, *args: object) -> None:  # noqa: A002
            pass

    port = int(published.base.rstrip("/").rsplit(":", 1)[1])
    try:
        httpd = http.server.ThreadingHTTPServer(
            ("127.0.0.1", port), functools.partial(Quiet, directory=str(published.site)))
    except OSError as exc:
        pytest.fail(f"the book was built for {published.base}, but another process has taken "
                    f"port {port} since ({exc}); run the tests again (tests/book_build.py picks "
                    "that port outside the range the system hands out, to make this rare)")
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield published.base
    finally:
        httpd.shutdown()
        httpd.server_close()


def _errors(cells: list[dict]) -> list[str]:
    """Error outputs (JupyterLab shows them as ``application/vnd.jupyter.error``)."""
    return [f"cell {i}: {o['text'][:600]}" for i, c in enumerate(cells) for o in c["outputs"]
            if o["mime"] == "application/vnd.jupyter.error" or (
                o["mime"] == "application/vnd.jupyter.stderr" and "Traceback" in o["text"])]


@pytest.mark.book
@pytest.mark.slow
def test_downloaded_chapter_runs_all_in_jupyterlab_in_headless_chromium(
        published: Published, site_server: str, lab_venv: tuple[Path, Background],
        tmp_path: Path) -> None:
    """What a student does (issue 28 items 1 and 2): a fresh venv with only JupyterLab,
    the chapter and the SCARA exercise downloaded from the book served on 127.0.0.1,
    opened in JupyterLab in headless Chromium, Run All. The first Run All installs rikin
    and draws everything with no error: the rotatable figure works (a solution button
    changes what it draws) and each live panel, which this page cannot show as a widget
    yet, is its still picture with one line saying to reload. After the reload the panel
    is a widget: moving a slider redraws it and changes its solution list."""
    from jupyterlab_driver import Lab

    base = site_server
    venv, made = lab_venv
    made.wait()
    probe = subprocess.run([venv / "bin" / "python", "-c", "import rikin"], capture_output=True)
    assert probe.returncode != 0, "the student's JupyterLab must not have rikin"
    student, home = tmp_path / "student", tmp_path / "home"
    student.mkdir()
    home.mkdir()
    chapter = f"{Path(LAB_CHAPTER).name}.ipynb"
    _download(base, f"{LAB_CHAPTER}.html", r"_sources/.*\.ipynb$", student / chapter)
    _download(base, "book/exercises.html", rf"_downloads/.*/{EXERCISE}\.ipynb$",
              student / f"{EXERCISE}.ipynb")
    shots = Path(os.environ.get("RIKIN_LAB_SCREENSHOTS", tmp_path / "screenshots"))
    with Lab(venv, student, _lab_env(home, published.wheelhouse, venv), shots) as lab:
        lab.open(chapter)
        cells = lab.run_all(timeout=900)
        assert not _errors(cells), "errors in the first Run All:\n" + "\n".join(_errors(cells))
        # the page refused the panels' comms: the kernel replaced them by their pictures
        lab.wait("the panels' outputs to be their pictures alone", lambda: len(lab.js(
            "return [...document.querySelectorAll('.rikin-still[data-refused]')];")) == 2, 120)
        cells = lab.cells()
        lab.js("document.querySelector('.rikin-still').scrollIntoView({block: 'start'});")
        lab.screenshot("1-chapter-after-first-run-all")
        _check_first_run(lab, cells, base, published.manifest["version"])
        _check_figure_buttons(lab)
        lab.reload()
        lab.run_cell("widgets.ik_panel(arm)", timeout=300)
        _check_live_panel(lab)
        lab.open(f"{EXERCISE}.ipynb")
        cells = lab.run_all(timeout=600)
        lab.js("""const e = document.querySelector(
            '.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.error"]');
            if (e) { e.scrollIntoView({block: 'center'}); }""")
        lab.screenshot("4-exercise-after-run-all-its-first-unfinished-task")
        _check_exercise(cells, published.manifest["version"])


def _check_first_run(lab, cells: list[dict], base: str, version: str) -> None:
    assert cells and all(re.fullmatch(r"\[\d+\]:", c["prompt"]) or (c["hidden"] and c["outputs"])
                         for c in cells), (
        "Run All did not run every cell: " + str([c["prompt"] for c in cells]))
    assert not _errors(cells), "errors after the first Run All:\n" + "\n".join(_errors(cells))
    said = " ".join(o["text"] for o in cells[0]["outputs"])
    assert f"installing it from {base}{rikin_site.DIST_PATH}/" in said, said
    assert re.search(r"\[\s*\d+ s\] getting numpy", said), f"no progress: {said}"
    assert f"rikin {version} installed" in said and "reloaded once" in said, said
    figures = [o for c in cells for o in c["outputs"] if o["plotly"]]
    assert figures, "no rotatable figure was drawn"
    panels = [c for c in cells if "widgets.ik_panel(arm)" in c["source"]
              or "widgets.teach(arm)" in c["source"]]
    assert len(panels) == 2, [c["source"][:80] for c in cells]
    for cell in panels:
        (out,) = cell["outputs"]
        assert out["mime"] == "text/html" and "A still picture of the live panel" in out["text"]
        assert "VBox(" not in out["text"] and not out["widget"], out
    pictures = lab.js("""return [...document.querySelectorAll('.rikin-still img')]
        .map(i => i.naturalWidth);""")
    assert len(pictures) == 2 and all(w > 100 for w in pictures), pictures


def _check_figure_buttons(lab) -> None:
    """Click solution 2 of the first rotatable figure: the title, the traces shown and the
    pixels drawn change."""
    from selenium.webdriver.common.by import By

    fig = lab.driver.find_elements(By.CSS_SELECTOR, ".rikin-interactive.js-plotly-plot")[0]
    lab.js("arguments[0].scrollIntoView({block: 'center'});", fig)
    state = """const gd = arguments[0]; return JSON.stringify([gd.layout.title.text,
        gd.data.map(t => t.visible)]);"""
    before, pixels = lab.js(state, fig), fig.screenshot_as_png
    buttons = fig.find_elements(By.CSS_SELECTOR, ".updatemenu-button")
    labels = [b.text.strip() for b in buttons]
    assert "2" in labels, labels
    buttons[labels.index("2")].click()
    lab.wait("the figure to show solution 2", lambda: lab.js(state, fig) != before, 30)
    lab.wait("the figure's pixels to change", lambda: fig.screenshot_as_png != pixels, 30)
    assert "2:" in lab.js("return arguments[0].layout.title.text;", fig)
    lab.screenshot("2-chapter-figure-solution-2")


def _check_live_panel(lab) -> None:
    """After the reload the IK panel is a widget; typing x in its slider's readout redraws
    the drawing and changes the solution list."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    with lab.output_of("widgets.ik_panel(arm)") as cell:
        panel = lab.wait("the live panel", lambda: cell.find_elements(
            By.CSS_SELECTOR, ".widget-vbox .widget-slider"), 120)
        assert not cell.find_elements(By.CSS_SELECTOR, ".rikin-still"), "still a picture"
        look = """const c = arguments[0]; const img = c.querySelector('.widget-image');
            const table = c.querySelector('.widget-html table');
            return JSON.stringify([img ? img.src.length + img.src.slice(-200) : null,
                                   table ? table.textContent : null]);"""
        before = lab.wait("the panel's drawing and table", lambda: (
            lambda v: v if "null" not in v else None)(lab.js(look, cell)), 120)
        lab.js("arguments[0].scrollIntoView({block: 'center'});", panel[0])
        readout = panel[0].find_element(By.CSS_SELECTOR, ".widget-readout")
        readout.click()
        readout.send_keys(Keys.CONTROL, "a")
        readout.send_keys("5", Keys.ENTER)
        after = lab.wait("the panel to redraw", lambda: (
            lambda v: v if v != before and "null" not in v else None)(lab.js(look, cell)), 120)
        _check_fits(lab, cell)
        img_before, table_before = json.loads(before)
        img_after, table_after = json.loads(after)
        assert img_after != img_before, "the drawing did not change"
        assert table_after != table_before, "the solution list did not change"
        lab.screenshot("3-chapter-live-panel-after-the-reload")


def _check_fits(lab, cell) -> None:
    """Issue 28 item 7, in the browser at 1366 x 768: the panel needs no horizontal scroll
    and its drawing stays inside the notebook's column."""
    m = lab.js("""const out = arguments[0].querySelector('.jp-OutputArea-output');
        const box = out.querySelector('.widget-vbox'), img = out.querySelector('.widget-image');
        const r = el => el.getBoundingClientRect();
        return {out: out.clientWidth, outScroll: out.scrollWidth, box: box.clientWidth,
                boxScroll: box.scrollWidth, imgRight: r(img).right, outRight: r(out).right,
                imgWidth: r(img).width, window: window.innerWidth};""", cell)
    assert m["window"] >= 1300, m
    assert m["outScroll"] <= m["out"] + 1 and m["boxScroll"] <= m["box"] + 1, m
    assert m["imgRight"] <= m["outRight"] + 1 and m["imgWidth"] > 300, m


def _check_exercise(cells: list[dict], version: str) -> None:
    said = " ".join(o["text"] for o in cells[0]["outputs"])
    assert f"rikin {version} is installed" in said, said
    ran = [c for c in cells if re.fullmatch(r"\[\d+\]:", c["prompt"])]
    assert len(ran) >= 4, [c["prompt"] for c in cells]
    errors = _errors(cells)
    assert all("NotImplementedError" in e for e in errors), errors


# ------------------------------------------------------------------ launch links, the banner
@pytest.mark.book
@pytest.mark.slow
def test_every_page_warns_of_a_loopback_build_and_offers_launch_links(
        published: Published) -> None:
    """The site was built for 127.0.0.1 with the launch key set (issue 28 item 4): every
    page says it is a local preview; every page published as a notebook, and every
    exercise on the exercises page, opens in Colab and in JupyterLab on Binder."""
    import yaml

    site = published.site
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    def files(entries: list[dict]) -> list[str]:  # chapters, parts and sections, nested
        return [f for e in entries for f in ([e["file"]] if "file" in e else [])
                + files(e.get("parts", []) + e.get("chapters", []) + e.get("sections", []))]

    pages = [toc["root"], *files([toc])]
    assert len(pages) > 10 and "book/instructor/hosting" in pages, pages
    repo = rikin_site.read_launch_repository(LAUNCH_REPOSITORY)
    assert repo is not None
    for page in pages:
        text = (site / f"{page}.html").read_text(encoding="utf-8")
        assert 'class="rikin-preview-banner"' in text and published.base in text, page
        if (site / "_sources" / f"{page}.ipynb").is_file():
            for url in rikin_site.launch_links(repo, f"_sources/{page}.ipynb").values():
                assert f'href="{html.escape(url)}"' in text, (page, url)
    exercises = (site / "book" / "exercises.html").read_text(encoding="utf-8")
    for name in ("cartesian", "cylindrical", "spherical", "scara"):
        for url in rikin_site.launch_links(
                repo, f"{rikin_site.EXERCISES_PATH}/{name}.ipynb").values():
            assert f'href="{html.escape(url)}"' in exercises, (name, url)
