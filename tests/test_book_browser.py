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

Every chapter is also laid out at two widths, with every folded cell and dropdown opened:

* at 1280 px every code cell, output, table, display equation and figure fits the text
  column: none scrolls sideways inside its box, none sticks out of the column, none is cut
  by ``overflow: hidden``, and the page does not scroll sideways;
* at 390 px (a phone) the page does not scroll sideways and nothing sticks out or is cut;
  a wide table, code block or equation may scroll inside its own box there (never a whole
  section or cell). ``test_the_layout_check_finds_what_does_not_fit`` shows the check
  catching each kind of defect.

And one interactive figure is operated: on the first chapter with an all-solutions
figure, clicking a solution's button must change the traces shown, the title (to that
solution's branch) and the pixels drawn, with plotly.js served by the book itself.

The book is the test session's one strict build (``book_site`` in conftest.py, shared with
``test_book_build.py`` and ``test_student_download.py``: a loopback base URL, the launch key
set); set ``RIKIN_BOOK_HTML`` to an existing ``_build/html`` folder to test that build
instead. Chromium and chromedriver come from the Debian packages ``chromium`` and
``chromium-driver`` (``tools/dev.py test`` installs them as root); without
them these tests fail, saying how to install them (never skip).
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import shutil
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
import yaml
from book_build import Site

ROOT = Path(__file__).resolve().parents[1]
#: Hang guards, not speed checks: a heavy page (the C4 chapter's interactive figures) took
#: over 60 s to load with both CPUs busy (load 20), and the suite must pass there.
PAGE_TIMEOUT_S = 300.0
MATHJAX_TIMEOUT_S = 180.0

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
    parts = toc.get("parts") or [{"chapters": toc.get("chapters", [])}]
    for entry in (c for part in parts for c in part["chapters"]):
        files.append(entry["file"])
        files += [sub["file"] for sub in entry.get("sections", [])]
    return [f"{f}.html" for f in files] + ["index.html", "genindex.html", "search.html"]


PAGES = _toc_pages()


# ------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def browser_paths() -> tuple[str, str]:
    browser, driver = _which(BROWSERS), _which(DRIVERS)
    if browser is None or driver is None:
        pytest.fail(
            "Chromium and chromedriver are not installed: the book's browser tests need them "
            "(Debian: apt-get install -y chromium chromium-driver; tools/dev.py test installs "
            "them when run as root)"
        )
    return browser, driver


@pytest.fixture(scope="module")
def book_html(browser_paths: tuple[str, str], request: pytest.FixtureRequest) -> Path:
    given = os.environ.get("RIKIN_BOOK_HTML")
    if given:
        html = Path(given)
        if not (html / "index.html").is_file():
            pytest.fail(f"RIKIN_BOOK_HTML={given} has no index.html: build the book first")
        return html
    # the session's one strict build (tests/book_build.py), asked for only when needed
    site: Site = request.getfixturevalue("book_site")
    assert site.returncode == 0, f"book build failed ({site.returncode}):\n{site.log[-20000:]}"
    return Path(site.html)


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
    drv = chrome(browser_paths)
    try:
        yield drv
    finally:
        drv.quit()


def chrome(browser_paths: tuple[str, str], page_load_strategy: str = "normal") -> object:
    """Headless Chromium at 1280 px with the network cut off (Selenium's driver of it);
    ``page_load_strategy`` is Selenium's (``"eager"``: a navigation is done once the page is
    parsed, without waiting for its images and scripts)."""
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
    opts.page_load_strategy = page_load_strategy
    drv = webdriver.Chrome(service=Service(executable_path=chromedriver), options=opts)
    drv.set_page_load_timeout(PAGE_TIMEOUT_S)
    drv.set_script_timeout(MATHJAX_TIMEOUT_S)
    return drv


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


#: A line of the page (code blocks included) that is a directive's fence: MyST that did not
#: parse (e.g. a backtick in a backtick fence's title) and is shown to the reader as is.
_RAW_MARKUP = r"""
const article = document.querySelector('article') || document.body;
return article.innerText.split('\n').filter(l => /^\s*(`{3,}|:{3,}|~{3,})\{[a-z-]+\}/.test(l))
              .map(l => l.trim().slice(0, 80));
"""


