"""Live arm GUIs for Jupyter, JupyterLab and Colab: the lab's pose panel and teach().

``pip install "rikin[widgets]"`` (ipywidgets). Both panels redraw a
matplotlib figure into an image widget, so they need nothing but
ipywidgets in the front end (no extra JavaScript extension) and work the
same in classic Jupyter, JupyterLab, VS Code and Colab.

* :func:`ik_panel` -- the Epson lab's GUI: sliders for the target's x, y, z
  and roll, pitch, yaw (x, y and the tool angle for a planar arm; x, y, z
  for a position-only arm); every IK solution is drawn live with its
  branch name, listed in a table, and an unreachable target is reported in
  words with how far out of reach it is.
* :func:`teach` -- joint sliders (degrees for revolute joints): the arm is
  drawn by forward kinematics and the TCP pose printed, like the
  ``teach()`` pendant of the lessons' toolbox.

Both return the panel object; display it as a cell's last expression. Its
``state`` (and the methods that compute it) can be used without a front
end, which is how the tests drive it.

Examples
--------
>>> import rikin
>>> from rikin import widgets                       # doctest: +SKIP
>>> widgets.ik_panel(rikin.robots.aula10_6r())     # doctest: +SKIP
>>> widgets.teach(rikin.robots.epson_c4())         # doctest: +SKIP
"""

from __future__ import annotations

import html
import importlib
import io
import math
import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ._validate import (
    FloatArray,
    as_flag,
    as_pose,
    as_positive,
    as_real,
    as_text,
    check_length_range,
)
from .dh import SerialArm
from .dhtext import arm_from_table, row_tokens
from .errors import InputError, RikinError, UnreachableError
from .i18n import branch_name, phrase, word
from .ik import classify, ik_numerical
from .ik.result import IKResult
from .plot import _check_arm, _q_text
from .transforms import homogeneous, r_to_rpy, rotz, rpy_to_r, wrap_angle

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["DHPanel", "EXAMPLES", "IKPanel", "PUMA560_TABLE", "TeachPanel", "arm_from_table",
           "dh_panel", "ik_panel", "pose_sliders_for", "teach"]

#: Pixel density of the redrawn figure.
DPI = 80
#: The panels' drawings are sized for a 1000 px notebook column (JupyterLab on a 1366 x 768
#: laptop screen with its file browser open): at most this wide, in inches at DPI (960 px).
DRAWING_WIDTH = 12.0
#: One solution's drawing at most this wide (inches): one or two solutions are not blown up.
PANEL_MAX = 3.6
#: The teach pendant's drawing and the drawing of a target out of reach (inches).
SMALL_DRAWING = 4.8


