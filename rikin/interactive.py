"""Interactive arm figures that work offline: rotate, step through IK solutions, follow a path.

The figures are plotly figures (``pip install "rikin[interactive]"``). In the
built book they are plain HTML: the page loads ``plotly.min.js`` from the
book's own ``_static/`` folder (copied there from the installed plotly
package at build time, see :func:`plotly_js`), so nothing is fetched from
the network. In a notebook (JupyterLab, Notebook 7, VS Code) they are the same
HTML, and the first figure a browser tab shows carries plotly.js itself, so no
front-end extension is needed: a figure works in a JupyterLab that was running
before plotly was installed. Colab shows plotly's own output.

* :func:`solutions_figure`: every IK solution of one target, one at a time
  (buttons ``1 .. k`` and ``all``), rotatable in 3D, with each solution's
  branch and joint values in the title;
* :func:`path_figure`: the target moves along a path (a slider and a play
  button); at every step the arm is drawn in each branch that reaches it;
* :func:`arm_figure`: one configuration, rotatable.

Every drawing uses the geometry of :mod:`rikin.plot` (the links as DH
pieces, the joint points, the gripper, the frames: x red, y green, z blue).

Examples
--------
>>> import rikin
>>> from rikin import interactive
>>> arm = rikin.robots.aula10_6r()
>>> res = arm.ik(arm.fk(rikin.rad([99.6, 9, 26.4, 68.4, 30, 151])))
>>> fig = interactive.solutions_figure(arm, res)     # doctest: +SKIP
>>> fig                                              # doctest: +SKIP
"""

from __future__ import annotations

import importlib
import json
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ._validate import FloatArray, as_count, as_flag, as_float_array, as_text, as_texts
from .dh import SerialArm
from .errors import InputError, RikinError
from .i18n import branch_name, phrase
from .ik.result import IKResult
from .plot import (
    AXIS_COLOURS,
    FRAME_FRACTION,
    MARKER_KEY,
    _check_arm,
    _joint_points,
    _link_path,
    _q_text,
    _square_limits,
    gripper_path,
    is_planar,
)

__all__ = ["InteractiveFigure", "PLOTLY_JS", "arm_figure", "path_figure", "plotly_js",
           "solutions_figure"]

#: Where the book serves plotly.js, relative to its ``_static/`` folder.
PLOTLY_JS = "plotly/plotly.min.js"
#: Marks an interactive figure in a page's HTML (the book loads plotly.js only on such pages).
HTML_MARKER = "rikin-interactive"
#: One colour per solution slot (the same order in every figure).
SLOT_COLOURS = ("#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860", "#da8bc3",
                "#8c8c8c")
_AXIS_HEX = {"tab:red": "#d62728", "tab:green": "#2ca02c", "tab:blue": "#1f77b4"}
#: Traces drawn per solution: links, joints, gripper, TCP, frame x, y, z.
TRACES_PER_ARM = 7


def _plotly() -> Any:
    try:
        return importlib.import_module("plotly.graph_objects")
    except ImportError as exc:  # pragma: no cover - exercised without the extra
        raise RikinError(
            "interactive figures need plotly: pip install 'rikin[interactive]' "
            "(or pip install 'plotly>=5.18,<8')"
        ) from exc


def plotly_js() -> Path:
    """The ``plotly.min.js`` of the installed plotly package (what the book copies to _static).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    RikinError
        plotly is not installed, or its package has no bundled plotly.js.
    """
    _plotly()
    import plotly

    path = Path(plotly.__file__).parent / "package_data" / "plotly.min.js"
    if not path.is_file():
        raise RikinError(f"the installed plotly has no bundled plotly.js at {path}")
    return path


# ------------------------------------------------------------------ plotly.js in a notebook
#: Set (to "1") by the book's build (``book/_ext/rikin_book.py``) in the environment of the
#: kernels that execute the chapters: the book's pages load plotly.js from ``_static``, so a
#: figure's HTML carries none of it.
BOOK_BUILD_ENV = "RIKIN_BOOK_BUILD"
#: What a figure says where its script has not run (a notebook opened but not yet run, or
#: a page without plotly.js): replaced by the drawing once the script runs.
NOT_DRAWN = ("Interactive figure: run this cell to draw it (the notebook's own outputs are "
             "drawn; outputs saved in a file you did not run are not).")