#: Output text a reader should never see: 0.30000000000000004 or 0.4999999999999999 (a
#: float printed unformatted), np.float64(...) / np.int64(...) (a numpy scalar's repr),
#: a negative zero (-0.0, -0.).
_NOISY_NUMBERS = r"""
const out = [];
const noise = new RegExp([String.raw`\d\.\d*(?:0{9,}[1-9]|9{9,}\d)`,
                          String.raw`np\.(?:float|int)\d+\(`,
                          String.raw`(?:^|[\s,(\[/])-0(?:\.0*)?(?=$|[\s,)\]/°])`].join('|'));
for (const el of document.querySelectorAll('.cell_output, .output')) {
  for (const line of el.innerText.split('\n')) {
    if (noise.test(line)) out.push(line.trim().slice(0, 80));
  }
}
return Array.from(new Set(out));
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


def _offline_state(driver: object, server: str, book_html: Path, page: str) -> dict:
    """What ``test_page_renders_offline`` reads of the page just loaded: MathJax's status,
    the math, the images (right after MathJax, then once loaded), the links, the markup,
    the outputs' numbers and the console's SEVERE messages."""
    has_math_script = bool(
        driver.execute_script(
            "return Array.from(document.scripts).some(s => /mathjax/i.test(s.src))"
        )
    )
    status = driver.execute_async_script(_WAIT_MATHJAX) if has_math_script else None
    math = driver.execute_script(_MATH_STATE)
    first_images = driver.execute_script(_IMAGES)
    time.sleep(0.2)
    deadline = time.monotonic() + 10
    images = driver.execute_script(_IMAGES)
    while not all(done for _, done, _ in images) and time.monotonic() < deadline:
        time.sleep(0.1)
        images = driver.execute_script(_IMAGES)
    links = _check_links(driver.execute_script(_LINKS), server, book_html, page)
    markup = driver.execute_script(_RAW_MARKUP)
    noisy = driver.execute_script(_NOISY_NUMBERS)
    severe = [e["message"] for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
    return {"has_math_script": has_math_script, "mathjax": status, "math": math,
            "first_images": first_images, "images": images, "links": links,
            "markup": markup, "noisy": noisy, "severe": severe}


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", PAGES)
def test_page_renders_offline(page: str, book_html: Path, loaded: LoadedPages) -> None:
    assert (book_html / page).is_file(), f"{page} was not built"
    state = loaded.desktop(page)["offline"]
    problems: list[str] = []

    has_math_script = state["has_math_script"]
    if has_math_script:
        status = state["mathjax"]
        if status != "ok":
            problems.append(f"{page}: {status}")
    math = state["math"]
    if math["n_math"] and not has_math_script:
        problems.append(f"{page}: {math['n_math']} math elements but no MathJax script")
    if math["n_math"] and math["n_typeset"] == 0:
        problems.append(f"{page}: MathJax typeset nothing (no mjx-container)")
    problems += [f"{page}: math not typeset: {t!r}" for t in math["untypeset"]]
    problems += [f"{page}: MathJax TeX error: {e!r}" for e in math["errors"]]
    problems += [f"{page}: raw TeX left in the text: {t!r}" for t in math["raw"]]

    images = state["images"]
    problems += [
        f"{page}: image not loaded: {src!r}"
        for src, done, width in images
        if not done or width == 0
    ]

    problems += state["links"]

    markup = state["markup"]
    problems += [f"{page}: MyST markup shown as text (a broken directive): {t!r}"
                 for t in markup]
    problems += [f"{page}: an output shows a number's rounding noise or its numpy type: {t!r}"
                 for t in state["noisy"]]

    severe = state["severe"]
    problems += [f"{page}: console error: {m}" for m in severe]
    assert not problems, "\n".join(problems)


@pytest.mark.book
@pytest.mark.slow
def test_chapters_have_math_and_figures(loaded: LoadedPages) -> None:
    """The checks above are not vacuous: the chapters do have typeset math and figures."""
    state = loaded.desktop("book/decoupling.html")["offline"]
    assert state["mathjax"] == "ok"
    math = state["math"]
    images = state["first_images"]
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
// the inside of a typeset formula, a plotly drawing or a heading's link is not a box of
// the text; inline math measures wider than its box by its glyphs' overhang (display
// math is checked)
const internal = el => el.closest('mjx-assistive-mml, .headerlink, script, style, '
                                  + '.modebar-container, .js-plotly-plot .plot-container, '
                                  + 'mjx-container:not([display="true"]), '
                                  + 'mjx-container[display="true"] *, span.math');
const overflowX = el => getComputedStyle(el).overflowX;
const scrolls = el => ['auto', 'scroll'].includes(overflowX(el));
const clips = el => ['hidden', 'clip'].includes(overflowX(el));
const kind = el => {
  if (el.matches('mjx-container:not([display="true"])')) return 'inline math';
  if (el.matches('.math, mjx-container') || el.querySelector('mjx-container[display]'))
    return 'equation';
  if (el.matches('table') || el.querySelector('table')) return 'table';
  if (el.closest('.cell_input')) return 'input cell';
  if (el.closest('.cell_output, .output')) return 'output';
  if (el.matches('pre, div.highlight') || el.querySelector('pre')) return 'code block';
  if (el.matches('img, svg, canvas, .rikin-interactive') || el.querySelector('img, svg'))
    return 'figure';
  return el.tagName.toLowerCase();
};
// a box that scrolls sideways is the box of ONE table, code block, equation or figure,
// not a section or a whole cell made to scroll so that everything in it passes
const ownBox = el => !el.matches('section, .cell, article, main')
  && !el.querySelector('h1, h2, h3, h4, h5, h6, section, .cell, p + p');
const describe = (el, why) => ({kind: kind(el), why: why, own: ownBox(el),
  text: (el.textContent || el.getAttribute('src') || '').trim().replace(/\s+/g, ' ')
          .slice(0, 70)});
const insideScroller = el => {
  for (let p = el.parentElement; p && p !== column; p = p.parentElement) {
    if (scrolls(p)) return true;
  }
  return false;
};
const scrolled = [], clipped = [], out = [];
const seen = [];
const under = el => seen.some(f => f !== el && f.contains(el));
// (a) a box whose content is wider than it: it scrolls sideways (or hides what is wider)
for (const el of column.querySelectorAll('*')) {
  if (internal(el) || el.clientWidth === 0) continue;
  if (!(scrolls(el) || clips(el)) || el.scrollWidth <= el.clientWidth + 1 || under(el)) continue;
  seen.push(el);
  const why = `content ${el.scrollWidth}px in a ${el.clientWidth}px box`;
  (scrolls(el) ? scrolled : clipped).push(describe(el, why));
}
// (b) a block that sticks out of the column (not inside a box that scrolls), and inline
// math that does (MathJax does not break a formula inside a line: one wider than the
// column is cut off at its edge); a glyph may overhang its box by a pixel or two
const inlineMath = 'mjx-container:not([display="true"])';
const blocks = column.querySelectorAll(
  'pre, div.highlight, table, img, svg, canvas, div.math, mjx-container[display="true"], '
  + '.rikin-interactive, .cell, .cell_output, figure, p, li, dl, blockquote, .admonition, '
  + inlineMath);
for (const el of blocks) {
  const inline = el.matches(inlineMath);
  if ((!inline && internal(el)) || under(el) || insideScroller(el)) continue;
  if (inline && el.parentElement.closest('mjx-assistive-mml, mjx-container')) continue;
  const r = el.getBoundingClientRect();
  if (r.width === 0 || r.height === 0) continue;
  const slack = inline ? 3 : 1;
  // cut at the edge of a box that hides what is wider (an admonition does)
  let clipper = null;
  for (let p = el.parentElement; p && p !== column && !clipper; p = p.parentElement) {
    if (clips(p)) clipper = p;
  }
  if (clipper && !clipper.matches('mjx-container')) {
    const c = clipper.getBoundingClientRect();
    if (r.right > c.right + slack || r.left < c.left - slack) {
      seen.push(el);
      clipped.push(describe(el, `${Math.round(r.width)}px wide, cut at the edge of its `
                                + `${Math.round(c.width)}px box`));
      continue;
    }
  }
  if (r.right > col.right + slack || r.left < col.left - slack) {
    seen.push(el);
    out.push(describe(el, `${Math.round(r.width)}px wide, sticks out of the `
                          + `${Math.round(col.width)}px column`));
  }
}
return {column: Math.round(col.width), page: document.documentElement.scrollWidth,
        viewport: window.innerWidth, scrolled: scrolled, clipped: clipped, out: out,
        n_checked: blocks.length};
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
    """Make the page ``px`` CSS pixels wide (``window.innerWidth``). Headless Chromium's
    window has no chrome, so the outer width is usually it; where it is not, the outer
    width is corrected by the difference, read once the resize has reached the page (on a
    busy machine the page may still report its old width just after the resize)."""
    outer = px
    for _ in range(3):
        driver.set_window_size(outer, 900)
        inner = _settled_inner_width(driver, outer)
        if inner == px:
            return
        outer += px - inner
        assert outer > 0, f"cannot make the page {px} px wide (it is {inner} px)"
    raise AssertionError(f"the page is {inner} px wide after three resizes, not {px}")


def _settled_inner_width(driver: object, outer: int) -> int:
    """``window.innerWidth`` once the resize to ``outer`` has reached the page: no wider
    than the window and the same on two reads 0.1 s apart (PAGE_TIMEOUT_S at most)."""
    deadline = time.monotonic() + PAGE_TIMEOUT_S
    last = None
    while True:
        inner = driver.execute_script("return window.innerWidth")
        if inner == last and inner <= outer:
            return int(inner)
        assert time.monotonic() < deadline, f"the page did not take the width {outer} px"
        last = inner
        time.sleep(0.1)


CHAPTER_PAGES = [p for p in PAGES if p.startswith("book/")]
#: The course's chapters (the instructor's guide is prose and screenshots for teachers).
COURSE_PAGES = [p for p in CHAPTER_PAGES if not p.startswith("book/instructor/")]



def _layout_problems(page: str, px: int, state: dict, *, may_scroll: bool) -> list[str]:
    """What a reader at ``px`` wide would find cut off, hidden or sticking out."""
    at = f"{page} at {px}px"
    problems = []
    if state["page"] > state["viewport"] + 1:
        problems.append(f"{at}: the page is {state['page']}px wide for a {state['viewport']}px "
                        "window: it scrolls sideways")
    problems += [f"{at}: {f['kind']} hidden (overflow hidden): {f['why']}: {f['text']!r}"
                 for f in state["clipped"]]
    problems += [f"{at}: {f['kind']} {f['why']}: {f['text']!r}" for f in state["out"]]
    for f in state["scrolled"]:
        if not may_scroll:
            problems.append(f"{at}: {f['kind']} does not fit the column, it scrolls "
                            f"sideways: {f['why']}: {f['text']!r}")
        elif not f["own"]:
            problems.append(f"{at}: a whole block of the text scrolls sideways, not one "
                            f"{f['kind']} in its own box: {f['why']}: {f['text']!r}")
    return problems


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", CHAPTER_PAGES)
def test_nothing_is_wider_than_the_column(page: str, loaded: LoadedPages) -> None:
    """Every folded cell and dropdown opened: at 1280 px every code cell, output, table,
    display equation and figure fits the text column (none scrolls sideways, none sticks
    out, none is cut by ``overflow: hidden``); at 390 px (a phone) the page never scrolls
    sideways and nothing sticks out or is cut, though a wide table, code block or
    equation may scroll inside its own box."""
    desk = loaded.desktop(page)["overflow"]
    phone = loaded.desktop(page)["overflow_resized"]
    assert desk["viewport"] == DESKTOP_PX and phone["viewport"] == PHONE_PX, (desk, phone)
    assert desk["column"] > 500, f"{page}: the text column is only {desk['column']}px at 1280"
    assert phone["column"] < PHONE_PX, f"{page}: the column is {phone['column']}px on a phone"
    assert desk["n_checked"] > 0, f"{page}: no block of text was found to check"
    problems = _layout_problems(page, DESKTOP_PX, desk, may_scroll=False)
    problems += _layout_problems(page, PHONE_PX, phone, may_scroll=True)
    assert not problems, "\n".join(problems)



_INJECT_BAD_LAYOUT = r"""
const sec = document.querySelector('article.bd-article section');
const add = html => { const d = document.createElement('div'); d.innerHTML = html;
                      sec.appendChild(d.firstElementChild); };
