"""The built book works offline in a real browser.

Every page of the book is opened in headless Chromium with the network cut off (a proxy to
nowhere, every host name unresolvable), served from a local http.server on 127.0.0.1. A page
fails on:

* unrendered TeX: MathJax did not typeset every math element, reported a TeX error, or
  raw delimiters (``\\(``, ``\\[``, ``$$``, ``\\begin{``) are left in the visible text;
* a missing image (an ``img`` whose ``naturalWidth`` is 0 once loaded);
* a broken internal link (an ``a[href]`` to a local file that does not exist, or to an
  ``#anchor`` that is not an id of the target page);
* a SEVERE message in the browser console (a script error, a resource that failed to load).

And one interactive figure is operated: on the first chapter with an all-solutions
figure, clicking a solution's button must change the traces shown, the title (to that
solution's branch) and the pixels drawn, with plotly.js served by the book itself.

The book is built once per module into a temporary directory with the same strict command
as ``test_book_build.py``; set ``RIKIN_BOOK_HTML`` to an existing ``_build/html`` folder to
test that build instead. Chromium and chromedriver come from the Debian packages
``chromium`` and ``chromium-driver``; the test is skipped, saying so, only when they are not
installed.
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
PAGE_TIMEOUT_S = 60.0
MATHJAX_TIMEOUT_S = 60.0

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
DRIVERS = ("chromedriver", "chromium-driver")


def _which(names: tuple[str, ...]) -> str | None:
    for name in names:
        path = shutil.which(name) or (
            f"/usr/bin/{name}" if Path(f"/usr/bin/{name}").exists() else None
        )
        if path:
            return path
    return None


def _toc_pages() -> list[str]:
    """Every page of the book (``_toc.yml``) as an HTML path, plus Sphinx's own pages."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    files = [toc["root"]]
    for entry in toc.get("chapters", []):
        files.append(entry["file"])
        files += [sub["file"] for sub in entry.get("sections", [])]
    return [f"{f}.html" for f in files] + ["index.html", "genindex.html", "search.html"]


PAGES = _toc_pages()


# ------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def browser_paths() -> tuple[str, str]:
    browser, driver = _which(BROWSERS), _which(DRIVERS)
    if browser is None or driver is None:
        pytest.skip(
            "Chromium and chromedriver are not installed "
            "(Debian: apt-get install -y chromium chromium-driver); CI installs them"
        )
    return browser, driver


@pytest.fixture(scope="module")
def book_html(browser_paths: tuple[str, str], tmp_path_factory: pytest.TempPathFactory) -> Path:
    given = os.environ.get("RIKIN_BOOK_HTML")
    if given:
        html = Path(given)
        if not (html / "index.html").is_file():
            pytest.fail(f"RIKIN_BOOK_HTML={given} has no index.html: build the book first")
        return html
    out = tmp_path_factory.mktemp("book")
    exe = Path(sys.executable).parent / ("jupyter-book.exe" if os.name == "nt" else "jupyter-book")
    env = dict(os.environ, PYTHONHASHSEED="0", JUPYTER_PREFER_ENV_PATH="1")
    env.setdefault("MPLBACKEND", "Agg")
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    proc = subprocess.run(
        [
            str(exe),
            "build",
            str(ROOT),
            "--path-output",
            str(out),
            "--all",
            "-W",
            "-n",
            "--keep-going",
        ],
        cwd=out,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=1800,
    )
    assert proc.returncode == 0, f"book build failed ({proc.returncode}):\n{proc.stdout[-20000:]}"
    return out / "_build" / "html"


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:  # noqa: A002
        pass


@pytest.fixture(scope="module")
def server(book_html: Path) -> Iterator[str]:
    handler = functools.partial(_QuietHandler, directory=str(book_html))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()
        httpd.server_close()


@pytest.fixture(scope="module")
def driver(browser_paths: tuple[str, str]) -> Iterator[object]:
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        pytest.fail(
            "the browser test needs the PyPI package selenium (pip install 'selenium>=4.15,<5')"
        )
    browser, chromedriver = browser_paths
    opts = webdriver.ChromeOptions()
    opts.binary_location = browser
    for flag in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        "--disable-default-apps",
        "--window-size=1280,900",
        # the network is off: every request that is not to 127.0.0.1 goes nowhere
        "--proxy-server=127.0.0.1:9",
        "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE localhost , EXCLUDE 127.0.0.1",
    ):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    drv = webdriver.Chrome(service=Service(executable_path=chromedriver), options=opts)
    drv.set_page_load_timeout(PAGE_TIMEOUT_S)
    drv.set_script_timeout(MATHJAX_TIMEOUT_S)
    try:
        yield drv
    finally:
        drv.quit()