#: What a figure says when its script runs but plotly.js is missing from the page.
NO_PLOTLY = ("This interactive figure needs plotly.js, which rikin puts in the first figure "
             "this page shows: it is drawn as soon as that one is; if it stays like this, "
             "run the notebook from its first cell again (Run All).")
#: How long a figure whose script ran before plotly.js was on the page waits for it (a
#: JupyterLab that attaches cells as they scroll into view may run a later figure's script
#: before the first one's), in seconds.
WAIT_FOR_PLOTLY_S = 600
#: The front ends (browser tabs: the ``session`` of their requests) that this kernel has
#: sent plotly.js to. A reloaded tab is a new session and gets it again.
_PLOTLY_SENT: set[str] = set()
_DISPLAYED = [0]  # figures displayed by this kernel (their div ids get the count)


def _frontend_session() -> str | None:
    """The session id of the front end whose request is running, or None outside a kernel."""
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython comes with every notebook kernel
        return None
    shell = get_ipython()
    header = getattr(shell, "parent_header", None) or {}
    session = header.get("header", {}).get("session") if isinstance(header, dict) else None
    return str(session) if session else None


def _in_book_build() -> bool:
    return os.environ.get(BOOK_BUILD_ENV) == "1"


def plotly_js_script() -> str:
    """plotly.js (the installed plotly's bundle) as one ``<script>`` for a notebook output.

    The library is wrapped so that it always defines ``window.Plotly`` (a page with an AMD
    loader or CommonJS globals would otherwise keep it to itself), and it is skipped where
    the page has plotly.js already.
    """
    js = plotly_js().read_text(encoding="utf-8").replace("</script", "<\\/script")
    return ("<script>\nif (!window.Plotly) {\n"
            "  window.PlotlyConfig = {MathJaxConfig: 'local'};\n"
            "  (function (define, module, exports) {\n" + js + "\n  }).call(window);\n"
            "}\n</script>\n")


# ------------------------------------------------------------------ the figure object
def _html_id(div_id: Any) -> str:
    """``div_id`` as the id of a ``<div>`` written into the page as it is; else InputError."""
    text = str(as_text(div_id, "div_id"))
    if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_:.-]{0,99}", text):
        raise InputError("div_id must be an HTML id: a letter, then letters, digits, '-', '_', "
                         f"':' or '.' (at most 100), got {text[:40]!r}")
    return text