add('<div class="rikin-table-wrap" style="overflow-x:auto"><table id="t-scroll">'
    + '<tr><td style="white-space:nowrap">' + 'scrolling table '.repeat(80)
    + '</td></tr></table></div>');
add('<pre id="t-hidden" style="overflow-x:hidden; white-space:pre">'
    + 'hidden code '.repeat(80) + '</pre>');
add('<table id="t-out"><tr><td style="white-space:nowrap">'
    + 'sticking-out table '.repeat(80) + '</td></tr></table>');
add('<p>a formula in a line: <mjx-container id="t-inline" style="display:inline-block;'
    + 'white-space:nowrap">' + 'x + '.repeat(200) + 'y</mjx-container></p>');
add('<section id="t-section" style="overflow-x:auto"><h3>a heading</h3><p>text</p>'
    + '<p style="white-space:nowrap">' + 'a whole scrolling section '.repeat(60)
    + '</p></section>');
"""

#: A formula in a line, typeset by the page's MathJax, wider than its 200 px column: the
#: theme's ``span.math`` shrinks to the line and hides the rest (its own box is not
#: checked: inline glyphs overhang it), so only the formula's edges show that it is cut.
_INJECT_CUT_FORMULA = r"""
const done = arguments[arguments.length - 1];
const box = document.createElement('div');
box.style.cssText = 'width:200px';
box.innerHTML = '<ol><li><p>in a box: <span class="math notranslate nohighlight">\\('
                + 'z + '.repeat(40) + 'w\\)</span></p></li></ol>';
