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
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._validate import FloatArray
from .dh import SerialArm
from .errors import InputError, RikinError, UnreachableError
from .ik.result import IKResult
from .plot import _check_arm, _q_text
from .transforms import homogeneous, r_to_rpy, rotz, rpy_to_r

__all__ = ["IKPanel", "TeachPanel", "ik_panel", "pose_sliders_for", "teach"]

#: Pixel density of the redrawn figure.
DPI = 80


def _ipywidgets() -> Any:
    try:
        return importlib.import_module("ipywidgets")
    except ImportError as exc:
        raise RikinError(
            "the live panels need ipywidgets: pip install 'rikin[widgets]' "
            "(or pip install 'ipywidgets>=8,<9'); Colab has it already"
        ) from exc


def _png(fig: Any) -> bytes:
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    plt.close(fig)
    return buf.getvalue()


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
    if arm.solver is None:
        raise InputError(f"{arm.name!r} has no closed-form IK in rikin, so no IK panel")
    kind = arm.solver.target_kind
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


class IKPanel:
    """The lab's pose panel: target sliders, every IK solution drawn live (see :func:`ik_panel`)."""

    def __init__(self, arm: SerialArm, values: dict[str, float] | None = None,
                 width: float = 9.0) -> None:
        _check_arm(arm)
        self.arm = arm
        self.spec = pose_sliders_for(arm)
        self.width = float(width)
        self.values = {name: 0.5 * (lo + hi) for name, _, lo, hi in self.spec}
        if values is None:
            values = self._home_values()
        self.set(**values, redraw=False)
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
        T = np.asarray(T, dtype=np.float64)
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
        names = {s[0] for s in self.spec}
        for k, v in values.items():
            if k not in names:
                raise InputError(f"{self.arm.name!r} has no target coordinate {k!r}; it takes "
                                 + ", ".join(s[0] for s in self.spec))
            fv = float(v)
            if not np.isfinite(fv):
                raise InputError(f"{k} must be a finite number, got {v!r}")
            self.values[k] = fv
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
            ex = float(exc.excess)
            return IKState(T, None, f"unreachable: {ex:.4g} {units} out of reach. {exc}".replace(
                "  ", " "), ex, units)
        except RikinError as exc:
            return IKState(T, None, f"no solution: {exc}")
        n = len(res)
        msg = f"{n} solution{'s' if n != 1 else ''}"
        if res.singular:
            msg += f" (singular: {res.singularity})"
        if res.discarded:
            msg += f"; {res.discarded} more outside the joint limits"
        return IKState(T, res, msg, labels=res.labels)

    def figure(self) -> Any:
        """The current drawing: every solution side by side (or the arm's reach if none)."""
        from .plot import plot_arm, plot_solutions

        st = self.state
        if st.result is not None:
            k = len(st.result)
            cols = min(k, 4)
            rows = -(-k // cols)
            return plot_solutions(self.arm, st.result, ncols=cols,
                                  figsize=(self.width, self.width / cols * 1.15 * rows + 0.4))
        ax = plot_arm(self.arm, np.zeros(self.arm.n), frames=False,
                      title=f"{self.arm.name}: target out of reach (the arm at q = 0 for scale)")
        p = st.target[:3, 3]
        three_d = ax.name == "3d"
        ax.plot(*p[:3 if three_d else 2], "o", ms=13, mfc="none", mec="tab:red", mew=2.0,
                ls="none", gid="target")
        fig = ax.figure
        fig.set_size_inches(self.width * 0.6, self.width * 0.6)
        return fig

    def table_html(self) -> str:
        """The solutions as an HTML table (branch and joint values), or the status in words."""
        st = self.state
        if st.result is None:
            return f'<p style="color:#b00"><b>{html.escape(st.message)}</b></p>'
        from .tables import solutions_table

        return (f"<p><b>{html.escape(st.message)}</b></p>"
                + solutions_table(st.result)._repr_html_())

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
                              description=f"{name} ({unit})" if unit else name,
                              continuous_update=False, readout_format=".4g",
                              style={"description_width": "70px"},
                              layout=w.Layout(width="100%"))
            s.observe(self._on_slider, names="value")
            self._sliders[name] = s
        self._image = w.Image(format="png", layout=w.Layout(max_width="100%"))
        self._table = w.HTML()
        box = w.VBox([w.HTML(f"<b>{html.escape(self.arm.name)}</b>: move the target; every IK "
                             "solution is drawn with its branch"),
                      *self._sliders.values(), self._table, self._image],
                     layout=w.Layout(max_width="100%"))
        self._widget = box
        self._refresh()
        return box

    def _on_slider(self, change: dict[str, Any]) -> None:
        for name, s in self._sliders.items():
            if s is change["owner"]:
                self.set(**{name: change["new"]})

    def _ipython_display_(self) -> None:
        from IPython.display import display

        display(self.widget())


class TeachPanel:
    """The lessons' ``teach()``: joint sliders, the arm drawn by FK (see :func:`teach`)."""

    def __init__(self, arm: SerialArm, q: Any = None, width: float = 6.0) -> None:
        _check_arm(arm)
        self.arm = arm
        self.width = float(width)
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
        for k, v in values.items():
            if not (k.startswith("q") and k[1:].isdigit() and 1 <= int(k[1:]) <= self.arm.n):
                raise InputError(f"no joint {k!r}: the joints are q1..q{self.arm.n}")
            i = int(k[1:]) - 1
            fv = float(v)
            if not np.isfinite(fv):
                raise InputError(f"{k} must be a finite number, got {v!r}")
            self.q[i] = np.radians(fv) if self.arm.links[i].is_revolute else fv
        if redraw:
            self._refresh()

    def pose_text(self) -> str:
        """The TCP pose in words: position and roll, pitch, yaw (degrees)."""
        T = self.arm.fk(self.q)
        u = f" {self.arm.units}" if self.arm.units else ""
        rpy = r_to_rpy(T[:3, :3], degrees=True)
        return (f"q = {_q_text(self.arm, self.q)} → TCP at "
                f"({T[0, 3]:.4g}, {T[1, 3]:.4g}, {T[2, 3]:.4g}){u}, "
                f"roll {rpy[0]:.2f}°, pitch {rpy[1]:.2f}°, yaw {rpy[2]:.2f}°")

    def figure(self) -> Any:
        from .plot import plot_arm

        ax = plot_arm(self.arm, self.q, title=f"{self.arm.name} (teach)")
        fig = ax.figure
        fig.set_size_inches(self.width, self.width)
        return fig

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
                              description=f"{name} ({unit})" if unit else name,
                              continuous_update=False, readout_format=".4g",
                              style={"description_width": "70px"},
                              layout=w.Layout(width="100%"))
            s.observe(self._on_slider, names="value")
            self._sliders.append(s)
        self._image = w.Image(format="png", layout=w.Layout(max_width="100%"))
        self._readout = w.HTML()
        self._widget = w.VBox([*self._sliders, self._readout, self._image],
                              layout=w.Layout(max_width="100%"))
        self._refresh()
        return self._widget

    def _on_slider(self, change: dict[str, Any]) -> None:
        i = self._sliders.index(change["owner"])
        self.set(**{f"q{i + 1}": change["new"]})

    def _ipython_display_(self) -> None:
        from IPython.display import display

        display(self.widget())


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