class InteractiveFigure:
    """A plotly figure that displays offline in the book and in every notebook front end.

    In the book the page loads plotly.js from the book's ``_static`` folder. In a notebook
    (JupyterLab, Notebook 7, VS Code, a classic Jupyter) the figure is HTML with a script
    and needs no front-end extension: the first figure a browser tab shows carries
    plotly.js itself (about 5 MB, once per tab), so figures work in a JupyterLab that was
    started before rikin and plotly were installed. Colab gets plotly's own output.

    Attributes
    ----------
    figure : plotly.graph_objects.Figure
        The figure itself (change it, or ``.figure.show()`` it).
    """

    def __init__(self, figure: Any, div_id: str) -> None:
        self.figure = figure
        self.div_id = div_id

    def to_html(self, div_id: str | None = None) -> str:
        """A ``<div>`` and the script that draws it; plotly.js must be loaded on the page.

        The figure's JSON is written with sorted keys and a fixed div id, so a
        rebuild writes the same page.

        Raises
        ------
        InputError
            ``div_id`` is not an HTML id (letters, digits, ``-``, ``_``, ``:``, ``.``).
        """
        div = self.div_id if div_id is None else _html_id(div_id)
        spec = self.figure.to_plotly_json()
        data = json.dumps(spec.get("data", []), sort_keys=True, cls=_Encoder)
        layout = json.dumps(spec.get("layout", {}), sort_keys=True, cls=_Encoder)
        frames = json.dumps(spec.get("frames", []), sort_keys=True, cls=_Encoder)
        config = json.dumps({"responsive": True, "displaylogo": False,
                             "modeBarButtonsToRemove": ["toImage"]})
        return (
            f'<div class="{HTML_MARKER}" id="{div}" style="width:100%;max-width:100%;'
            f'height:{int(self.figure.layout.height or 520)}px">{phrase(NOT_DRAWN)}</div>\n'
            "<script>(function () {\n"
            f'  var el = document.getElementById("{div}"), tries = 0;\n'
            "  if (!el) { return; }\n"
            "  function draw() {\n"
            "    if (!window.Plotly) {\n"
            f"      el.textContent = {json.dumps(phrase(NO_PLOTLY))};\n"
            f"      if (tries++ < {4 * WAIT_FOR_PLOTLY_S}) {{ setTimeout(draw, 250); }}\n"
            "      return;\n"
            "    }\n"
            '    el.textContent = "";\n'
            f"    var frames = {frames};\n"
            f"    Plotly.newPlot(el, {data}, {layout}, {config}).then(function () {{\n"
            "      if (frames.length) { return Plotly.addFrames(el, frames); }\n"
            "    });\n"
            "  }\n"
            "  draw();\n"
            "})();</script>"
        )

    def as_html(self) -> Any:
        """The figure as an ``IPython.display.HTML`` (only ``text/html``), for ``myst_nb.glue``.

        A glued figure gets the book's numbered caption (``{glue:figure}``);
        glue renders every mime type it is given, so give it this one alone. It carries
        no plotly.js (the book's page loads it); in a notebook, display the figure itself.
        """
        from IPython.display import HTML

        return HTML(self.to_html())

    def notebook_html(self) -> str:
        """The figure's HTML for a notebook: plotly.js first where this tab has not had it.

        Every call gets its own div id (a figure shown twice in one page draws twice).
        """
        _DISPLAYED[0] += 1
        html = self.to_html(f"{self.div_id}-{_DISPLAYED[0]}")
        session = _frontend_session()
        if session is None or session in _PLOTLY_SENT:
            return html
        _PLOTLY_SENT.add(session)
        return plotly_js_script() + html

    def _repr_mimebundle_(self, include: Any = None, exclude: Any = None) -> dict[str, Any]:
        if "google.colab" in sys.modules:
            # Colab shows each output in its own frame; plotly's Colab renderer loads
            # plotly.js into it
            return dict(self.figure._repr_mimebundle_(include, exclude))
        title = self.figure.layout.title.text or ""
        text = f"<rikin interactive figure: {title.split('<br>')[0]}>"
        if _in_book_build():
            return {"text/html": self.to_html(), "text/plain": text}
        return {"text/html": self.notebook_html(), "text/plain": text}

    def show(self) -> None:
        """Display with plotly's renderer (a browser tab outside a notebook)."""
        self.figure.show()


class _Encoder(json.JSONEncoder):
    def default(self, o: Any) -> Any:
        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, np.generic):
            return o.item()
        return super().default(o)


def _div_id(kind: str, arm: SerialArm, extra: Any) -> str:
    """A deterministic div id: the same figure gets the same id at every build."""
    import hashlib

    h = hashlib.sha256(f"{kind}|{arm.name}|{np.asarray(extra).round(9).tobytes().hex()}".encode())
    return f"{HTML_MARKER}-{kind}-{h.hexdigest()[:10]}"


# ------------------------------------------------------------------ geometry as traces
def _xyz(points: FloatArray, dims: int) -> dict[str, list[float | None]]:
    """Plotly coordinate lists; NaN rows become gaps (None)."""
    out: dict[str, list[float | None]] = {}
    for k, name in enumerate("xyz"[:dims]):
        out[name] = [None if not np.isfinite(v) else round(float(v), 6) for v in points[:, k]]
    return out


def _segments(starts: FloatArray, ends: FloatArray) -> FloatArray:
    """Segments as one polyline with NaN gaps, shape (3 m, 3)."""
    m = len(starts)
    out = np.full((3 * m, 3), np.nan)
    out[0::3] = starts
    out[1::3] = ends
    return out


def _empty(dims: int) -> dict[str, list[Any]]:
    return {name: [] for name in "xyz"[:dims]}


def _arm_geometry(arm: SerialArm, q: FloatArray | None, fs: float, dims: int,
                  frames: bool) -> list[dict[str, Any]]:
    """Coordinates of the ``TRACES_PER_ARM`` traces of one arm (empty when ``q`` is None)."""
    if q is None:
        return [_empty(dims) for _ in range(TRACES_PER_ARM)]
    F = arm._fk(q, frames=True)
    geo = [_xyz(_link_path(arm, F), dims), _xyz(_joint_points(arm, F), dims),
           _xyz(gripper_path(F[-1], (0.9 if dims == 3 else 0.55) * fs, planar=dims == 2), dims),
           _xyz(F[-1:, :3, 3], dims)]
    for k in range(3):
        if frames and k < dims:
            o = F[:, :3, 3]
            geo.append(_xyz(_segments(o, o + fs * F[:, :3, k]), dims))
        else:
            geo.append(_empty(dims))
    return geo