document.querySelector('article.bd-article section').appendChild(box);
MathJax.typesetPromise([box]).then(() => done(box.querySelector('mjx-container') ? 'ok'
                                                : 'not typeset')).catch(e => done(String(e)));
"""


@pytest.mark.book
@pytest.mark.slow
def test_the_layout_check_finds_what_does_not_fit(book_html: Path, server: str,
                                                  driver: object) -> None:
    """The check above is not vacuous: a page given a table that scrolls, code cut by
    ``overflow: hidden``, a table and a formula in a line sticking out, and a whole section
    made to scroll fails, each for its own reason, at both widths."""
    page = "book/planar.html"
    try:
        for px in (DESKTOP_PX, PHONE_PX):
            _set_width(driver, px)
            _open(driver, f"{server}/{page}")
            driver.execute_script(_INJECT_BAD_LAYOUT)
            assert driver.execute_async_script(_INJECT_CUT_FORMULA) == "ok"
            time.sleep(0.2)
            problems = "\n".join(_layout_problems(page, px, driver.execute_script(_OVERFLOW),
                                                  may_scroll=px == PHONE_PX))
            assert "hidden (overflow hidden)" in problems and "hidden code" in problems
            assert "sticks out of the" in problems and "sticking-out table" in problems
            assert "it scrolls sideways" in problems  # the page itself, for the wide table
            assert "a whole scrolling section" in problems
            assert "inline math " in problems and "x + x + x" in problems
            assert "inline math hidden (overflow hidden)" in problems
            assert re.search(r"inline math hidden \(overflow hidden\): \d+px wide, cut at "
                             r"the edge of its 1\d\dpx box: 'z\+z\+z", problems), problems
            if px == DESKTOP_PX:
                assert "table does not fit the column, it scrolls sideways" in problems
                assert "scrolling table" in problems
            else:  # on a phone one table may scroll in its own box, a section may not
                assert "scrolling table" not in problems, problems
                assert "a whole block of the text scrolls sideways" in problems
    finally:
        _set_width(driver, DESKTOP_PX)


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


# ------------------------------------------------------------------ figures a reader can read
#: The smallest text a figure may show in the 1280 px layout (CSS px of its font size).
MIN_FIGURE_TEXT_PX = 9.0

#: Every figure image of the article: its source, shown width, and for an SVG the size of
#: each text in CSS px on the page (the font size in the SVG's own units times the image's
#: shown width over the SVG's width). A PNG's text cannot be measured (and blurs when the
#: image is shrunk): figures are SVG with their text kept as text.
_FIGURE_TEXT = r"""
const done = arguments[arguments.length - 1];
const column = document.querySelector('article.bd-article') || document.querySelector('main');
const imgs = Array.from(column.querySelectorAll('img'))
  .filter(i => i.getBoundingClientRect().width > 0);