# ------------------------------------------------------------------ page checks
_WAIT_MATHJAX = """
const done = arguments[arguments.length - 1];
const start = Date.now();
(function poll() {
  const mj = window.MathJax;
  if (mj && mj.startup && mj.startup.promise) {
    mj.startup.promise.then(() => done("ok")).catch(e => done("MathJax failed: " + e));
  } else if (Date.now() - start > 20000) {
    done("MathJax never started (the script did not load)");
  } else {
    setTimeout(poll, 50);
  }
})();
"""

_MATH_STATE = """
const maths = Array.from(document.querySelectorAll('.math'));
const untypeset = maths.filter(m => !m.querySelector('mjx-container'))
                       .map(m => m.textContent.trim().slice(0, 80));
const errors = Array.from(document.querySelectorAll('mjx-merror'))
                    .map(e => e.getAttribute('data-mjx-error') || e.textContent.slice(0, 80));
const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT, {
  acceptNode(node) {
    for (let el = node.parentElement; el; el = el.parentElement) {
      const tag = el.tagName;
      if (['PRE', 'CODE', 'SCRIPT', 'STYLE', 'TEXTAREA', 'MJX-CONTAINER'].includes(tag)) {
        return NodeFilter.FILTER_REJECT;
      }
    }
    return NodeFilter.FILTER_ACCEPT;
  }
});
const raw = [];
for (let n = walker.nextNode(); n; n = walker.nextNode()) {
  const t = n.textContent;
  if (/\\\\\\(|\\\\\\)|\\\\\\[|\\\\\\]|\\$\\$|\\\\begin\\{/.test(t)) {
    raw.push(t.trim().slice(0, 80));
  }
}
return {n_math: maths.length, n_typeset: document.querySelectorAll('mjx-container').length,
        untypeset: untypeset, errors: errors, raw: raw};
"""

_IMAGES = """
const imgs = Array.from(document.images);
imgs.forEach(i => { i.loading = 'eager'; i.scrollIntoView(); });
return imgs.map(i => [i.getAttribute('src'), i.complete, i.naturalWidth]);
"""

_LINKS = """
return Array.from(document.querySelectorAll('a[href]')).map(a => [a.getAttribute('href'), a.href]);
"""


def _ids_of(html_file: Path) -> set[str]:
    text = html_file.read_text(encoding="utf-8", errors="replace")
    return set(re.findall(r'\bid="([^"]+)"', text)) | set(re.findall(r'\bname="([^"]+)"', text))