def _arm_traces(go: Any, dims: int, colour: str, name: str, group: str,
                geo: list[dict[str, Any]], hover: str, show_legend: bool = True) -> list[Any]:
    Scatter = go.Scatter3d if dims == 3 else go.Scatter
    width = 7 if dims == 3 else 5
    common = {"legendgroup": group, "hoverinfo": "text", "text": hover}
    traces = [
        Scatter(mode="lines", line={"color": colour, "width": width}, name=name,
                showlegend=show_legend, **common, **geo[0]),
        Scatter(mode="markers", marker={"size": 5 if dims == 3 else 9, "color": "white",
                                        "line": {"color": colour, "width": 2}},
                name=name + " joints", showlegend=False, **common, **geo[1]),
        Scatter(mode="lines", line={"color": "#ff7f0e", "width": 5 if dims == 3 else 3},
                name=name + " gripper", showlegend=False, **common, **geo[2]),
        Scatter(mode="markers", marker={"size": 5 if dims == 3 else 11, "color": "#ff7f0e",
                                        "symbol": "diamond"},
                name=name + " TCP", showlegend=False, **common, **geo[3]),
    ]
    for k in range(3):
        traces.append(Scatter(mode="lines", line={"color": _AXIS_HEX[AXIS_COLOURS[k]],
                                                  "width": 3 if dims == 3 else 2},
                              name=f"{name} {'xyz'[k]} axes", showlegend=False,
                              hoverinfo="skip", legendgroup=group, **geo[4 + k]))
    return traces


#: Characters per line of a title or of the key, so that no line runs past the figure on
#: a phone (a 390 px screen leaves the figure about 330 px: 13 px text, ~7 px a character).
LINE_CHARS = 44
#: Lines of the title the top margin leaves room for: the arm, the solution shown, and
#: its joints (six of them take two lines).
TITLE_LINES = 4


def _lines(text: str, width: int = LINE_CHARS) -> list[str]:
    """``text`` broken at spaces into lines of at most ``width`` characters (where it can)."""
    out: list[str] = []
    for part in text.split("<br>"):
        line = ""
        for word in part.split(" "):
            if line and len(line) + 1 + len(word) > width:
                out.append(line)
                line = word
            else:
                line = f"{line} {word}" if line else word
        out.append(line)
    return out


def _title(text: str, max_lines: int = TITLE_LINES) -> str:
    """A title of at most ``max_lines`` short lines (plotly does not wrap a title)."""
    lines = _lines(text)
    if len(lines) > max_lines:
        lines = lines[:max_lines]
        lines[-1] = lines[-1][:LINE_CHARS - 1] + "…"
    return "<br>".join(lines)


def _key(dims: int) -> str:
    """The marker key, one item a line."""
    key = phrase(MARKER_KEY).replace("★", "◆")
    if dims == 2:
        key = key.replace(phrase("approach along z"), phrase("approach along x"))
        key = key.replace(phrase(", z blue"), "")
    return "<br>".join(line for item in key.split("  ·  ") for line in _lines(item))


def _layout(go: Any, arm: SerialArm, lim: FloatArray, dims: int, title: str,
            height: int) -> dict[str, Any]:
    u = f" ({arm.units})" if arm.units else ""
    key = _key(dims)
    key_lines = key.count("<br>") + 1
    layout: dict[str, Any] = {
        "title": {"text": _title(title), "font": {"size": 13}, "x": 0.01, "xanchor": "left",
                  "y": 0.985, "yanchor": "top", "yref": "container", "pad": {"t": 6}},
        "height": height + 14 * key_lines,
        "margin": {"l": 10, "r": 10, "t": 30 + 17 * TITLE_LINES + 28, "b": 20 + 14 * key_lines},
        # the legend sits on top of the plot, the controls under it, the key at the bottom
        "legend": {"orientation": "h", "x": 0.0, "y": 1.0, "yanchor": "bottom",
                   "font": {"size": 11}},
        "autosize": True,
        "uirevision": "keep",     # keep the user's rotation when the data change
        "annotations": [{"text": key, "showarrow": False, "align": "left",
                         "xref": "paper", "yref": "paper", "x": 0.0, "y": 0.0,
                         "xanchor": "left", "yanchor": "top", "yshift": -10,
                         "font": {"size": 10, "color": "#555"}}],
    }
    if dims == 3:
        axes = {f"{'xyz'[k]}axis": {"range": [float(lim[k, 0]), float(lim[k, 1])],
                                   "title": {"text": f"{'xyz'[k]}{u}"}, "nticks": 5}
                for k in range(3)}
        layout["scene"] = {**axes, "aspectmode": "cube",
                           "domain": {"x": [0.0, 1.0], "y": [0.04, 1.0]},
                           "camera": {"eye": {"x": 1.7, "y": -1.7, "z": 1.0}}}
    else:
        layout["xaxis"] = {"range": [float(lim[0, 0]), float(lim[0, 1])], "title": f"x{u}",
                           "zeroline": False}
        layout["yaxis"] = {"range": [float(lim[1, 0]), float(lim[1, 1])], "title": f"y{u}",
                           "scaleanchor": "x", "scaleratio": 1, "zeroline": False}
    return layout