const sizeOf = style => {
  const m = /font-size:\s*([\d.]+)px/.exec(style || '')
         || /font:\s*(?:[a-z-]+\s+)*([\d.]+)px/.exec(style || '');
  return m ? parseFloat(m[1]) : NaN;
};
(async () => {
  const out = [];
  for (const img of imgs) {
    const src = img.currentSrc || img.src;
    const shown = img.getBoundingClientRect().width;
    const item = {src: img.getAttribute('src'), alt: img.getAttribute('alt') || '',
                  shown: Math.round(shown), svg: /\.svg([?#]|$)/i.test(src), texts: 0,
                  min: null, smallest: ''};
    if (item.svg) {
      const doc = new DOMParser().parseFromString(await (await fetch(src)).text(),
                                                  'image/svg+xml');
      const svg = doc.documentElement;
      const vb = (svg.getAttribute('viewBox') || '').trim().split(/[\s,]+/).map(Number);
      const width = vb.length === 4 ? vb[2] : parseFloat(svg.getAttribute('width'));
      for (const t of doc.querySelectorAll('text')) {
        if (!t.textContent.trim()) continue;
        let size = sizeOf(t.getAttribute('style'));
        if (!isFinite(size)) size = parseFloat(t.getAttribute('font-size'));
        if (!isFinite(size)) continue;
        const px = size * shown / width;
        item.texts++;
        if (item.min === null || px < item.min) {
          item.min = px; item.smallest = t.textContent.trim().slice(0, 40);
        }
      }
    }
    out.push(item);
  }
  // the interactive figures are drawn in the page: their text is measured directly
  for (const fig of column.querySelectorAll('.rikin-interactive')) {
    for (const t of fig.querySelectorAll('svg text')) {
      const r = t.getBoundingClientRect();
      if (!t.textContent.trim() || r.width === 0) continue;
      const px = parseFloat(getComputedStyle(t).fontSize);
      out.push({src: 'interactive ' + fig.id, alt: 'an interactive figure in the page',
                shown: 0, svg: true, texts: 1, min: px,
                smallest: t.textContent.trim().slice(0, 40)});
    }
  }
  done(out);
})().catch(e => done(String(e)));
"""


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", COURSE_PAGES)
def test_figure_text_is_readable_at_1280(page: str, loaded: LoadedPages) -> None:
    """At 1280 px every figure is an SVG whose text is text, and no text of it, shrunk or
    not to the column, is smaller than MIN_FIGURE_TEXT_PX; every figure has alt text."""
    figures = loaded.desktop(page)["figure_text"]
    assert isinstance(figures, list), figures
    problems = []
    for f in figures:
        name = f["src"]
        if not f["svg"]:
            problems.append(f"{page}: {name} is a raster image: its text cannot be measured "
                            "and blurs when shrunk (draw it as SVG: rikin.plot.book_style())")
        elif f["texts"] == 0:
            problems.append(f"{page}: {name} has no text elements (text drawn as outlines?)")
        elif f["min"] < MIN_FIGURE_TEXT_PX:
            problems.append(f"{page}: {name} shown {f['shown']}px wide: text "
                            f"{f['smallest']!r} is {f['min']:.1f}px high "
                            f"(< {MIN_FIGURE_TEXT_PX})")
        if len(f["alt"].split()) < 5:
            problems.append(f"{page}: {name} has no real alt text: {f['alt']!r}")
    assert not problems, "\n".join(problems)


#: The text of every interactive figure that lies outside the figure's own box (cut off:
#: plotly does not wrap a title).
_INTERACTIVE_CLIPPING = r"""
const out = [];
for (const fig of document.querySelectorAll('.rikin-interactive')) {
  const box = fig.getBoundingClientRect();
  if (box.width === 0) continue;
  for (const t of fig.querySelectorAll('svg text')) {
    const r = t.getBoundingClientRect();
    if (!t.textContent.trim() || r.width === 0) continue;
    if (r.left < box.left - 1 || r.right > box.right + 1) {
      out.push({text: t.textContent.trim().slice(0, 60), left: Math.round(r.left - box.left),
                right: Math.round(r.right - box.right), width: Math.round(box.width)});
    }
  }
}
return out;
"""


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", CHAPTER_PAGES)
def test_no_figure_text_is_clipped_on_a_phone(page: str, loaded: LoadedPages) -> None:
    """At 390 px every title, legend entry, button and note of an interactive figure lies
    inside the figure (plotly cuts off text that runs past its edge)."""
    cut = loaded.phone(page)["clipping"]
    assert not cut, "\n".join(
        f"{page} at {PHONE_PX}px: {c['text']!r} runs {max(-c['left'], c['right'])}px past "
        f"the {c['width']}px figure" for c in cut)


#: Lines of code that wrap (they are wider than their box when kept on one line).
_WRAPPED_CODE = r"""
document.querySelectorAll('details').forEach(d => { d.open = true; });
document.querySelectorAll('.toggle-hidden').forEach(el => el.classList.remove('toggle-hidden'));
const out = [];
const column = document.querySelector('article.bd-article') || document.querySelector('main');
for (const pre of column.querySelectorAll('div.cell_input pre, div.highlight pre')) {
  if (pre.closest('.cell_output, .output') || pre.clientWidth === 0) continue;
  const old = pre.style.whiteSpace;
  pre.style.whiteSpace = 'pre';
  const wide = pre.scrollWidth > pre.clientWidth + 1;
  pre.style.whiteSpace = old;
  if (wide) {
    const longest = pre.textContent.split('\n').reduce((a, b) => b.length > a.length ? b : a, '');
    out.push({chars: longest.length, line: longest.trim().slice(0, 70)});
  }
}
return out;
"""


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", COURSE_PAGES)
def test_no_line_of_code_wraps_at_1280(page: str, loaded: LoadedPages) -> None:
    """Every code line, folded cells opened, fits its box at 1280 px: a wrapped line of
    Python reads as a new statement."""
    wrapped = loaded.desktop(page)["wrapped_code"]
    assert not wrapped, "\n".join(
        f"{page}: a {w['chars']}-character line wraps at {DESKTOP_PX}px: {w['line']!r}"
        for w in wrapped)


#: Per figure (image or interactive), the mean lightness of its pixels and of its
#: lightest 0.5 % (its lines and text), from a screenshot of the element (0 black ..
#: 1 white).
def _lightness(png: bytes) -> tuple[float, float]:
    import io

    from PIL import Image

    img = Image.open(io.BytesIO(png)).convert("L")
    values = sorted(img.getdata())
    mean = sum(values) / len(values) / 255.0
    top = values[int(0.995 * (len(values) - 1))] / 255.0
    return mean, top


def _dark_figures(driver: object) -> list[dict]:
    """Each figure (image or interactive) of the article in the page just loaded: its size,
    name, and the lightness of its screenshot (:func:`_lightness`) when it is 50 px or more
    both ways."""
    from selenium.webdriver.common.by import By

    figures = []
    for el in driver.find_elements(
            By.CSS_SELECTOR, "article.bd-article img, article.bd-article .rikin-interactive"):
        figure = {"size": el.size, "mean": None, "top": None}
        figures.append(figure)
        if el.size["width"] < 50 or el.size["height"] < 50:
            continue
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", el)
        time.sleep(0.1)
        figure["mean"], figure["top"] = _lightness(el.screenshot_as_png)
        figure["name"] = el.get_attribute("src") or "interactive " + (el.get_attribute("id")
                                                                      or "")
    return figures


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", CHAPTER_PAGES)
def test_figures_are_dark_in_dark_mode(page: str, book_html: Path,
                                       loaded: LoadedPages) -> None:
    """With the theme's dark mode (data-theme="dark") no figure is a white box on the dark
    page: each figure, drawn image or interactive, is mostly dark, and its lines and text
    are light."""
    dark = loaded.dark(page)
    assert dark["theme"] == "dark"
    problems = []
    figures = dark["figures"]
    for el in figures:
        if el["size"]["width"] < 50 or el["size"]["height"] < 50:
            continue
        mean, top = el["mean"], el["top"]
        name = el["name"]
        if mean > 0.4:
            problems.append(f"{page}: {name.rsplit('/', 1)[-1]} is light in dark mode "
                            f"(mean lightness {mean:.2f})")
        elif top < 0.5:
            problems.append(f"{page}: {name.rsplit('/', 1)[-1]} shows nothing light in "
                            f"dark mode (its text is dark on dark)")
    html = (book_html / page).read_text(encoding="utf-8")
    if "<img" in html or "rikin-interactive" in html:
        assert figures, f"{page}: no figure was found"
    assert not problems, "\n".join(problems)


#: Text a reader should never see: a MyST role that did not parse ({term}`x`), and a
#: punctuation mark that a line break has parted from the formula before it (a period
#: alone at the start of a line).
_LEFTOVER = r"""
const column = document.querySelector('article.bd-article') || document.querySelector('main');
const out = [];
const walker = document.createTreeWalker(column, NodeFilter.SHOW_TEXT, {
  acceptNode(node) {
    return node.parentElement.closest('pre, code, script, style, mjx-container')
      ? NodeFilter.FILTER_REJECT : NodeFilter.FILTER_ACCEPT;
  }
});
for (let n = walker.nextNode(); n; n = walker.nextNode()) {
  const t = n.textContent;
  const role = /\{(term|numref|doc|ref|download|eq|math|glue:text)\}`/.exec(t);
  if (role) out.push('role shown as text: ' + t.trim().slice(0, 60));
  const prev = n.previousSibling;
  const math = prev && (prev.matches && prev.matches('mjx-container, span.math')
    ? prev : null);
  if (math && /^[.,;:)]/.test(t)) {
    const range = document.createRange();
    range.setStart(n, 0);
    range.setEnd(n, 1);
    const r = range.getBoundingClientRect(), m = math.getBoundingClientRect();
    if (r.width > 0 && r.left < m.right - 1 && r.top >= m.bottom - 2) {
      out.push('punctuation alone at the start of a line after a formula: '
               + (math.textContent.trim().slice(-30)) + ' / ' + t.trim().slice(0, 30));
    }
  }
}
return out;
"""


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", CHAPTER_PAGES)
def test_no_leftover_markup(page: str, loaded: LoadedPages) -> None:
    """No MyST role is shown as text, and no period or comma is parted from its formula by a
    line break, at 1280 px and at 390 px."""
    problems = []
    for px in (DESKTOP_PX, PHONE_PX):
        view = loaded.desktop(page) if px == DESKTOP_PX else loaded.phone(page)
        problems += [f"{page} at {px}px: {p}" for p in view["leftover"]]
    assert not problems, "\n".join(problems)


_SEARCH_FIELDS = r"""
return Array.from(document.querySelectorAll('.search-button-field, form.bd-search input'))
  .filter(e => { const r = e.getBoundingClientRect();
                 return r.width > 0 && r.height > 0
                        && getComputedStyle(e).visibility !== 'hidden'; })
  .map(e => e.closest('[class]').parentElement.className || e.className);
"""


@pytest.mark.book
@pytest.mark.slow
def test_one_search_field(loaded: LoadedPages) -> None:
    """At 1280 px the page shows one search field (the sidebar's), not a second one in a
    bar above it."""
    fields = loaded.desktop("book/planar.html")["search_fields"]
    assert len(fields) == 1, fields


_TABLES_SCROLL = r"""
return Array.from(document.querySelectorAll('article.bd-article table.rikin-table'))
  .filter(t => t.getBoundingClientRect().width > 0)
  .map(t => { const box = t.closest('.rikin-table-wrap') || t.parentElement;
              return {wide: box.scrollWidth > box.clientWidth + 1, cols: t.rows[0].cells.length,
                      text: t.textContent.trim().slice(0, 60)}; })
  .filter(t => t.wide);
"""


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", CHAPTER_PAGES)
def test_tables_fit_a_phone(page: str, loaded: LoadedPages) -> None:
    """At 390 px no table of results (every solution with its joints) needs scrolling
    sideways: a wide one is laid out in fewer columns."""
    wide = loaded.phone(page)["tables"]
    assert not wide, "\n".join(f"{page}: a {w['cols']}-column table scrolls sideways at "
                               f"{PHONE_PX}px: {w['text']!r}" for w in wide)


_PRINTED_ROWS = r"""
return Array.from(document.querySelectorAll('article.bd-article div.cell_output div.output pre'))
  .filter(pre => pre.clientWidth > 0
                 && pre.textContent.split('\n').filter(l => /\S {2,}\S/.test(l)).length >= 2)
  .filter(pre => getComputedStyle(pre).whiteSpace !== 'pre')
  .map(pre => ({white: getComputedStyle(pre).whiteSpace,
                text: pre.textContent.trim().slice(0, 60)}));
"""


@pytest.mark.book
@pytest.mark.slow
@pytest.mark.parametrize("page", COURSE_PAGES)
def test_printed_tables_keep_their_rows_on_a_phone(page: str, loaded: LoadedPages) -> None:
    """At 390 px a table a cell prints (two or more lines in columns: the IK tables, DH
    tables) keeps each row on one line and scrolls sideways in its own box: wrapped, its
    rows broke mid-row and the columns fell apart."""
    wrapped = loaded.phone(page)["printed_rows"]
    assert not wrapped, "\n".join(f"{page}: a printed table wraps its rows ({w['white']}) "
                                  f"at {PHONE_PX}px: {w['text']!r}" for w in wrapped)


# ------------------------------------------------------------------ one load per view of a page
class _Values:
    """The results of the checks run on one load of a page, by name; a check that raised
    raises again when its result is asked for (the other checks of the load still count)."""

    def __init__(self) -> None:
        self._values: dict[str, tuple[bool, object]] = {}

    def run(self, name: str, check: object, *args: object) -> None:
        try:
            self._values[name] = (True, check(*args))
        except Exception as error:  # noqa: BLE001 -- given to the test that reads it
            self._values[name] = (False, error)

    def __getitem__(self, name: str) -> object:
        ok, value = self._values[name]
        if not ok:
            raise value
        return value


class LoadedPages:
    """Every page opened once per view: at 1280 px (:meth:`desktop`), at 390 px
    (:meth:`phone`) and at 1280 px in dark mode (:meth:`dark`). Each view runs every check
    that reads it, in an order where a check that changes the page (opening the folded
    cells, resizing the window) comes after those that only read it, and keeps the results;
    the tests read them. A load that fails fails every test of that view."""

    def __init__(self, driver: object, server: str, book_html: Path) -> None:
        self.driver, self.server, self.book_html = driver, server, book_html
        self._views: dict[tuple[str, str], tuple[bool, object]] = {}

    def desktop(self, page: str) -> _Values:
        return self._view(page, "desktop", self._desktop)

    def phone(self, page: str) -> _Values:
        return self._view(page, "phone", self._phone)

    def dark(self, page: str) -> _Values:
        return self._view(page, "dark", self._dark)

    def _view(self, page: str, name: str, load: object) -> _Values:
        if (page, name) not in self._views:
            try:
                self._views[page, name] = (True, load(page))
            except Exception as error:  # noqa: BLE001 -- every test of the view fails with it
                self._views[page, name] = (False, error)
        ok, value = self._views[page, name]
        if not ok:
            raise value
        return value

    def _desktop(self, page: str) -> _Values:
        """At 1280 px: what ``test_page_renders_offline`` reads (console messages from this
        load only), then the search fields, the figures' text, the leftover markup, the
        layout (folded cells opened), the wrapped code and the layout once the window is
        resized to 390 px."""
        driver, values = self.driver, _Values()
        _set_width(driver, DESKTOP_PX)
        driver.get_log("browser")  # drop messages of earlier pages
        driver.get(f"{self.server}/{page}")
        deadline = time.monotonic() + PAGE_TIMEOUT_S
        while driver.execute_script("return document.readyState") != "complete":
            assert time.monotonic() < deadline, f"{page} did not finish loading"
            time.sleep(0.05)
        values.run("offline", _offline_state, driver, self.server, self.book_html, page)
        # the rest as after _open: MathJax done (the offline state waited for it when the
        # page has its script), the images asked for
        if driver.execute_script("return !!window.MathJax"):
            driver.execute_async_script(_WAIT_MATHJAX)
        driver.execute_script(_IMAGES)
        values.run("search_fields", driver.execute_script, _SEARCH_FIELDS)
        if page in COURSE_PAGES:
            values.run("figure_text", driver.execute_async_script, _FIGURE_TEXT)
        if page not in CHAPTER_PAGES:
            return values
        values.run("leftover", driver.execute_script, _LEFTOVER)
        values.run("overflow", driver.execute_script, _OVERFLOW)
        if page in COURSE_PAGES:
            values.run("wrapped_code", driver.execute_script, _WRAPPED_CODE)
        try:
            _set_width(driver, PHONE_PX)
            time.sleep(0.5)  # plotly and MathJax re-lay out on resize
            values.run("overflow_resized", driver.execute_script, _OVERFLOW)
        finally:
            _set_width(driver, DESKTOP_PX)
        return values

    def _phone(self, page: str) -> _Values:
        """Opened at 390 px: the leftover markup, the tables, the printed tables' rows, and
        half a second later the interactive figures' text."""
        driver, values = self.driver, _Values()
        try:
            _set_width(driver, PHONE_PX)
            _open(driver, f"{self.server}/{page}")
            values.run("leftover", driver.execute_script, _LEFTOVER)
            values.run("tables", driver.execute_script, _TABLES_SCROLL)
            values.run("printed_rows", driver.execute_script, _PRINTED_ROWS)
            time.sleep(0.5)
            values.run("clipping", driver.execute_script, _INTERACTIVE_CLIPPING)
        finally:
            _set_width(driver, DESKTOP_PX)
        return values

    def _dark(self, page: str) -> _Values:
        """Opened at 1280 px in dark mode (the theme's ``mode`` in localStorage, set back to
        light after): the page's theme and its figures' lightness."""
        driver, values = self.driver, _Values()
        url = f"{self.server}/{page}"
        _set_width(driver, DESKTOP_PX)
        if not driver.current_url.startswith(f"{self.server}/"):
            driver.get(url)  # localStorage is the site's: be on it to set it
        driver.execute_script("localStorage.setItem('mode', 'dark')")
        try:
            _open(driver, url)
            values.run("theme", driver.execute_script,
                       "return document.documentElement.dataset.theme")
            time.sleep(0.5)
            values.run("figures", _dark_figures, driver)
        finally:
            driver.execute_script("localStorage.setItem('mode', 'light')")
        return values


@pytest.fixture(scope="module")
def loaded(driver: object, server: str, book_html: Path) -> LoadedPages:
    return LoadedPages(driver, server, book_html)