def _solutions_figsize(width: float, k: int) -> tuple[tuple[float, float], int]:
    """(figsize, columns) for k solutions side by side within ``width`` inches."""
    cols = min(k, 4)
    rows = -(-k // cols)
    panel = min(width / cols, PANEL_MAX)
    return (panel * cols, panel * 1.15 * rows + 0.5), cols


def _unit(unit: str) -> str:
    """A slider's unit as a panel shows it: degrees (``"deg"``) in the current language."""
    return phrase(unit) if unit == "deg" else unit


def plain_unreachable(exc: UnreachableError) -> str:
    """An UnreachableError in plain words, how far first.

    "out of reach by 451.4 mm: the wrist centre is 951.4 mm from the shoulder axis, links
    2-3 reach 500 mm" (the arm's name, "target is unreachable" and the note on rounded
    poses are left out: the panel says them elsewhere, or they are not for a slider).
    """
    units = f" {exc.units}" if getattr(exc, "units", "") else ""
    text = re.sub(r"^.*?target is unreachable:\s*", "", str(exc))
    text = re.sub(r"\s*\(a pose up to [^()]* off is taken as rounded[^()]*\)", "", text)
    m = re.match(r"(?P<what>.+?) is [\d.eE+-]+(?: \w+)? beyond the reach of (?P<links>links "
                 r"[\d-]+) \((?:it is (?P<dist>[\d.eE+-]+)(?: \w+)? from the (?P<from>[^;]+)|"
                 r"distance (?P<dist2>[\d.eE+-]+) from (?P<from2>[^,]+)); (?:links [\d-]+ )?"
                 r"reach (?P<reach>[\d.eE+-]+)(?: \w+)?\)$", text.replace(", reach", "; reach"))
    if m:
        dist = float(m["dist"] or m["dist2"])
        where = f"the {m['from']}" if m["from"] else m["from2"]
        text = (f"{m['what']} is {dist:.4g}{units} from {where}, "
                f"{m['links']} reach {float(m['reach']):.4g}{units}")
    excess = float(getattr(exc, "excess", float("nan")))
    head = (phrase("out of reach by {excess}", excess=f"{excess:.4g}{units}")
            if math.isfinite(excess) else phrase("out of reach"))
    return f"{head}: {text}" if text else head


def _ipywidgets() -> Any:
    try:
        return importlib.import_module("ipywidgets")
    except ImportError as exc:
        raise RikinError(
            "the live panels need ipywidgets: pip install 'rikin[widgets]' "
            "(or pip install 'ipywidgets>=8,<9'); Colab has it already"
        ) from exc


def _figure_of(ax: Axes) -> Figure:
    """The figure rikin.plot drew ``ax`` in (its root figure: never a subfigure)."""
    fig = ax.get_figure(root=True)
    if fig is None:  # rikin.plot always draws into a figure
        raise RikinError("the drawing's Axes belong to no figure")
    return fig


def _png(fig: Any) -> bytes:
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    plt.close(fig)
    return buf.getvalue()


#: What a panel's still picture says. The picture is the panel's output wherever the page
#: cannot show widgets: a JupyterLab or Notebook page opened before ipywidgets was installed
#: (they load the widget support when a page opens), a static viewer.
STILL_NOTE = ("A still picture of the live panel: this page cannot show widgets yet. "
              "After rikin's first install, reload the page (F5), then run the notebook "
              "again (Run All): JupyterLab and Jupyter Notebook load the widget support "
              "when a page opens.")


def _png_html(fig: Any, alt: str) -> str:
    """A matplotlib figure as an ``<img>`` (embedded PNG), sized to its panel."""
    import base64

    data = base64.b64encode(_png(fig)).decode("ascii")
    return (f'<img src="data:image/png;base64,{data}" alt="{html.escape(alt)}" '
            'style="max-width:100%;height:auto">')


def _still_bundle(panel: Any, refused: bool = False) -> dict[str, str]:
    """The panel as it looks now, as a still picture with :data:`STILL_NOTE` (no widgets).

    ``refused``: the page has refused the live panel (its ``div`` says so, for tests)."""
    note = (f'<p class="rikin-still-note" style="color:#8a4b00;font-size:90%">'
            f"{html.escape(phrase(STILL_NOTE))}</p>")
    div = '<div class="rikin-still"' + (' data-refused="1">' if refused else ">")
    return {"text/html": div + note + panel.still_html() + "</div>",
            "text/plain": f"<rikin {type(panel).__name__}: {phrase(STILL_NOTE)}>"}


def _display_panel(panel: Any) -> None:
    """Display a panel: the live widget, and its still picture for a page without widgets.

    The output carries both: a front end with the widget manager shows the widget; one
    without it (JupyterLab opened before ipywidgets was installed) shows the still
    picture and says how to get the live panel. Such a front end refuses the widget's
    comm; the kernel then replaces the output by the still picture alone, so the saved
    notebook holds no widget that would look alive after a reload and do nothing.
    """
    from IPython.display import display

    box = panel.widget()
    still = _still_bundle(panel)
    bundle = {**dict(box._repr_mimebundle_() or {}), **still}
    handle = display(bundle, raw=True, display_id=True)
    comm = getattr(box, "comm", None)
    if handle is None or comm is None or not hasattr(comm, "on_close"):
        return

    def refused(_msg: Any = None) -> None:
        panel.frontend_refused = True
        handle.update(_still_bundle(panel, refused=True), raw=True)

    comm.on_close(refused)


def _reach(arm: SerialArm) -> float:
    """A generous bound on how far the TCP gets from the base: every link and the tool."""
    total = sum(abs(float(lk.a)) + abs(float(lk.d)) for lk in arm.links)
    for lk, lim in zip(arm.links, arm.qlim, strict=True):
        if not lk.is_revolute and np.isfinite(lim).all():
            total += float(np.abs(lim).max())
    return total + float(np.linalg.norm(arm.tool[:3, 3]))


def pose_sliders_for(arm: SerialArm) -> list[tuple[str, str, float, float]]:
    """The target coordinates the arm's IK takes, each with its slider range.

    Returns
    -------
    list of (name, unit, low, high)
        ``x, y, z`` (length units) and ``roll, pitch, yaw`` (degrees) for a
        6-DOF pose; ``x, y, z`` for a position-only arm; ``x, y`` and
        ``phi`` (degrees) for a planar arm.
    """
    _check_arm(arm)
    if arm.solver is not None:
        kind = arm.solver.target_kind
    else:  # an arm typed from its DH table: the general 6R solver, when classify allows it
        verdict = classify(arm)
        if not verdict.closed_form:
            raise InputError(f"{arm.name!r} has no closed-form IK in rikin, so no IK panel: "
                             f"{verdict.reason}")
        kind = "pose"
    r = _reach(arm)
    c = arm.base[:3, 3]
    u = arm.units
    lin = [(name, u, float(c[k] - r), float(c[k] + r)) for k, name in enumerate("xyz")]
    if kind == "pose":
        return lin + [(name, "deg", -180.0, 180.0) for name in ("roll", "pitch", "yaw")]
    if kind == "position":
        return lin
    if kind == "planar_pose":
        return lin[:2] + [("phi", "deg", -180.0, 180.0)]
    return lin[:2]


@dataclass
class IKState:
    """What the IK panel shows for one target.

    Attributes
    ----------
    target : ndarray, shape (4, 4)
        The target pose in the world frame.
    result : IKResult or None
        None when the target is out of reach.
    message : str
        The status line in words ("8 solutions", "unreachable: ...").
    excess : float or None
        How far out of reach, in ``excess_units`` (None when reachable).
    """

    target: FloatArray
    result: IKResult | None
    message: str
    excess: float | None = None
    excess_units: str = ""
    labels: tuple[str, ...] = field(default_factory=tuple)


def _slider_value(v: Any, name: str) -> float:
    try:
        return as_real(v, name)
    except InputError as exc:
        raise InputError(f"{name} must be a finite number, got {v!r:.60} ({exc})") from None


class IKPanel:
    """The lab's pose panel: target sliders, every IK solution drawn live (see :func:`ik_panel`)."""

    def __init__(self, arm: SerialArm, values: dict[str, float] | None = None,
                 width: float = DRAWING_WIDTH) -> None:
        _check_arm(arm)
        self.arm = arm
        self.spec = pose_sliders_for(arm)
        self.width = float(as_positive(width, "width"))  # type: ignore[arg-type]
        self.values = {name: 0.5 * (lo + hi) for name, _, lo, hi in self.spec}
        if values is None:
            values = self._home_values()
        elif not isinstance(values, dict) or not all(isinstance(k, str) for k in values):
            raise InputError(f"values must be a dict of target coordinates by name, e.g. "
                             f"{{'x': 1.0}}, got {values!r:.80}")
        try:
            self.set(**values, redraw=False)
        except InputError as exc:
            raise InputError(f"values: {exc}") from None
        self.state = self.compute()
        self._widget: Any = None

    # ---- the computation (no front end needed)
    def _home_values(self) -> dict[str, float]:
        """The pose of a comfortable configuration: every revolute joint at 20 degrees."""
        q = np.where(self.arm.revolute, np.radians(20.0), 0.0)
        lo, hi = self.arm.qlim[:, 0], self.arm.qlim[:, 1]
        q = np.where(np.isfinite(lo) & (q < lo), lo, q)
        q = np.where(np.isfinite(hi) & (q > hi), hi, q)
        return self.values_of(self.arm.fk(q))

    def values_of(self, T: Any) -> dict[str, float]:
        """Slider values of a world pose ``T`` (4, 4)."""
        T = as_pose(T, "T")
        if T.shape != (4, 4):
            raise InputError(f"T must be one world pose of shape (4, 4), got shape {T.shape}")
        names = [s[0] for s in self.spec]
        out = {k: float(T[i, 3]) for i, k in enumerate("xyz") if k in names}
        if "roll" in names:
            out.update(zip(("roll", "pitch", "yaw"), map(float, r_to_rpy(T[:3, :3], degrees=True)),
                           strict=True))
        if "phi" in names:
            out["phi"] = float(np.degrees(np.arctan2(T[1, 0], T[0, 0])))
        return out

    def set(self, redraw: bool = True, **values: float) -> None:
        """Set target coordinates by name (``x=..., yaw=...``); degrees for angles."""
        redraw = as_flag(redraw, "redraw")
        names = {s[0] for s in self.spec}
        for k, v in values.items():
            if k not in names:
                raise InputError(f"{self.arm.name!r} has no target coordinate {k!r}; it takes "
                                 + ", ".join(s[0] for s in self.spec))
            self.values[k] = _slider_value(v, k)
            if k in ("x", "y", "z"):
                check_length_range(abs(self.values[k]), k)
        if redraw:
            self.state = self.compute()
            self._refresh()

    def target(self) -> FloatArray:
        """The target pose (4, 4) the sliders describe."""
        v = self.values
        if "roll" in v:
            R = rpy_to_r(v["roll"], v["pitch"], v["yaw"], degrees=True)
        elif "phi" in v:
            R = rotz(np.radians(v["phi"]))
        else:
            R = np.eye(3)
        return homogeneous(R, np.array([v["x"], v["y"], v.get("z", 0.0)]))

    def compute(self) -> IKState:
        """All IK solutions of the current target, or why there are none."""
        T = self.target()
        try:
            res = self.arm.ik(T)
        except UnreachableError as exc:
            units = getattr(exc, "units", "") or ""
            return IKState(T, None, plain_unreachable(exc), float(exc.excess), units)
        except RikinError as exc:
            return IKState(T, None, phrase("no solution: {why}", why=exc))
        n = len(res)
        msg = phrase("{n} solution" if n == 1 else "{n} solutions", n=n)
        if res.singular:
            msg += phrase(" (singular: {why})", why=res.singularity)
        if res.discarded:
            msg += phrase("; {k} more outside the joint limits", k=res.discarded)
        return IKState(T, res, msg, labels=res.labels)

    def figure(self) -> Any:
        """The current drawing: every solution side by side (or the arm's reach if none)."""
        from .plot import plot_arm, plot_solutions

        st = self.state
        if st.result is not None:
            size, cols = _solutions_figsize(self.width, len(st.result))
            return plot_solutions(self.arm, st.result, ncols=cols, figsize=size)
        ax = plot_arm(self.arm, np.zeros(self.arm.n), frames=False,
                      title=phrase("{name}: target out of reach\n(the arm at q = 0 for scale)",
                                   name=self.arm.name))
        p = st.target[:3, 3]
        three_d = ax.name == "3d"
        ax.plot(*p[:3 if three_d else 2], "o", ms=13, mfc="none", mec="tab:red", mew=2.0,
                ls="none", gid="target")
        fig = _figure_of(ax)
        fig.set_size_inches(SMALL_DRAWING, SMALL_DRAWING)
        return fig

    def table_html(self) -> str:
        """The solutions as an HTML table (branch and joint values), or the status in words."""
        st = self.state
        if st.result is None:
            return f'<p style="color:#b00"><b>{html.escape(st.message)}</b></p>'
        from .tables import solutions_table

        return (f"<p><b>{html.escape(st.message)}</b></p>"
                + solutions_table(st.result, arm=self.arm)._repr_html_())

    def still_html(self) -> str:
        """The panel as it looks now, without widgets: the target, the solutions, the drawing."""
        values = ", ".join(f"{name} = {self.values[name]:.4g}{' ' + _unit(unit) if unit else ''}"
                           for name, unit, _, _ in self.spec)
        target = phrase("target {values}", values=values)
        return (f"<p><b>{html.escape(self.arm.name)}</b>: {html.escape(target)}</p>"
                + self.table_html() + _png_html(self.figure(), f"{self.arm.name}: "
                                                 f"{self.state.message}"))

    # ---- the widget
    def _refresh(self) -> None:
        if self._widget is None:
            return
        self._image.value = _png(self.figure())
        self._table.value = self.table_html()

    def widget(self) -> Any:
        """The ipywidgets box (built once)."""
        if self._widget is not None:
            return self._widget
        w = _ipywidgets()
        self._sliders = {}
        for name, unit, lo, hi in self.spec:
            step = 1.0 if unit == "deg" else float(10 ** np.floor(np.log10((hi - lo) / 200)))
            s = w.FloatSlider(value=self.values[name], min=lo, max=hi, step=step,
                              description=f"{name} ({_unit(unit)})" if unit else name,
                              continuous_update=False, readout_format=".4g",
                              style={"description_width": "70px"},
                              layout=w.Layout(width="auto"))
            s.observe(self._on_slider, names="value")
            self._sliders[name] = s
        self._image = w.Image(format="png", layout=w.Layout(max_width="100%", height="auto"))
        self._table = w.HTML(layout=w.Layout(max_width="100%", overflow="auto"))
        # the sliders side by side where the column is wide (x y z / roll pitch yaw in a
        # 1000 px column), one under the other where it is not
        grid = w.GridBox(list(self._sliders.values()), layout=w.Layout(
            grid_template_columns="repeat(auto-fill, minmax(290px, 1fr))", width="auto"))
        box = w.VBox([w.HTML(f"<b>{html.escape(self.arm.name)}</b>: " + html.escape(phrase(
                             "move the target; every IK solution is drawn with its branch"))),
                      grid, self._table, self._image],
                     layout=w.Layout(width="auto", max_width="100%"))
        self._widget = box
        self._refresh()
        return box

    def _on_slider(self, change: dict[str, Any]) -> None:
        for name, s in self._sliders.items():
            if s is change["owner"]:
                self.set(**{name: change["new"]})

    def _ipython_display_(self) -> None:
        _display_panel(self)


class TeachPanel:
    """The lessons' ``teach()``: joint sliders, the arm drawn by FK (see :func:`teach`)."""

    def __init__(self, arm: SerialArm, q: Any = None, width: float = SMALL_DRAWING) -> None:
        _check_arm(arm)
        self.arm = arm
        self.width = float(as_positive(width, "width"))  # type: ignore[arg-type]
        self.q = np.zeros(arm.n) if q is None else arm.check_q(q).astype(np.float64).copy()
        if self.q.shape != (arm.n,):
            raise InputError(f"q must be one configuration of shape ({arm.n},)")
        self._widget: Any = None

    def ranges(self) -> list[tuple[str, str, float, float]]:
        """Per joint: name, unit, low, high (degrees for revolute joints)."""
        out = []
        for i, (lk, lim) in enumerate(zip(self.arm.links, self.arm.qlim, strict=True), 1):
            if lk.is_revolute:
                lo = np.degrees(lim[0]) if np.isfinite(lim[0]) else -180.0
                hi = np.degrees(lim[1]) if np.isfinite(lim[1]) else 180.0
                out.append((f"q{i}", "deg", float(lo), float(hi)))
            else:
                r = _reach(self.arm)
                lo = lim[0] if np.isfinite(lim[0]) else -r
                hi = lim[1] if np.isfinite(lim[1]) else r
                out.append((f"q{i}", self.arm.units, float(lo), float(hi)))
        return out

    def set(self, redraw: bool = True, **values: float) -> None:
        """Set joints by name, ``q1=30`` (degrees for revolute joints, length units else)."""
        redraw = as_flag(redraw, "redraw")
        for k, v in values.items():
            if not (k.startswith("q") and k[1:].isdigit() and 1 <= int(k[1:]) <= self.arm.n):
                raise InputError(f"no joint {k!r}: the joints are q1..q{self.arm.n}")
            i = int(k[1:]) - 1
            fv = _slider_value(v, k)
            self.q[i] = np.radians(fv) if self.arm.links[i].is_revolute else fv
        if redraw:
            self._refresh()

    def pose_text(self) -> str:
        """The TCP pose in words: position and roll, pitch, yaw (degrees)."""
        T = self.arm.fk(self.q)
        u = f" {self.arm.units}" if self.arm.units else ""
        rpy = r_to_rpy(T[:3, :3], degrees=True)
        return phrase("q = {q} → TCP at ({x}, {y}, {z}){units}, roll {roll}°, pitch {pitch}°, "
                      "yaw {yaw}°", q=_q_text(self.arm, self.q), x=f"{T[0, 3]:.4g}",
                      y=f"{T[1, 3]:.4g}", z=f"{T[2, 3]:.4g}", units=u, roll=f"{rpy[0]:.2f}",
                      pitch=f"{rpy[1]:.2f}", yaw=f"{rpy[2]:.2f}")

    def figure(self) -> Any:
        from .plot import plot_arm

        ax = plot_arm(self.arm, self.q, title=f"{self.arm.name} (teach)")
        fig = _figure_of(ax)
        fig.set_size_inches(self.width, self.width)
        return fig

    def still_html(self) -> str:
        """The pendant as it looks now, without widgets: the pose and the drawing."""
        return (f"<p><code>{html.escape(self.pose_text())}</code></p>"
                + _png_html(self.figure(), phrase("{name} at the sliders' joint values",
                                                  name=self.arm.name)))

    def _refresh(self) -> None:
        if self._widget is None:
            return
        self._image.value = _png(self.figure())
        self._readout.value = f"<code>{html.escape(self.pose_text())}</code>"

    def widget(self) -> Any:
        if self._widget is not None:
            return self._widget
        w = _ipywidgets()
        self._sliders = []
        for i, (name, unit, lo, hi) in enumerate(self.ranges()):
            value = np.degrees(self.q[i]) if unit == "deg" else self.q[i]
            s = w.FloatSlider(value=float(np.clip(value, lo, hi)), min=lo, max=hi,
                              step=1.0 if unit == "deg" else (hi - lo) / 200,
                              description=f"{name} ({_unit(unit)})" if unit else name,
                              continuous_update=False, readout_format=".4g",
                              style={"description_width": "70px"},
                              layout=w.Layout(width="auto"))
            s.observe(self._on_slider, names="value")
            self._sliders.append(s)
        self._image = w.Image(format="png", layout=w.Layout(max_width="100%", height="auto",
                                                              flex="0 1 auto"))
        self._readout = w.HTML()
        # the sliders beside the drawing (and under it where the column is narrow)
        controls = w.VBox([*self._sliders, self._readout],
                          layout=w.Layout(flex="1 1 300px", min_width="260px", max_width="100%"))
        self._widget = w.HBox([controls, self._image], layout=w.Layout(
            flex_flow="row wrap", align_items="flex-start", width="auto", max_width="100%"))
        self._refresh()
        return self._widget

    def _on_slider(self, change: dict[str, Any]) -> None:
        i = self._sliders.index(change["owner"])
        self.set(**{f"q{i + 1}": change["new"]})

    def _ipython_display_(self) -> None:
        _display_panel(self)


#: The table :func:`dh_panel` starts with: the Puma 560 in standard DH, metres and degrees
#: (Corke and Armstrong-Hélouvry 1994, as in roboticstoolbox's ``Puma560``; d1 is the
#: pedestal, 26.45 in).
PUMA560_TABLE = """\
# type d        a       alpha offset
R      0.67183  0        90   0
R      0        0.4318    0   0
R      0.15005  0.0203  -90   0
R      0.4318   0        90   0
R      0        0       -90   0
R      0        0         0   0
"""

#: Tables the DH panel offers to start from: name -> its inputs (see :class:`DHPanel`).
EXAMPLES: dict[str, dict[str, str]] = {
    "Puma 560": {"table": PUMA560_TABLE, "convention": "standard", "units": "m",
                 "tool": "0 0 0", "target": "20 -30 40 10 50 60"},
    "KUKA KR5": {"table": """\
# KUKA KR5 (ARTE): m and degrees
# type d      a     alpha offset
R      0.4    0.18  -90   0
R      0      0.6     0   0
R      0      0.12   90   0
R     -0.62   0     -90   0
R      0      0      90   0
R     -0.115  0     180   0
""", "convention": "standard", "units": "m", "tool": "0 0 0", "target": "20 -40 60 30 40 50"},
    "Epson C4 (modified DH)": {"table": """\
# Epson C4, the lab's arm: mm and degrees
# type d     a    alpha offset
R      320   0      0    0
R      0     100   90   90
R      0     250    0    0
R     -250   0    -90    0
R      0     0     90    0
R      0     0    -90    0
""", "convention": "modified", "units": "mm", "tool": "0 0 -65 180 0 0",
        "target": "30 20 -20 20 40 30"},
    "UR5 (no spherical wrist)": {"table": """\
# Universal Robots UR5: m and degrees
# type d         a         alpha offset
R      0.089159  0          90   0
R      0        -0.425       0   0
R      0        -0.39225     0   0
R      0.10915   0          90   0
R      0.09465   0         -90   0
R      0.0823    0           0   0
""", "convention": "standard", "units": "m", "tool": "0 0 0",
        "target": "30 -60 80 -110 -90 20"},
    # KUKA KR 5 arc (metres), its axes A1..A6 as KUKA's controller counts them: A1, A4 and
    # A6 turn against this table's z axes (-q), the limits as KUKA's data sheet prints
    # them; the same arm as rikin.robots.kuka_kr5_arc (checked there against
    # ROS-Industrial's kuka_kr5_support model), its flange frame KUKA's $FLANGE.
    "KUKA KR 5 arc (as KUKA counts A1-A6)": {"table": """\
# KUKA KR 5 arc: A1, A4, A6 counted against z (-q); limits as printed
| axis | θ        | d     | a    | α   | limits   |
|------|----------|-------|------|-----|----------|
| A1   | -q1      | 0.4   | 0.18 | -90 | ±155     |
| A2   | q2       | 0     | 0.6  | 0   | -180..65 |
| A3   | q3 - 90° | 0     | 0.12 | -90 | -15..158 |
| A4   | -q4      | 0.62  | 0    | 90  | ±350     |
| A5   | q5       | 0     | 0    | -90 | ±130     |
| A6   | -q6      | 0.115 | 0    | 0   | ±350     |
""", "convention": "standard", "units": "m", "tool": "0 0 0 0 0 90",
        "target": "40 -80 100 20 60 -30"},
}

#: The "start from" menu's entry that leaves the typed table as it is.
YOUR_TABLE = "(your table)"

#: The DH panel's help line (HTML; a :func:`rikin.i18n.phrase`).
DH_HELP = ("<b>Your own arm</b>: one row per joint, <code>type d a alpha offset</code> (R or P; "
           "lengths in your units, angles in degrees or with pi: <code>-90</code>, "
           "<code>-90°</code>, <code>-pi/2</code>), or paste a table with a header row naming "
           "its columns in any order (<code>| joint | θ | d | a | α |</code>, joint variables "
           "such as <code>q2 + 90°</code>); press Solve for every IK solution of the target, "
           "drawn.")

#: The column names of a table's header comment (``# type d a alpha offset``), said in the
#: current language word by word (:func:`rikin.i18n.word`).
_HEADER_WORDS = frozenset({"type", "d", "a", "alpha", "offset", "theta"})


def _table_text(table: Any) -> str:
    """A typed table as the panel shows it: its comment lines in the current language (the
    examples' ``# KUKA KR5 (ARTE): m and degrees``, a header comment's column names), the
    rows as typed."""
    lines = []
    for line in str(table).rstrip().split("\n"):
        head, sep, said = line.partition("#")
        if sep and not head.strip() and said.strip():
            if set(said.split()) <= _HEADER_WORDS:
                said = re.sub(r"[a-z]+", lambda m: word(m.group()), said)
            else:
                said = " " + phrase(said.strip())
        lines.append(head + sep + said)
    return "\n".join(lines)


def _numbers(text: Any, count: int, what: str) -> FloatArray:
    """``count`` numbers typed as text (or given as a sequence)."""
    try:
        tokens = row_tokens(text) if isinstance(text, str) else list(np.ravel(
            np.array(text, dtype=object)))
        values = np.array([float(t) if isinstance(t, str) else as_real(t, what) for t in tokens])
    except (TypeError, ValueError):
        raise InputError(f"{what} must be {count} numbers, got {text!r}") from None
    if values.shape != (count,) or not np.isfinite(values).all():
        raise InputError(f"{what} must be {count} finite numbers, got {len(values)}: {text!r}")
    return values


def _tool_pose(text: Any) -> FloatArray:
    """The tool ``T_n_tcp`` from "x y z" or "x y z roll pitch yaw" (degrees)."""
    try:
        tokens = row_tokens(text) if isinstance(text, str) else list(np.ravel(
            np.array(text, dtype=object)))
    except (TypeError, ValueError):
        raise InputError(f"the tool must be 3 or 6 numbers, got {text!r:.80}") from None
    v = _numbers(tokens, 6 if len(tokens) == 6 else 3, "the tool (x y z, or x y z roll pitch yaw)")
    R = rpy_to_r(*v[3:], degrees=True) if len(v) == 6 else np.eye(3)
    return homogeneous(R, v[:3])


@dataclass
class DHState:
    """What the DH-table panel shows.

    Attributes
    ----------
    arm : SerialArm or None
        None when the table could not be read.
    verdict : IKClass or None
        :func:`rikin.ik.classify` of the arm.
    target : ndarray, shape (4, 4), or None
        The world pose solved for.
    result : IKResult or None
        Every closed-form solution (None without a closed form or a reachable target).
    numerical : NumericalIKResult or None
        For an arm without a closed form: one solution from :func:`rikin.ik.ik_numerical`.
    message : str
        The status in words.
    typed_q : ndarray, shape (n,), or None
        The joints the target was made from (target given as joints).
    """

    arm: SerialArm | None
    verdict: Any
    target: FloatArray | None
    result: IKResult | None
    message: str
    numerical: Any = None
    typed_q: FloatArray | None = None


def _check_inputs(inputs: dict[str, Any]) -> None:
    """The panel's text inputs are text (what a user typed is read, and reported in the
    panel's status when it cannot be); the target and the tool may also be numbers."""
    for k in ("table", "convention", "units", "mode", "name"):
        if k in inputs:
            as_text(inputs[k], k)


class DHPanel:
    """Type a DH table, get every IK solution of one pose, drawn (see :func:`dh_panel`)."""

    MODES = ("joints", "pose")

    def __init__(self, table: str = PUMA560_TABLE, convention: str = "standard",
                 units: str = "m", target: Any = "20 -30 40 10 50 60", mode: str = "joints",
                 tool: Any = "0 0 0", name: str = "your arm",
                 width: float = DRAWING_WIDTH) -> None:
        default_name = isinstance(name, str) and name == "your arm"  # in the page's language
        self.inputs: dict[str, Any] = {"table": table, "convention": convention,
                                       "units": units, "target": target, "mode": mode,
                                       "tool": tool,
                                       "name": phrase(name) if default_name else name}
        _check_inputs(self.inputs)
        self.width = float(as_positive(width, "width"))  # type: ignore[arg-type]
        self.state = self.compute()
        self._widget: Any = None

    # ---- the computation (no front end needed)
    def set(self, redraw: bool = True, **inputs: Any) -> None:
        """Change inputs by name: ``table``, ``convention``, ``units``, ``target``,
        ``mode`` ("joints": the target is FK of six joint values, degrees for revolute
        joints; "pose": x y z roll pitch yaw, degrees), ``tool`` (the TCP in the last
        frame: x y z, or x y z roll pitch yaw) and ``name``."""
        redraw = as_flag(redraw, "redraw")
        for k in inputs:
            if k not in self.inputs:
                raise InputError(f"the DH panel has no input {k!r}; it has "
                                 + ", ".join(self.inputs))
        _check_inputs(inputs)
        self.inputs.update(inputs)
        if redraw:
            self.state = self.compute()
            self._refresh()

    def compute(self) -> DHState:
        """Read the table, classify the arm, solve the target: every step's outcome in words."""
        inp = self.inputs
        try:
            if inp["mode"] not in self.MODES:
                raise InputError(f"mode must be 'joints' or 'pose', got {inp['mode']!r}")
            try:
                tool = _tool_pose(inp["tool"])
            except RikinError as exc:  # say it is the tool (not the rows) that is wrong
                why = str(exc) if "tool" in str(exc) else phrase("the tool: {why}", why=exc)
                return DHState(None, None, None, None,
                               phrase("The table cannot be read: {why}", why=why))
            arm = arm_from_table(inp["table"], inp["convention"], inp["units"],
                                 name=str(inp["name"]), tool=tool)
        except RikinError as exc:
            return DHState(None, None, None, None,
                           phrase("The table cannot be read: {why}", why=exc))
        verdict = classify(arm)
        try:
            if inp["mode"] == "joints":
                values = _numbers(inp["target"], arm.n, f"the target joints ({arm.n} values)")
                q = np.where(arm.revolute, np.radians(values), values)
                T, typed = arm.fk(q), q
            else:
                v = _numbers(inp["target"], 6, "the target pose (x y z roll pitch yaw)")
                T, typed = homogeneous(rpy_to_r(*v[3:], degrees=True), v[:3]), None
        except RikinError as exc:
            return DHState(arm, verdict, None, None,
                           phrase("The target cannot be read: {why}", why=exc))
        if not verdict.closed_form:
            return _numerical_state(arm, verdict, T, typed)
        try:  # an arm with joint limits (typed as printed): the solutions they allow
            res = arm.ik(T, within_limits=bool(np.isfinite(arm.qlim).any()))
        except UnreachableError as exc:
            return DHState(arm, verdict, T, None, phrase("Unreachable: {why}", why=exc),
                           typed_q=typed)
        except RikinError as exc:
            return DHState(arm, verdict, T, None, phrase("No solution: {why}", why=exc),
                           typed_q=typed)
        err = _pose_error(arm, res.q, res.target, rotation=_sets_rotation(arm, verdict))
        msg = phrase("{n} solution, each put back through FK: largest pose error {err}"
                     if len(res) == 1 else
                     "{n} solutions, each put back through FK: largest pose error {err}",
                     n=len(res), err=f"{err:.0e}")
        if res.discarded:
            msg += phrase("; {k} more outside the joint limits left out", k=res.discarded)
        if typed is not None:
            d = np.where(arm.revolute, np.abs(wrap_angle(res.q - typed)), np.abs(res.q - typed))
            hit = int(np.argmin(d.max(axis=1))) if len(res) else -1
            if hit >= 0 and d[hit].max() < 1e-6:
                msg += phrase("; the joints you typed are solution {k} ({label})", k=hit + 1,
                              label=branch_name(res.labels[hit]))
        if res.singular:
            msg += phrase(". Singular: {why}", why=res.singularity)
        return DHState(arm, verdict, T, res, msg + ".", typed_q=typed)

    def html(self) -> str:
        """The verdict, the status and the solutions as HTML (after the table as rikin read
        it, when a joint is reversed or has limits)."""
        from .tables import solutions_table, table

        st = self.state
        parts = self._read_back()
        if st.verdict is not None:
            verdict = phrase("{verdict}", verdict=str(st.verdict))  # rikin's words, quoted
            parts.append(f"<p><b>{html.escape(phrase('classify:'))}</b> "
                         f"{html.escape(verdict)}</p>")
        colour = "#b00" if st.result is None else "inherit"
        parts.append(f'<p style="color:{colour}">{html.escape(st.message)}</p>')
        if st.result is not None and len(st.result):
            parts.append(solutions_table(st.result, decimals=1, arm=st.arm)._repr_html_())
        elif st.numerical is not None and st.numerical.success and st.arm is not None:
            qd = np.where(st.arm.revolute, np.degrees(st.numerical.q), st.numerical.q)
            parts.append(table(["", *[f"q{j + 1}" for j in range(st.arm.n)]],
                               [["ik_numerical", *map(float, qd)]], decimals=2)._repr_html_())
        return "\n".join(parts)

    def figure(self) -> Any:
        """Every solution side by side (the arm at q = 0 or the numerical solution else)."""
        from .plot import plot_arm, plot_solutions

        st = self.state
        if st.arm is None:
            return None
        if st.result is not None and len(st.result):
            size, cols = _solutions_figsize(self.width, len(st.result))
            return plot_solutions(st.arm, st.result, ncols=cols, figsize=size)
        q = st.numerical.q if st.numerical is not None and st.numerical.success else None
        title = phrase("{name}: ik_numerical's solution" if q is not None else
                       "{name}: the arm at q = 0", name=st.arm.name)
        ax = plot_arm(st.arm, np.zeros(st.arm.n) if q is None else q, frames=True, title=title)
        fig = _figure_of(ax)
        fig.set_size_inches(SMALL_DRAWING, SMALL_DRAWING)
        return fig

    def text_html(self) -> str:
        """The panel's text as it looks, without a kernel: the typed table, the verdict
        and the solutions (:meth:`static_html` without the drawing), for a page that shows
        :meth:`figure` as a figure of its own."""
        return self._static_div(self._text_rows())

    def static_html(self, alt: str = "") -> str:
        """The panel as it looks, without a kernel: the typed table, the verdict, the
        solutions and the drawing (an embedded PNG), for a page built without one."""
        alt = str(as_text(alt, "alt"))
        rows = self._text_rows()
        fig = self.figure()
        if fig is not None:
            rows.append(_png_html(fig, alt))
        return self._static_div(rows)

    def _text_rows(self) -> list[str]:
        inp = self.inputs
        said = phrase("({convention} DH, {units}; tool at ({tool}); target joints ({target}))"
                      if inp["mode"] == "joints" else
                      "({convention} DH, {units}; tool at ({tool}); target pose ({target}))",
                      convention=word(str(inp["convention"])),
                      units=str(inp["units"]) or phrase("no units"), tool=str(inp["tool"]),
                      target=str(inp["target"]))
        return [f"<p><b>{html.escape(phrase('DH table'))}</b> {html.escape(said)}</p>",
                f'<pre class="rikin-dh-table">{html.escape(_table_text(inp["table"]))}</pre>',
                self.html()]

    def _read_back(self) -> list[str]:
        """The table as rikin read it, when that says more than the typed text can be
        trusted to: which joints turn against their z axis (``−q1``) and the limits."""
        from .tables import dh_table

        arm = self.state.arm
        if arm is None:
            return []
        limits = bool(np.isfinite(arm.qlim).any())
        if not arm.reversed_joints and not limits:
            return []
        return [dh_table(arm, limits=limits)._repr_html_()]

    @staticmethod
    def _static_div(rows: list[str]) -> str:
        return ('<div class="rikin-dh-panel" style="text-align:left">' + "\n".join(rows)
                + "</div>")

    def still_html(self) -> str:
        """The panel as it looks now, without widgets (:meth:`static_html`)."""
        return self.static_html(alt=phrase("every IK solution of the target, drawn"))

    # ---- the widget
    def _refresh(self) -> None:
        if self._widget is None:
            return
        self._out.value = self.html()
        fig = self.figure()
        self._image.value = _png(fig) if fig is not None else b""
        self._image.layout.display = None if fig is not None else "none"

    def widget(self) -> Any:
        """The ipywidgets box (built once)."""
        if self._widget is not None:
            return self._widget
        w = _ipywidgets()
        full = w.Layout(width="auto")  # stretched by the box, margins included
        style = {"description_width": "100px"}
        inp = self.inputs
        self._fields = {
            "table": w.Textarea(value=_table_text(inp["table"]), description=phrase("DH table"),
                                style=style, layout=w.Layout(width="auto", height="170px")),
            "convention": w.ToggleButtons(options=[(word(c), c) for c in ("standard", "modified")],
                                          value=inp["convention"],
                                          description=phrase("convention"), style=style),
            "name": w.Text(value=str(inp["name"]), description=phrase("name"), style=style,
                           layout=full),
            "units": w.Text(value=str(inp["units"]), description=phrase("units"), style=style,
                            layout=full),
            "tool": w.Text(value=str(inp["tool"]), description=phrase("tool"), style=style,
                           layout=full, placeholder=phrase("x y z  or  x y z roll pitch yaw")),
            "mode": w.ToggleButtons(options=[(phrase(m), m) for m in self.MODES],
                                    value=inp["mode"], description=phrase("target as"),
                                    style=style),
            "target": w.Text(value=str(inp["target"]), description=phrase("target"),
                             style=style, layout=full,
                             placeholder=phrase("q1 ... q6 (deg)  or  x y z roll pitch yaw")),
        }
        self._example = w.Dropdown(
            options=[(phrase(YOUR_TABLE), YOUR_TABLE), *((phrase(k), k) for k in EXAMPLES)],
            value=YOUR_TABLE, description=phrase("start from"), style=style)
        self._example.observe(self._on_example, names="value")
        button = w.Button(description=phrase("Solve"), button_style="primary")
        button.on_click(self._on_solve)
        self._out = w.HTML()
        self._image = w.Image(format="png", layout=w.Layout(max_width="100%"))
        help_text = w.HTML(phrase(DH_HELP))
        self._widget = w.VBox([help_text, self._example, *self._fields.values(), button,
                               self._out,
                               self._image], layout=w.Layout(max_width="100%"))
        self._refresh()
        return self._widget

    def _on_solve(self, _button: Any = None) -> None:
        self.set(**{k: f.value for k, f in self._fields.items()})

    def _on_example(self, change: dict[str, Any]) -> None:
        example = EXAMPLES.get(change["new"])
        if example is None:
            return
        for k, v in {**example, "name": change["new"].split(" (")[0], "mode": "joints"}.items():
            self._fields[k].value = _table_text(v) if k == "table" else v
        self._on_solve()

    def _ipython_display_(self) -> None:
        _display_panel(self)


def _numerical_state(arm: SerialArm, verdict: Any, T: FloatArray,
                     typed: FloatArray | None) -> DHState:
    """The panel's state for an arm without a closed form: the reason, and one solution of
    :func:`rikin.ik.ik_numerical` (the TCP position only for an arm of fewer than six
    joints, which cannot match a whole pose), or why it could not try."""
    why = phrase("No closed form: {why}.", why=verdict.reason)
    mask = None if arm.n >= 6 else (1, 1, 1, 0, 0, 0)
    try:
        num = ik_numerical(arm, T, rng=0, mask=mask)
    except RikinError as exc:
        return DHState(arm, verdict, T, None, why + phrase(
            " rikin.ik.ik_numerical cannot take this arm: {why}", why=exc), typed_q=typed)
    how = (phrase("it found one solution") if num.success else
           phrase("it did not converge ({why})", why=num.reason))
    return DHState(arm, verdict, T, None, why + phrase(
        " rikin.ik.ik_numerical (Levenberg-Marquardt from a seeded start): {how}; "
        "ik_numerical_multistart finds more, with no guarantee of all." if mask is None else
        " rikin.ik.ik_numerical (Levenberg-Marquardt from a seeded start, for the TCP "
        "position): {how}; ik_numerical_multistart finds more, with no guarantee of all.",
        how=how), numerical=num, typed_q=typed)


def _sets_rotation(arm: SerialArm, verdict: Any) -> bool:
    """Whether the arm's IK solves for the target's orientation (an arm of five or six
    joints; a planar 3R's tool angle), not only for its TCP position (a positioning arm
    of three joints, a planar 2R: the orientation then follows from the joints)."""
    return arm.n >= 5 or str(verdict.family).startswith("planar 3R")


def _pose_error(arm: SerialArm, Q: FloatArray, T: FloatArray, rotation: bool = True) -> float:
    """Largest FK error of solutions ``Q`` against the pose ``T`` they solve: position /
    arm size, and the rotation (max abs entry) when ``rotation``."""
    if not len(Q):
        return 0.0
    F = arm.fk(Q)
    pos = np.linalg.norm(F[..., :3, 3] - T[:3, 3], axis=-1) / arm.scale
    if not rotation:
        return float(pos.max())
    rot = np.abs(F[..., :3, :3] - T[:3, :3]).max(axis=(-1, -2))
    return float(max(pos.max(), rot.max()))


def dh_panel(table: str = PUMA560_TABLE, **inputs: Any) -> DHPanel:
    """Type your arm's DH table, see every IK solution of one pose, drawn.

    Parameters
    ----------
    table : str
        One row per joint, ``type d a alpha offset`` (see :func:`arm_from_table`);
        default: the Puma 560.
    **inputs
        ``convention`` ("standard" or "modified"), ``units``, ``tool`` ("x y z" or
        "x y z roll pitch yaw"),
        ``mode`` ("joints" or "pose"), ``target`` (six numbers: joint values in
        degrees, or x y z roll pitch yaw) and ``name``.

    Returns
    -------
    DHPanel
        Displays as the input fields, a Solve button, the verdict of
        :func:`rikin.ik.classify`, the solutions table and the drawing.
    """
    return DHPanel(table, **inputs)


def ik_panel(arm: SerialArm, **values: float) -> IKPanel:
    """The Epson lab's GUI in a notebook: enter a tool pose, see every IK solution.

    Parameters
    ----------
    arm : SerialArm
        An arm with closed-form IK (every arm of :mod:`rikin.robots`).
    **values : float
        Start values of the target by name (``x``, ``y``, ``z`` in length
        units, ``roll``, ``pitch``, ``yaw`` or ``phi`` in degrees); default:
        the pose of a comfortable configuration.

    Returns
    -------
    IKPanel
        Displays as sliders, the solutions table and the drawing.
    """
    panel = IKPanel(arm)
    if values:
        panel.set(redraw=True, **values)
    return panel


def teach(arm: SerialArm, q: Any = None) -> TeachPanel:
    """Joint sliders that move the drawn arm (the lessons' ``teach()`` pendant).

    Parameters
    ----------
    arm : SerialArm
    q : array_like, shape (n,), optional
        Start configuration (radians for revolute joints); default zeros.

    Returns
    -------
    TeachPanel
    """
    return TeachPanel(arm, q)