def _limits(arm: SerialArm, points: FloatArray, dims: int) -> FloatArray:
    if dims == 2:
        reach = sum(abs(float(lk.a)) for lk in arm.links) + float(np.linalg.norm(arm.tool[:2, 3]))
        c = arm.base[:2, 3]
        return np.stack([c - 1.12 * reach, c + 1.12 * reach], axis=1)
    return _square_limits(np.vstack([points, arm.base[None, :3, 3]]), 3, 0.15 * arm.scale)


def _target_trace(go: Any, dims: int, p: FloatArray) -> Any:
    Scatter = go.Scatter3d if dims == 3 else go.Scatter
    return Scatter(mode="markers", name=phrase("target"), hoverinfo="name",
                   marker={"size": 9 if dims == 3 else 16, "color": "rgba(0,0,0,0)",
                           "line": {"color": "#d62728", "width": 3}},
                   **_xyz(p[None, :3], dims))


def _as_result(arm: SerialArm,
               result: Any) -> tuple[FloatArray, tuple[str, ...], FloatArray | None]:
    if isinstance(result, IKResult):
        Q = np.asarray(result.q, dtype=np.float64)
        return Q, result.labels, result.target
    Q = arm.check_q(result, "result")
    Q = Q[None] if Q.ndim == 1 else Q
    return Q, tuple("" for _ in Q), None


def _check_height(height: Any) -> int:
    if isinstance(height, bool) or not isinstance(height, (int, np.integer)) or height < 200:
        raise InputError(f"height must be an integer number of pixels >= 200, got {height!r}")
    return int(height)


def _solution_traces(go: Any, arm: SerialArm, Q: FloatArray, labels: Any, fs: float,
                     dims: int, frames: bool) -> tuple[list[Any], list[str]]:
    """Every solution's traces (TRACES_PER_ARM each, in its slot's colour) and its heading:
    number, branch and joints."""
    traces: list[Any] = []
    heads = []
    for i in range(len(Q)):
        head = f"{i + 1}: {branch_name(labels[i])}" if labels[i] else phrase("solution {n}",
                                                                             n=i + 1)
        heads.append(f"{head}<br>q = {_q_text(arm, Q[i])}")
        geo = _arm_geometry(arm, Q[i], fs, dims, frames)
        traces += _arm_traces(go, dims, SLOT_COLOURS[i % len(SLOT_COLOURS)], head, f"s{i}", geo,
                              heads[-1])
    return traces, heads


def _visible(k: int, n_target: int, which: int | None) -> list[bool]:
    """Which traces show solution ``which`` (from 0; None: all k) and the target's."""
    vis = [which is None or i == which for i in range(k) for _ in range(TRACES_PER_ARM)]
    return vis + [True] * n_target


def _solution_buttons(k: int, n_target: int, base: str, heads: list[str],
                      selected: int) -> dict[str, Any]:
    """The row of buttons ``1 .. k`` and ``all`` under the figure, ``selected`` pressed."""
    buttons = [{"label": str(i + 1), "method": "update",
                "args": [{"visible": _visible(k, n_target, i)},
                         {"title.text": _title(f"{base}<br>{heads[i]}")}]}
               for i in range(k)]
    every = _title(f"{base}<br>" + phrase("all {k} solutions (legend: click to hide)", k=k))
    buttons.append({"label": phrase("all"), "method": "update",
                    "args": [{"visible": _visible(k, n_target, None)}, {"title.text": every}]})
    return {"type": "buttons", "direction": "right", "buttons": buttons,
            "active": selected - 1, "showactive": True, "x": 0.0, "y": -0.06,
            "xanchor": "left", "yanchor": "top", "pad": {"t": 4}, "font": {"size": 12}}


