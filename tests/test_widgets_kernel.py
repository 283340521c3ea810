"""rikin.widgets in a live Jupyter kernel, driven over the Jupyter protocol as a front end
(JupyterLab, classic Jupyter, Colab) drives it.

A real ipykernel is started; a cell displays the Epson lab's pose panel (``ik_panel``) and
``teach``. The test then does what a browser does when a student drags a slider: it sends
the widget's comm an ``update`` message with the slider's new value. The kernel must answer
by sending the front end a new drawing (the image model's bytes change) and a new
solutions table, and the panel must then hold the IK solutions of the new pose, each
reaching it by FK.
"""

from __future__ import annotations

import os
import queue
import re
import sys
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

import rikin

TIMEOUT_S = 120.0


@pytest.fixture(scope="module")
def kernel() -> Iterator[Any]:
    from jupyter_client.manager import start_new_kernel

    env = dict(os.environ, MPLBACKEND="Agg", PYTHONHASHSEED="0")
    km, kc = start_new_kernel(kernel_name="python3", env=env,
                              extra_arguments=["--HistoryManager.enabled=False"])
    try:
        # what every test below uses, so that each runs alone too (pytest -k)
        _run(kc, "import rikin\nfrom rikin import widgets\narm = rikin.robots.epson_c4()")
        yield kc
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)


def _run(kc: Any, code: str) -> list[dict[str, Any]]:
    """Execute ``code``; every iopub message of that execution, until the kernel is idle."""
    msg_id = kc.execute(code)
    reply = kc.get_shell_msg(timeout=TIMEOUT_S)
    while reply["parent_header"].get("msg_id") != msg_id:
        reply = kc.get_shell_msg(timeout=TIMEOUT_S)
    msgs = _iopub_until_idle(kc, msg_id)
    errors = [m for m in msgs if m["msg_type"] == "error"]
    assert reply["content"]["status"] == "ok" and not errors, (
        "\n".join("\n".join(m["content"]["traceback"]) for m in errors) or reply["content"])
    return msgs


def _iopub_until_idle(kc: Any, parent_id: str) -> list[dict[str, Any]]:
    msgs = []
    deadline = time.monotonic() + TIMEOUT_S
    while time.monotonic() < deadline:
        try:
            m = kc.get_iopub_msg(timeout=1.0)
        except queue.Empty:
            continue
        if m["parent_header"].get("msg_id") != parent_id:
            continue
        msgs.append(m)
        if m["msg_type"] == "status" and m["content"]["execution_state"] == "idle":
            return msgs
    raise AssertionError("the kernel did not finish in time")


def _stdout(msgs: list[dict[str, Any]]) -> str:
    return "".join(m["content"]["text"] for m in msgs
                   if m["msg_type"] == "stream" and m["content"]["name"] == "stdout")