def _check_links(links: list[list[str]], origin: str, html: Path, page: str) -> list[str]:
    problems = []
    ids_cache: dict[Path, set[str]] = {}
    for raw, absolute in links:
        if raw.startswith(("javascript:", "mailto:", "tel:")) or not absolute.startswith(
            origin + "/"
        ):
            continue  # not a link into the book (external links cannot be followed offline)
        parts = urlsplit(absolute)
        target = html / unquote(parts.path).lstrip("/")
        if target.is_dir():
            target = target / "index.html"
        if not target.is_file():
            problems.append(f"{page}: link {raw!r} -> {target.relative_to(html)} does not exist")
            continue
        if parts.fragment and target.suffix == ".html":
            ids = ids_cache.setdefault(target, _ids_of(target))
            if unquote(parts.fragment) not in ids:
                problems.append(
                    f"{page}: link {raw!r}: no id {parts.fragment!r} in {target.relative_to(html)}"
                )
    return problems


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", PAGES)
def test_page_renders_offline(page: str, book_html: Path, server: str, driver: object) -> None:
    assert (book_html / page).is_file(), f"{page} was not built"
    driver.get_log("browser")  # drop messages of earlier pages
    driver.get(f"{server}/{page}")
    deadline = time.monotonic() + PAGE_TIMEOUT_S
    while driver.execute_script("return document.readyState") != "complete":
        assert time.monotonic() < deadline, f"{page} did not finish loading"
        time.sleep(0.05)
    problems: list[str] = []

    has_math_script = bool(
        driver.execute_script(
            "return Array.from(document.scripts).some(s => /mathjax/i.test(s.src))"
        )
    )
    if has_math_script:
        status = driver.execute_async_script(_WAIT_MATHJAX)
        if status != "ok":
            problems.append(f"{page}: {status}")
    math = driver.execute_script(_MATH_STATE)
    if math["n_math"] and not has_math_script:
        problems.append(f"{page}: {math['n_math']} math elements but no MathJax script")
    if math["n_math"] and math["n_typeset"] == 0:
        problems.append(f"{page}: MathJax typeset nothing (no mjx-container)")
    problems += [f"{page}: math not typeset: {t!r}" for t in math["untypeset"]]
    problems += [f"{page}: MathJax TeX error: {e!r}" for e in math["errors"]]
    problems += [f"{page}: raw TeX left in the text: {t!r}" for t in math["raw"]]

    driver.execute_script(_IMAGES)
    time.sleep(0.2)
    deadline = time.monotonic() + 10
    images = driver.execute_script(_IMAGES)
    while not all(done for _, done, _ in images) and time.monotonic() < deadline:
        time.sleep(0.1)
        images = driver.execute_script(_IMAGES)
    problems += [
        f"{page}: image not loaded: {src!r}"
        for src, done, width in images
        if not done or width == 0
    ]

    problems += _check_links(driver.execute_script(_LINKS), server, book_html, page)

    severe = [e["message"] for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
    problems += [f"{page}: console error: {m}" for m in severe]
    assert not problems, "\n".join(problems)


@pytest.mark.book
@pytest.mark.slow
def test_chapters_have_math_and_figures(book_html: Path, server: str, driver: object) -> None:
    """The checks above are not vacuous: the chapters do have typeset math and figures."""
    driver.get(f"{server}/book/decoupling.html")
    assert driver.execute_async_script(_WAIT_MATHJAX) == "ok"
    math = driver.execute_script(_MATH_STATE)
    images = driver.execute_script(_IMAGES)
    assert math["n_typeset"] >= 10, math
    assert len(images) >= 2 and all(w > 0 for _, _, w in images), images


# ------------------------------------------------------------------ layout: fits the column
#: The widths the layout is checked at: a laptop window and a phone.
DESKTOP_PX = 1280
PHONE_PX = 390

_OVERFLOW = r"""
// open every folded cell and dropdown: what a reader unfolds must fit too
document.querySelectorAll('details').forEach(d => { d.open = true; });
document.querySelectorAll('.toggle-hidden, .toggle-details').forEach(
  el => el.classList.remove('toggle-hidden'));
const column = document.querySelector('article.bd-article') || document.querySelector('main');
const col = column.getBoundingClientRect();
// inline math measures wider than its box by its glyphs' overhang; display math is checked
const internal = el => el.closest('mjx-assistive-mml, .headerlink, script, style, '
                                  + '.modebar-container, .plotly .main-svg defs, '
                                  + 'mjx-container:not([display="true"]), span.math');
const scrolls = el => ['auto', 'scroll', 'hidden', 'clip'].includes(
  getComputedStyle(el).overflowX);
const kind = el => {
  if (el.matches('.math, mjx-container') || el.querySelector('mjx-container[display]'))
    return 'equation';
  if (el.matches('table') || el.querySelector(':scope > table')) return 'table';
  if (el.closest('.cell_input')) return 'input cell';
  if (el.closest('.cell_output, .output')) return 'output';
  if (el.matches('pre, div.highlight')) return 'code block';
  if (el.matches('img, svg, canvas, .rikin-interactive')) return 'figure';
  return el.tagName.toLowerCase();
};
const describe = (el, why) => ({kind: kind(el), why: why,
  text: (el.textContent || el.getAttribute('src') || '').trim().replace(/\s+/g, ' ')
          .slice(0, 70)});
const insideScroller = el => {
  for (let p = el.parentElement; p && p !== column; p = p.parentElement) {
    if (scrolls(p)) return true;
  }
  return false;
};
const found = [];
const flagged = [];
const under = el => flagged.some(f => f.contains(el));
// (a) a box that scrolls (or clips) sideways because its content is wider than it
for (const el of column.querySelectorAll('*')) {
  if (internal(el) || !scrolls(el) || el.clientWidth === 0) continue;
  if (el.scrollWidth > el.clientWidth + 1 && !under(el)) {
    flagged.push(el);
    found.push(describe(el, `content ${el.scrollWidth}px in a ${el.clientWidth}px box`));
  }
}
// (b) a block that sticks out of the column (not inside a box that scrolls)
const blocks = column.querySelectorAll(
  'pre, div.highlight, table, img, svg, canvas, div.math, mjx-container[display="true"], '
  + '.rikin-interactive, .cell, .cell_output, figure, p, li, dl, blockquote, .admonition');
for (const el of blocks) {
  if (internal(el) || under(el) || insideScroller(el)) continue;
  const r = el.getBoundingClientRect();
  if (r.width === 0 || r.height === 0) continue;
  if (r.right > col.right + 1 || r.left < col.left - 1) {
    flagged.push(el);
    found.push(describe(el, `${Math.round(r.width)}px wide, sticks out of the `
                            + `${Math.round(col.width)}px column`));
  }
}
return {column: Math.round(col.width), page: document.documentElement.scrollWidth,
        viewport: window.innerWidth, found: found};
"""


def _open(driver: object, url: str) -> None:
    driver.get(url)
    deadline = time.monotonic() + PAGE_TIMEOUT_S
    while driver.execute_script("return document.readyState") != "complete":
        assert time.monotonic() < deadline, f"{url} did not finish loading"
        time.sleep(0.05)
    if driver.execute_script("return !!window.MathJax"):
        driver.execute_async_script(_WAIT_MATHJAX)
    driver.execute_script(_IMAGES)


def _set_width(driver: object, px: int) -> None:
    driver.set_window_size(px, 900)
    # the window's outer size includes no chrome in headless mode; make sure
    inner = driver.execute_script("return window.innerWidth")
    if inner != px:
        driver.set_window_size(px + (px - inner), 900)


CHAPTER_PAGES = [p for p in PAGES if p.startswith("book/")]


# ------------------------------------------------------------------ an interactive figure, operated
_FIGURE_STATE = r"""
const el = document.querySelector('.rikin-interactive');
if (!el || !el._fullLayout) return null;
const title = el._fullLayout.title ? el._fullLayout.title.text : '';
return {title: title, visible: el.data.map(t => t.visible === true),
        buttons: Array.from(el.querySelectorAll('g.updatemenu-button')).map(
            b => b.textContent.trim())};
"""


@pytest.mark.book
@pytest.mark.slow
def test_interactive_figure_steps_through_the_solutions(book_html: Path, server: str,
                                                        driver: object) -> None:
    """Click a solution button of the all-solutions figure: a different arm is drawn."""
    from selenium.webdriver.common.by import By

    pages = [p for p in CHAPTER_PAGES
             if "rikin-interactive-solutions" in (book_html / p).read_text(encoding="utf-8")]
    assert pages, "no chapter has an interactive all-solutions figure"
    assert (book_html / "_static" / "plotly" / "plotly.min.js").is_file()
    page = pages[0]
    _set_width(driver, DESKTOP_PX)
    driver.get_log("browser")
    _open(driver, f"{server}/{page}")
    scripts = driver.execute_script("return Array.from(document.scripts).map(s => s.src)")
    assert any("/_static/plotly/plotly.min.js" in s for s in scripts), scripts
    deadline = time.monotonic() + 30
    state = None
    while state is None and time.monotonic() < deadline:
        state = driver.execute_script(_FIGURE_STATE)
        time.sleep(0.1)
    assert state is not None, f"{page}: the interactive figure was never drawn (plotly.js?)"
    fig = driver.find_element(By.CSS_SELECTOR, ".rikin-interactive")
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", fig)
    time.sleep(0.5)
    before_png = fig.screenshot_as_png
    before = driver.execute_script(_FIGURE_STATE)
    assert before["buttons"][:2] == ["1", "2"], before["buttons"]
    target = "3" if "3" in before["buttons"] else "2"
    (button,) = [b for b in fig.find_elements(By.CSS_SELECTOR, "g.updatemenu-button")
                 if b.text.strip() == target]
    button.click()
    deadline = time.monotonic() + 10
    after = driver.execute_script(_FIGURE_STATE)
    while after["visible"] == before["visible"] and time.monotonic() < deadline:
        time.sleep(0.1)
        after = driver.execute_script(_FIGURE_STATE)
    time.sleep(0.5)
    after_png = fig.screenshot_as_png
    assert after["visible"] != before["visible"], "clicking the button changed no trace"
    assert after["title"] != before["title"] and after["title"].split("<br>")[1].startswith(
        f"{target}:"), after["title"]
    assert after_png != before_png, "the drawing did not change"
    severe = [e["message"] for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
    assert not severe, severe