# ------------------------------------------------------------------ the public figures
def solutions_figure(arm: SerialArm, result: Any, *, frames: bool = True, height: int = 560,
                     title: str | None = None, selected: int = 1) -> InteractiveFigure:
    """Every IK solution of one target, stepped through with buttons; rotatable in 3D.

    Buttons ``1 .. k`` show one solution at a time (its branch and joint
    values in the title), ``all`` shows every solution at once, each in its
    own colour (click a legend entry to hide one). Drag to rotate, scroll to
    zoom (3D).

    Parameters
    ----------
    arm : SerialArm
    result : IKResult or array_like, shape (k, n)
    frames : bool
        Draw every joint frame's axes (x red, y green, z blue): they tell
        apart solutions whose joints lie at the same points.
    height : int
        Pixels.
    title : str, optional
        Default: the arm's name and the number of solutions.
    selected : int
        The solution shown first (numbered from 1).

    Returns
    -------
    InteractiveFigure

    Raises
    ------
    InputError
        No solutions, a bad shape, ``selected`` out of range.
    """
    _check_arm(arm)
    go = _plotly()
    Q, labels, target = _as_result(arm, result)
    if Q.ndim != 2 or len(Q) == 0:
        raise InputError("there are no solutions to draw (the IK result is empty)")
    Q = arm.check_q(Q, "result.q")
    k = len(Q)
    selected = as_count(selected, "selected", minimum=1, maximum=k, what="a solution number")
    height = _check_height(height)
    frames = as_flag(frames, "frames")
    title = as_text(title, "title", optional=True)
    dims = 2 if is_planar(arm) else 3
    F = arm._fk(Q, frames=True)
    pts = F[:, :, :3, 3].reshape(-1, 3)
    if target is not None:
        pts = np.vstack([pts, target[None, :3, 3]])
    lim = _limits(arm, pts, dims)
    fs = float(FRAME_FRACTION * (lim[0, 1] - lim[0, 0]))
    traces, heads = _solution_traces(go, arm, Q, labels, fs, dims, frames)
    n_target = 0
    if target is not None:
        traces.append(_target_trace(go, dims, target[:3, 3]))
        n_target = 1
    base = (phrase(f"{{name}}: {{k}} IK solution{'s' if k != 1 else ''}", name=arm.name, k=k)
            if title is None else title)
    for tr, v in zip(traces, _visible(k, n_target, selected - 1), strict=True):
        tr.visible = v
    layout = _layout(go, arm, lim, dims, f"{base}<br>{heads[selected - 1]}", height)
    layout["updatemenus"] = [_solution_buttons(k, n_target, base, heads, selected)]
    layout["margin"]["b"] += 60
    layout["annotations"][0]["yshift"] = -70
    fig = go.Figure(data=traces, layout=layout)
    return InteractiveFigure(fig, _div_id("solutions", arm, Q))


def arm_figure(arm: SerialArm, q: Any, *, frames: bool = True, height: int = 520,
               title: str | None = None) -> InteractiveFigure:
    """One configuration of the arm, rotatable (3D) and zoomable.

    Parameters
    ----------
    arm : SerialArm
    q : array_like, shape (n,)
    frames : bool
    height : int
    title : str, optional

    Returns
    -------
    InteractiveFigure
    """
    _check_arm(arm)
    go = _plotly()
    qv = arm.check_q(q)
    if qv.ndim != 1:
        raise InputError(f"q must be one configuration of shape ({arm.n},), got {qv.shape}; "
                         "use solutions_figure for several")
    height = _check_height(height)
    frames = as_flag(frames, "frames")
    title = as_text(title, "title", optional=True)
    dims = 2 if is_planar(arm) else 3
    F = arm._fk(qv, frames=True)
    lim = _limits(arm, F[:, :3, 3], dims)
    fs = float(FRAME_FRACTION * (lim[0, 1] - lim[0, 0]))
    text = (phrase("{name} at q = {q}", name=arm.name, q=_q_text(arm, qv)) if title is None
            else title)
    traces = _arm_traces(go, dims, SLOT_COLOURS[0], arm.name, "arm",
                         _arm_geometry(arm, qv, fs, dims, frames), text)
    fig = go.Figure(data=traces, layout=_layout(go, arm, lim, dims, text, height))
    return InteractiveFigure(fig, _div_id("arm", arm, qv))


