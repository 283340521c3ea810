"""rikin.interactive's figure HTML in headless Chromium, without JupyterLab (issue 28 item 1).

A figure's HTML needs no front-end extension: the first figure a browser tab shows carries
plotly.js, the later ones only their data. A JupyterLab that attaches cells as they come
into view can run a later figure's script before the first one's; that figure must then
draw as soon as plotly.js is on the page, not stay blank.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from jupyterlab_driver import BROWSERS, CHROMIUM_FLAGS, DRIVERS, which  # noqa: E402

from rikin import interactive, robots  # noqa: E402


@pytest.fixture
def chromium():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser, chromedriver = which(BROWSERS), which(DRIVERS)
    if browser is None or chromedriver is None:
        pytest.fail("Chromium and chromedriver are needed (Debian: apt-get install -y "
                    "chromium chromium-driver; tools/dev.py test installs them)")
    opts = webdriver.ChromeOptions()
    opts.binary_location = browser
    for flag in CHROMIUM_FLAGS:
        opts.add_argument(flag)
    drv = webdriver.Chrome(service=Service(executable_path=chromedriver), options=opts)
    drv.set_page_load_timeout(120)
    drv.set_script_timeout(60)
    try:
        yield drv
    finally:
        drv.quit()


def _wait(what, probe, timeout: float = 120):
    import time

    end = time.monotonic() + timeout
    last = None
    while time.monotonic() < end:
        last = probe()
        if last:
            return last
        time.sleep(0.2)
    raise AssertionError(f"timed out waiting for {what} (last: {str(last)[:300]})")


@pytest.mark.slow
def test_a_figure_run_before_plotly_js_is_drawn_once_plotly_js_comes(chromium, tmp_path):
    arm = robots.epson_c4()
    res = arm.ik(arm.fk(np.radians([20, -30, 40, 10, 30, 0])))
    assert len(res) > 1
    fig = interactive.solutions_figure(arm, res)
    page = tmp_path / "page.html"
    # a later figure's output (no plotly.js in it), shown first
    page.write_text(f"<!doctype html><html><body>{fig.to_html('later')}</body></html>",
                    encoding="utf-8")
    (tmp_path / "plotly.js").write_text(
        interactive.plotly_js_script().split("<script>", 1)[1].rsplit("</script>", 1)[0],
        encoding="utf-8")
    chromium.get(page.as_uri())
    said = _wait("the figure's script to run", lambda: chromium.execute_script(
        "return document.getElementById('later').textContent;") != interactive.NOT_DRAWN
        and chromium.execute_script("return document.getElementById('later').textContent;"))
    assert said == interactive.NO_PLOTLY
    assert not chromium.execute_script("return !!window.Plotly;")
    # the first figure's output (the one carrying plotly.js) is drawn now
    chromium.execute_script("""const s = document.createElement('script');
        s.src = 'plotly.js'; document.body.appendChild(s);""")
    _wait("the figure to be drawn", lambda: chromium.execute_script(
        "const el = document.getElementById('later');"
        "return el.classList.contains('js-plotly-plot') && !!el.querySelector('svg');"))
    assert interactive.NO_PLOTLY not in chromium.execute_script(
        "return document.getElementById('later').textContent;")
