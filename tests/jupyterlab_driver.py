"""Drive a real JupyterLab in headless Chromium, as a student clicks it (tests only).

:class:`Lab` starts ``jupyter lab`` from a given virtual environment (a student's: only
``pip install jupyterlab``) on 127.0.0.1 with a token, and Debian's Chromium through
selenium with the network cut off (every host but 127.0.0.1 unresolvable, a proxy to
nowhere). Its methods do what a student does: open a notebook, *Run > Run All Cells*,
reload the page, run one cell, type into a slider's readout, click a figure's button;
and they read what the page shows. Every wait polls with a timeout (no fixed sleeps)
and saves a screenshot when it runs out.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import socket
import subprocess
import time
import urllib.request
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
DRIVERS = ("chromedriver", "chromium-driver")
CHROMIUM_FLAGS = (
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--no-first-run", "--disable-extensions", "--disable-default-apps",
    "--window-size=1366,768",
    "--proxy-server=127.0.0.1:9",
    "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE localhost , EXCLUDE 127.0.0.1",
)

#: JavaScript: the code cells of the open notebook, what each shows.
CELLS_JS = """
const nb = document.querySelector('.jp-NotebookPanel:not(.lm-mod-hidden) .jp-Notebook');
if (!nb) { return null; }
return [...nb.querySelectorAll('.jp-CodeCell')].map(c => ({
  source: (c.querySelector('.jp-InputArea-editor') || {}).textContent || '',
  prompt: (c.querySelector('.jp-InputArea-prompt') || {}).textContent || '',
  hidden: !!c.querySelector('.jp-InputPlaceholder'),
  outputs: [...c.querySelectorAll('.jp-OutputArea-child .jp-OutputArea-output')].map(o => ({
    mime: o.getAttribute('data-mime-type'),
    text: o.textContent.slice(0, 4000),
    widget: !!o.querySelector('.jupyter-widgets, .widget-box'),
    plotly: !!o.querySelector('.rikin-interactive.js-plotly-plot'),
  })),
}));
"""


def which(names: tuple[str, ...]) -> str | None:
    for name in names:
        path = shutil.which(name) or (f"/usr/bin/{name}" if Path(f"/usr/bin/{name}").exists()
                                      else None)
        if path:
            return path
    return None


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Lab:
    """A JupyterLab server and a Chromium page on it (use as a context manager)."""

    def __init__(self, venv: Path, root: Path, env: dict[str, str], shots: Path,
                 app: str = "lab") -> None:
        """``app``: "lab" (JupyterLab) or "notebook" (Jupyter Notebook 7, the same pieces)."""
        self.venv, self.root, self.env, self.shots, self.app = venv, root, env, shots, app
        self.port, self.token = free_port(), secrets.token_hex(16)
        self.base = f"http://127.0.0.1:{self.port}"
        self.log = shots / "jupyterlab.log"
        self.server: subprocess.Popen[bytes] | None = None
        self.driver: Any = None

    # ---- start and stop
    def __enter__(self) -> Lab:
        self.shots.mkdir(parents=True, exist_ok=True)
        with self.log.open("wb") as log:
            self.server = subprocess.Popen(
                [str(self.venv / "bin" / "jupyter"), self.app, "--no-browser", "--ip=127.0.0.1",
                 f"--port={self.port}", f"--IdentityProvider.token={self.token}",
                 f"--ServerApp.root_dir={self.root}", "--ServerApp.open_browser=False",
                 *(["--allow-root"] if os.geteuid() == 0 else [])],
                env=self.env, stdout=log, stderr=subprocess.STDOUT, cwd=self.root)
        self._wait_for_server(180)
        self.driver = self._chromium()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.driver is not None:
            with contextlib.suppress(Exception):
                self.driver.quit()
        if self.server is not None:
            self.server.terminate()
            try:
                self.server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.server.kill()
                self.server.wait()

    def _wait_for_server(self, timeout: float) -> None:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            assert self.server is not None
            if self.server.poll() is not None:
                raise AssertionError(f"jupyter lab exited:\n{self.log.read_text()[-3000:]}")
            with contextlib.suppress(OSError):
                urllib.request.urlopen(f"{self.base}/api/status?token={self.token}",
                                       timeout=5).close()
                return
            time.sleep(0.2)
        raise AssertionError(f"jupyter lab did not answer:\n{self.log.read_text()[-3000:]}")

    def _chromium(self) -> Any:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        browser, chromedriver = which(BROWSERS), which(DRIVERS)
        if browser is None or chromedriver is None:
            raise AssertionError("Chromium and chromedriver are needed (Debian: apt-get install "
                                 "-y chromium chromium-driver; tools/dev.py test installs them)")
        opts = webdriver.ChromeOptions()
        opts.binary_location = browser
        for flag in CHROMIUM_FLAGS:
            opts.add_argument(flag)
        drv = webdriver.Chrome(service=Service(executable_path=chromedriver), options=opts)
        drv.set_page_load_timeout(120)
        drv.set_script_timeout(60)
        return drv

    # ---- waiting and looking
    def wait(self, what: str, probe: Callable[[], Any], timeout: float) -> Any:
        """Poll ``probe`` until it returns something true; fail with a screenshot."""
        end = time.monotonic() + timeout
        last: Any = None
        while time.monotonic() < end:
            try:
                last = probe()
            except Exception as exc:  # noqa: BLE001 - a page in the middle of a change
                last = exc
            if last and not isinstance(last, Exception):
                return last
            time.sleep(0.25)
        shot = self.screenshot(f"timeout-{what.replace(' ', '-')}")
        raise AssertionError(f"timed out after {timeout:.0f} s waiting for {what} (last: "
                             f"{str(last)[:500]}); screenshot {shot}")

    def js(self, script: str, *args: Any) -> Any:
        return self.driver.execute_script(script, *args)

    def screenshot(self, name: str) -> Path:
        path = self.shots / f"{name}.png"
        self.driver.save_screenshot(str(path))
        return path

    def cells(self) -> list[dict[str, Any]]:
        return self.js(CELLS_JS) or []

    def kernel_idle(self) -> bool:
        """Every kernel of the server is idle (the server's REST API says so)."""
        import json

        with urllib.request.urlopen(f"{self.base}/api/kernels?token={self.token}",
                                    timeout=10) as r:
            kernels = json.load(r)
        return bool(kernels) and all(k.get("execution_state") == "idle" for k in kernels)

    # ---- doing
    def open(self, name: str) -> None:
        """Open notebook ``name`` (in the server's root) and wait for its kernel."""
        where = "lab/tree" if self.app == "lab" else "notebooks"
        self.driver.get(f"{self.base}/{where}/{name}?token={self.token}")
        self._wait_for_notebook(name)

    #: JavaScript: whether the page shows the notebook's kernel as connected and idle
    #: (JupyterLab's status bar; Notebook 7's kernel indicator in the toolbar).
    PAGE_KERNEL_IDLE_JS = """
      if (window.__rikinOldPage || document.querySelector('.jp-Spinner')) { return false; }
      const bar = [...document.querySelectorAll('.jp-StatusBar-TextItem')]
        .some(e => /\\| Idle/.test(e.textContent));
      const toolbar = [...document.querySelectorAll('.jp-Notebook-ExecutionIndicator, '
        + '.jp-KernelStatus, [data-jp-item-name="kernelStatus"]')]
        .some(e => /idle/i.test(e.getAttribute('title') || '') || /Idle/.test(e.textContent));
      return bar || toolbar;"""

    def _wait_for_notebook(self, name: str) -> None:
        """The notebook shown with its cells and its kernel connected and idle."""
        self.wait(f"{name} to open with its kernel idle", lambda: self.js(
            self.PAGE_KERNEL_IDLE_JS) and len(self.cells()) > 0, 300)
        self.wait(f"{name}'s kernel", self.kernel_idle, 180)

    def menu(self, top: str, *items: str) -> None:
        """Click ``top`` in the menu bar, then the first of ``items`` its menu has (JupyterLab
        and Notebook 7 name a few entries differently)."""
        from selenium.webdriver.common.by import By

        bar = self.wait(f"menu {top}", lambda: [m for m in self.driver.find_elements(
            By.CSS_SELECTOR, ".lm-MenuBar-item") if m.text.strip() == top], 60)
        bar[0].click()

        def entries() -> list[Any]:
            found = {}
            for m in self.driver.find_elements(By.CSS_SELECTOR, ".lm-Menu-item"):
                label = m.find_elements(By.CSS_SELECTOR, ".lm-Menu-itemLabel")
                if label:
                    found.setdefault(label[0].text.strip(), m)
            return [found[i] for i in items if i in found]

        self.wait(f"menu item {items[0]}", entries, 60)[0].click()

    def run_all(self, timeout: float) -> list[dict[str, Any]]:
        """*Run > Run All Cells*; wait until no cell runs or waits, and the kernel is idle."""
        before = [c["prompt"] for c in self.cells()]
        self.menu("Run", "Run All Cells")
        self.wait("Run All to start", lambda: [c["prompt"] for c in self.cells()] != before
                  or any("*" in c["prompt"] for c in self.cells()), 60)

        def finished() -> list[dict[str, Any]] | None:
            cells = self.cells()
            if any("*" in c["prompt"] for c in cells) or not self.kernel_idle():
                return None
            return cells

        return self.wait("Run All to finish", finished, timeout)

    def reload(self) -> None:
        """Save (the browser asks before leaving unsaved changes), then reload the page."""
        self.menu("File", "Save Notebook", "Save and Checkpoint", "Save")
        self.wait("the notebook to be saved", lambda: not self.js(
            "return !!document.querySelector('.jp-mod-dirty');"), 60)
        self.js("window.__rikinOldPage = true;")
        self.driver.refresh()
        self._wait_for_notebook("the reloaded notebook")

    @contextlib.contextmanager
    def output_of(self, needle: str) -> Iterator[Any]:
        """The code cell whose source contains ``needle``. JupyterLab attaches a notebook's
        cells as they come into view: the notebook is scrolled from its top until it is."""
        find = """
          const nb = document.querySelector('.jp-NotebookPanel:not(.lm-mod-hidden) .jp-Notebook');
          const text = c => (c.querySelector('.jp-InputArea-editor') || {}).textContent || '';
          return [...nb.querySelectorAll('.jp-CodeCell')].find(
            c => text(c).includes(arguments[0])) || null;"""
        scroll = """
          const nb = document.querySelector('.jp-NotebookPanel:not(.lm-mod-hidden) .jp-Notebook');
          const box = nb.querySelector('.jp-WindowedPanel-outer')
            || nb.closest('.jp-WindowedPanel-outer') || nb;
          if (arguments[0]) { box.scrollTop = 0; return false; }
          const end = box.scrollTop + box.clientHeight >= box.scrollHeight - 2;
          box.scrollTop += 0.7 * box.clientHeight;
          return end;"""
        self.js(scroll, True)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            el = self.js(find, needle)
            if el is not None:
                yield el
                return
            if self.js(scroll, False) and self.js(find, needle) is None:
                break
            time.sleep(0.2)  # let JupyterLab attach the cells now in view
        shot = self.screenshot("no-cell")
        raise AssertionError(f"no code cell contains {needle!r}; screenshot {shot}")

    def run_cell(self, needle: str, timeout: float) -> None:
        """Select the code cell whose source contains ``needle`` and run it (Shift+Enter)."""
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.common.keys import Keys

        with self.output_of(needle) as cell:
            self.js("arguments[0].scrollIntoView({block: 'center'});", cell)
            prompt = cell.find_element("css selector", ".jp-InputArea-prompt")
            before = prompt.text
            prompt.click()
            ActionChains(self.driver).key_down(Keys.SHIFT).send_keys(Keys.ENTER).key_up(
                Keys.SHIFT).perform()
            self.wait(f"the cell {needle!r} to run", lambda: prompt.text != before
                      and "*" not in prompt.text and self.kernel_idle(), timeout)