def path_figure(arm: SerialArm, targets: Any, *, frames: bool = False, height: int = 600,
                title: str | None = None, step_labels: Any = None) -> InteractiveFigure:
    """The target moves along a path; at each step every branch that reaches it is drawn.

    A slider (and a play button) moves the target through ``targets``. Each
    branch keeps its colour and its legend entry along the whole path (click
    an entry to hide that branch); a branch that cannot reach a step is left
    out there, and a step no branch reaches says so in the title, with by
    how much it is out of reach.

    Parameters
    ----------
    arm : SerialArm
    targets : sequence of targets
        Anything ``arm.ik`` takes, one per step (e.g. an array ``(m, 4, 4)``
        of poses, or ``(m, 3)`` positions for a position-only arm).
    frames : bool
        Draw the joint frames too.
    height : int
    title : str, optional
    step_labels : sequence of str, optional
        The slider's label of each step; default ``1 .. m``.

    Returns
    -------
    InteractiveFigure

    Raises
    ------
    InputError
        Fewer than 2 targets, a bad target, or labels of the wrong length.
    """
    _check_arm(arm)
    go = _plotly()
    steps = _check_targets(targets)
    m = len(steps)
    labels_given = None if step_labels is None else list(as_texts(step_labels, "step_labels", m))
    height = _check_height(height)
    frames = as_flag(frames, "frames")
    title = as_text(title, "title", optional=True)
    dims = 2 if is_planar(arm) else 3
    results, why = _solve_steps(arm, steps)
    branch_names = _branch_names(results)
    tpos = np.stack([_pose_position(arm, r, t) for r, t in zip(results, steps, strict=True)])
    lim = _limits(arm, _path_points(arm, results, tpos), dims)
    fs = float(FRAME_FRACTION * (lim[0, 1] - lim[0, 0]))
    base = phrase("{name}: the target along a path", name=arm.name) if title is None else title

    def step_data(s: int) -> tuple[list[dict[str, Any]], str]:
        r = results[s]
        data: list[dict[str, Any]] = []
        for b in branch_names:
            q = None
            if r is not None and b in r.labels:
                q = np.asarray(r.q[r.labels.index(b)])
            data += _arm_geometry(arm, q, fs, dims, frames)
        data.append(_xyz(tpos[s:s + 1], dims))
        if r is None:
            text = phrase("step {s}: unreachable: {why}", s=s + 1, why=why[s])
        else:
            text = phrase(f"step {{s}}: {{n}} solution{'s' if len(r) != 1 else ''}", s=s + 1,
                          n=len(r))
        return data, text

    first, first_text = step_data(0)
    traces = _branch_traces(go, dims, branch_names, first)
    Scatter = go.Scatter3d if dims == 3 else go.Scatter
    traces.append(_target_trace(go, dims, tpos[0]))
    traces.append(Scatter(mode="lines", name=phrase("path"), hoverinfo="skip",
                          line={"color": "#d62728", "width": 2, "dash": "dot"},
                          **_xyz(tpos, dims)))
    frames_out = _path_frames(go, Scatter, m, len(branch_names), step_data, base)
    names = labels_given if labels_given is not None else [str(s + 1) for s in range(m)]
    layout = _layout(go, arm, lim, dims, f"{base}<br>{first_text}", height)
    layout["sliders"] = [_path_slider(names)]
    layout["updatemenus"] = [_play_button()]
    layout["margin"]["b"] += 100
    layout["annotations"][0]["yshift"] = -110
    fig = go.Figure(data=traces, layout=layout, frames=frames_out)
    return InteractiveFigure(fig, _div_id("path", arm, tpos))


def _path_points(arm: SerialArm, results: list[IKResult | None],
                 tpos: FloatArray) -> FloatArray:
    """Every point the path's figure must hold ``(k, 3)``: the targets' positions and
    every frame origin of every solution at every step."""
    allpts = [tpos]
    for r in results:
        if r is not None:
            allpts.append(arm._fk(np.asarray(r.q), frames=True)[:, :, :3, 3].reshape(-1, 3))
    return np.vstack(allpts)