def _models(msgs: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Widget models the kernel opened: comm id -> state (what the front end draws)."""
    return {m["content"]["comm_id"]: m["content"]["data"]["state"]
            for m in msgs if m["msg_type"] == "comm_open"
            and m["content"]["target_name"] == "jupyter.widget"}


def _said(msgs: list[dict[str, Any]]) -> str:
    """Every text the kernel sent the front end's widgets (HTML and labels)."""
    return " ".join(str(m["content"]["data"]["state"]["value"]) for m in msgs
                    if m["msg_type"] == "comm_msg" and "state" in m["content"]["data"]
                    and isinstance(m["content"]["data"]["state"].get("value"), str))


def _drag(kc: Any, comm_id: str, value: float) -> list[dict[str, Any]]:
    """What the browser sends when a slider is released at ``value``; the kernel's answer."""
    msg = kc.session.msg("comm_msg", {"comm_id": comm_id, "data": {
        "method": "update", "state": {"value": value}, "buffer_paths": []}})
    kc.shell_channel.send(msg)
    return _iopub_until_idle(kc, msg["header"]["msg_id"])


@pytest.mark.slow
def test_ik_panel_in_a_live_kernel_follows_a_dragged_slider(kernel: Any) -> None:
    msgs = _run(kernel, "import rikin\nfrom rikin import widgets\n"
                        "arm = rikin.robots.epson_c4()\n"
                        "panel = widgets.ik_panel(arm, x=350.0, y=0.0, z=500.0, "
                        "roll=0.0, pitch=90.0, yaw=0.0)\npanel")
    views = [m for m in msgs if m["msg_type"] == "display_data"
             and "application/vnd.jupyter.widget-view+json" in m["content"]["data"]]
    assert views, "the panel displayed no widget (a front end would show only text)"
    models = _models(msgs)
    sliders = {s["description"]: cid for cid, s in models.items()
               if s.get("_model_name") == "FloatSliderModel"}
    assert set(sliders) == {"x (mm)", "y (mm)", "z (mm)", "roll (deg)", "pitch (deg)",
                            "yaw (deg)"}, sliders
    images = [cid for cid, s in models.items() if s.get("_model_name") == "ImageModel"]
    # the panel's HTML: its heading ("move the target ...") and the solutions table
    tables = [cid for cid, s in models.items() if s.get("_model_name") == "HTMLModel"
              and "move the target" not in s.get("value", "")]
    assert len(images) == 1 and len(tables) == 1, models

    answer = _drag(kernel, sliders["x (mm)"], 400.0)
    updates = [m for m in answer if m["msg_type"] == "comm_msg"
               and m["content"]["data"].get("method") == "update"]
    image_updates = [m for m in updates if m["content"]["comm_id"] == images[0]]
    table_updates = [m["content"]["data"]["state"].get("value", "") for m in updates
                     if m["content"]["comm_id"] == tables[0]]
    assert image_updates and image_updates[-1]["buffers"], "no new drawing was sent"
    png = bytes(image_updates[-1]["buffers"][0])
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert table_updates and "front/" in table_updates[-1], table_updates

    out = _stdout(_run(kernel, "import numpy as np\n"
                               "st = panel.state\n"
                               "print(panel.values['x'], len(st.result))\n"
                               "print(np.abs(arm.fk(st.result.q) - panel.target()).max())\n"
                               "print(' '.join(st.result.labels))"))
    x, n, err, labels = out.split()[0], int(out.split()[1]), float(out.split()[2]), out.split()[3:]
    assert float(x) == 400.0 and n >= 1 and err < 1e-9, out
    # what the kernel drew and tabled is the IK of the new pose, computed here independently
    arm = rikin.robots.epson_c4()
    T = arm.fk(np.zeros(6))
    T[:3, :3] = rikin.rpy_to_r(0.0, 90.0, 0.0, degrees=True)
    T[:3, 3] = [400.0, 0.0, 500.0]
    expected = arm.ik(T)
    assert n == len(expected) and sorted(labels) == sorted(expected.labels)
    for lab in expected.labels:
        assert lab in table_updates[-1]


@pytest.mark.slow
def test_ik_panel_in_a_live_kernel_says_out_of_reach_in_words(kernel: Any) -> None:
    msgs = _run(kernel, "panel2 = widgets.ik_panel(arm)\npanel2")
    models = _models(msgs)
    x_id = next(cid for cid, s in models.items() if s.get("description") == "x (mm)")
    x_max = models[x_id]["max"]
    answer = _drag(kernel, x_id, x_max)
    said = _said(answer)
    assert re.search(r"out of reach by [\d.]+ mm: the wrist centre is [\d.]+ mm from the "
                     r"shoulder axis, links 2-3 reach 500 mm", said), said


@pytest.mark.slow
def test_teach_in_a_live_kernel_moves_the_arm(kernel: Any) -> None:
    msgs = _run(kernel, "pendant = widgets.teach(arm)\npendant")
    models = _models(msgs)
    q2 = next(cid for cid, s in models.items() if s.get("description") == "q2 (deg)")
    answer = _drag(kernel, q2, -30.0)
    said = _said(answer)
    T = rikin.robots.epson_c4().fk(rikin.rad([0, -30, 0, 0, 0, 0]))
    assert f"({T[0, 3]:.4g}, {T[1, 3]:.4g}, {T[2, 3]:.4g}) mm" in said, said


def test_kernel_runs_this_interpreter() -> None:
    """The kernel the tests start is the one of this environment (rikin importable)."""
    from jupyter_client.kernelspec import KernelSpecManager

    spec = KernelSpecManager().get_kernel_spec("python3")
    assert spec.argv[0] in (sys.executable, "python", "python3") or os.path.samefile(
        spec.argv[0], sys.executable), spec.argv


# ------------------------------------------------------------------ a page without widgets
def _refuse(kc: Any, comm_id: str) -> list[dict[str, Any]]:
    """What JupyterLab without the widget manager sends for a widget's comm_open: a
    comm_close (it has no handler for the target); the kernel's answer."""
    msg = kc.session.msg("comm_close", {"comm_id": comm_id, "data": {}})
    kc.shell_channel.send(msg)
    return _iopub_until_idle(kc, msg["header"]["msg_id"])


@pytest.mark.slow
def test_a_panel_on_a_page_without_widgets_is_its_still_picture(kernel: Any) -> None:
    """Issue 28 item 1: the output carries the widget and, for a page that cannot show
    widgets, the panel's picture with one line saying to reload; when the page refuses the
    widget's comm, the kernel replaces the output by the picture alone (no dead widget is
    left in the notebook for after the reload)."""
    for code in ("widgets.ik_panel(arm)", "widgets.teach(arm)", "widgets.dh_panel()"):
        msgs = _run(kernel, code)
        (shown,) = [m for m in msgs if m["msg_type"] == "display_data"]
        data = shown["content"]["data"]
        assert "application/vnd.jupyter.widget-view+json" in data, code
        assert "A still picture of the live panel" in data["text/html"], code
        assert "reload the page" in data["text/html"] and "data:image/png;base64," in data[
            "text/html"], code
        assert "VBox(" not in data["text/plain"] and "HBox(" not in data["text/plain"]
        display_id = shown["content"]["transient"]["display_id"]
        root = data["application/vnd.jupyter.widget-view+json"]["model_id"]
        answer = _refuse(kernel, root)
        (update,) = [m for m in answer if m["msg_type"] == "update_display_data"]
        assert update["content"]["transient"]["display_id"] == display_id
        assert set(update["content"]["data"]) == {"text/html", "text/plain"}, code
        assert 'data-refused="1"' in update["content"]["data"]["text/html"]


@pytest.mark.slow
def test_figures_carry_plotly_js_once_per_browser_tab(kernel: Any) -> None:
    """A figure's HTML works without plotly's JupyterLab extension: the first figure a tab
    (a front-end session) shows carries plotly.js, later ones do not; a reloaded tab is a
    new session and gets it again."""
    setup = ("from rikin import interactive\nres = arm.ik(arm.fk(np.radians([20, -30, 40, 10, "
             "30, 0])))\nimport numpy as np\n")
    _run(kernel, "import numpy as np\n" + setup)

    def figure_html() -> str:
        msgs = _run(kernel, "interactive.solutions_figure(arm, res)")
        (out,) = [m for m in msgs if m["msg_type"] in ("execute_result", "display_data")]
        assert "application/vnd.plotly.v1+json" not in out["content"]["data"]
        return out["content"]["data"]["text/html"]

    first, second = figure_html(), figure_html()
    assert "window.Plotly" in first and "plotly.js v" in first and len(first) > 1_000_000
    assert "plotly.js v" not in second and len(second) < 300_000
    assert 'Plotly.newPlot' in first and 'Plotly.newPlot' in second
    kernel.session.session = "another-tab"  # what a reloaded page sends: a new session id
    assert "plotly.js v" in figure_html()