def _branch_traces(go: Any, dims: int, branch_names: list[str],
                   first: list[dict[str, Any]]) -> list[Any]:
    """One arm's traces per branch, in the branch's colour, drawn at the first step's data
    (TRACES_PER_ARM geometries per branch in ``first``)."""
    traces: list[Any] = []
    for j, b in enumerate(branch_names):
        name = branch_name(b)
        traces += _arm_traces(go, dims, SLOT_COLOURS[j % len(SLOT_COLOURS)], name, f"b{j}",
                              first[j * TRACES_PER_ARM:(j + 1) * TRACES_PER_ARM], name)
    return traces


def _path_frames(go: Any, Scatter: Any, m: int, nb: int,
                 step_data: Callable[[int], tuple[list[dict[str, Any]], str]],
                 base: str) -> list[Any]:
    """The animation's frames ``step0 .. step{m-1}``: each moves the ``nb`` branches' arms
    and the target (the first traces) to ``step_data(s)`` and retitles the figure."""
    moving = list(range(nb * TRACES_PER_ARM + 1))
    frames_out = []
    for s in range(m):
        data, text = step_data(s)
        frames_out.append(go.Frame(
            name=f"step{s}", traces=moving,
            data=[Scatter(**d) for d in data],
            layout={"title": {"text": _title(f"{base}<br>{text}")}}))
    return frames_out


def _check_targets(targets: Any) -> list[Any]:
    """The path's targets as a list, at least 2 (each is checked by ``arm.ik``)."""
    if isinstance(targets, (str, bytes)) or not hasattr(targets, "__len__") or (
            isinstance(targets, np.ndarray) and targets.ndim == 0):
        raise InputError(f"targets must be a sequence of targets (e.g. an array (m, 4, 4)), "
                         f"got {type(targets).__name__}")
    steps = list(targets)
    if len(steps) < 2:
        raise InputError(f"a path needs at least 2 targets, got {len(steps)}")
    return steps


def _solve_steps(arm: SerialArm, steps: list[Any]) -> tuple[list[IKResult | None], list[str]]:
    """Every step's IK result, or None and why (unreachable); a bad target is an error."""
    results: list[IKResult | None] = []
    why: list[str] = []
    for t in steps:
        try:
            results.append(arm.ik(t))
            why.append("")
        except InputError as exc:
            raise InputError(f"targets[{len(results)}]: {exc}") from None
        except RikinError as exc:       # unreachable (or another IK error): say why
            results.append(None)
            why.append(str(exc))
    return results, why


def _branch_names(results: list[IKResult | None]) -> list[str]:
    """Every branch that reaches some step, in the order they first appear."""
    branch_names: list[str] = []
    for r in results:
        for lab in (r.labels if r is not None else ()):
            if lab not in branch_names:
                branch_names.append(lab)
    if not branch_names:
        raise InputError("no target on the path is reachable: there is nothing to draw")
    return branch_names


def _path_slider(names: list[str]) -> dict[str, Any]:
    """The slider that moves the target: one step per name (frames ``step0``, ...).

    It starts clear of the play button (about 65 px) on a phone too, and says which step
    it is at its right end, away from the button."""
    steps = [{"label": name, "method": "animate",
              "args": [[f"step{s}"], {"mode": "immediate",
                                      "frame": {"duration": 0, "redraw": True},
                                      "transition": {"duration": 0}}]}
             for s, name in enumerate(names)]
    return {"active": 0, "steps": steps, "x": 0.2, "len": 0.8, "y": -0.02,
            "yanchor": "top", "currentvalue": {"prefix": phrase("target") + " ", "xanchor": "right",
                                               "font": {"size": 12}},
            "pad": {"t": 30}}


def _play_button() -> dict[str, Any]:
    """The play button, left of :func:`_path_slider`: it runs through the steps."""
    return {"type": "buttons", "showactive": False, "x": 0.0, "y": -0.02, "xanchor": "left",
            "yanchor": "top", "pad": {"t": 40},
            "buttons": [{"label": phrase("▶ play"), "method": "animate",
                         "args": [None, {"frame": {"duration": 120, "redraw": True},
                                         "fromcurrent": True, "transition": {"duration": 0}}]}]}


def _pose_position(arm: SerialArm, result: IKResult | None, target: Any) -> FloatArray:
    """The target's position (3,) for drawing, reachable or not."""
    if result is not None:
        return np.asarray(result.target[:3, 3], dtype=np.float64)
    t = as_float_array(target, "target")
    if t.shape == (4, 4):
        return t[:3, 3]
    p = np.zeros(3)
    n = min(len(t), 3 if not is_planar(arm) else 2)
    p[:n] = t[:n]
    return p
