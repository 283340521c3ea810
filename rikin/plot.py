"""Figures for the book: stick drawings of an arm, every IK solution side by side, workspaces.

Every function draws into matplotlib Axes and returns them (or the Figure);
none calls ``plt.show()``, so the functions work with the headless ``Agg``
backend and in notebooks alike. Drawings are deterministic (no random
sampling). Planar arms (see :func:`is_planar`) are drawn in 2D, spatial
arms in 3D with equal scale on all three axes.

Artists carry a ``gid`` so that tests and notebooks can find them:
``"arm"`` (the links: the DH polyline through the frame origins, see
:func:`link_path`), ``"joints"``,
``"tcp"``, ``"frame-x"``/``"frame-y"``/``"frame-z"`` (triads), ``"tool"``
(a planar arm's tool direction), ``"target"``, ``"link1"``/``"link2"`` and
``"reach"`` (the triangle), ``"tcp-region"``/``"wrist-region"``
(planar workspaces), ``"gripper"`` (the two-finger gripper at the TCP),
``"wrist-centre"`` and ``"approach"`` (:func:`plot_wrist_centre`),
``"frame-label"`` (texts of :func:`plot_dh_frames`) and ``"workspace"``
(:func:`plot_workspace_3d`).

What the marks mean is :data:`MARKER_KEY`, the same words the book uses.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, cast

import matplotlib.colors
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.patches import Arc, PathPatch
from matplotlib.path import Path
from matplotlib.textpath import text_to_path
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d import Axes3D

from ._validate import (
    FloatArray,
    as_choice,
    as_count,
    as_flag,
    as_float_array,
    as_length,
    as_pose,
    as_text,
    as_texts,
)
from .dh import SerialArm, check_arm
from .errors import InputError, UnreachableError
from .i18n import branch_name, phrase, word
from .ik.kernels import elbow_above, reach_excess, two_link
from .ik.result import IKResult

__all__ = ["MARKER_KEY", "book_style", "gripper_path", "is_planar", "joint_points", "link_path",
           "plot_arm", "plot_dh_frames", "plot_solutions", "plot_two_link_triangle", "plot_view",
           "plot_workspace_3d", "plot_workspace_planar", "plot_wrist_centre", "same_joint_points",
           "turned_axes", "wrist_centre"]

#: Colours of the frame triads' x, y and z axes.
AXIS_COLOURS = ("tab:red", "tab:green", "tab:blue")
#: A parameter whose absolute value is below this counts as zero in :func:`is_planar`.
PLANAR_TOL = 1e-12
#: Empty space around the drawn points, as a fraction of the view's size.
MARGIN = 0.12
#: Default frame-triad length as a fraction of the view's side.
FRAME_FRACTION = 0.09
ARM_COLOUR = "0.25"
#: 3D view: camera elevation, and its azimuth relative to the arm's horizontal direction.
VIEW_ELEVATION_DEG = 22.0
VIEW_OFFSET_DEG = 60.0
#: Frame-triad length and 3D zoom of the small panels of :func:`plot_solutions`.
SOLUTIONS_FRAME_FRACTION = 0.14
SOLUTIONS_ZOOM = 1.25
#: What the marks of every arm drawing mean (shown under the all-solution figures).
MARKER_KEY = ("frame axes: x red, y green, z blue  ·  ○ revolute joint, □ prismatic joint  ·  "
              "★ TCP with the gripper (fingers open along y, approach along z)  ·  "
              "red ring: the target")
#: A joint point within this fraction of the arm's scale of another counts as the same point.
SAME_POINT_TOL = 1e-6
#: The smallest font (points) of the book's figures: in the book's 1280 px layout a figure
#: is shown at most 660 px wide, where this is 9 px high or more for a figure up to
#: 8.1 inches wide (10.7 px at its natural size, up to 6.9 inches).
SMALLEST_FONT_PT = 8.0
#: Font size (points) of each subplot's title in :func:`plot_solutions`.
SOLUTION_TITLE_PT = 8.5
#: The part of a column's width (figure width / columns) a solution's title may take: the
#: 3D layout's panels sit a little closer than the columns, and titles need a gap.
TITLE_ROOM = 0.85
#: Colour of the other solutions drawn faintly behind each subplot of plot_solutions.
GHOST_COLOUR = "0.8"
#: Colour of the :func:`knuckles` that tell apart solutions whose stick figures coincide.
TWIN_COLOUR = "tab:purple"
#: matplotlib settings of the book's figures (:func:`book_style`): text kept as text in
#: the SVG (sharp, searchable, measurable), fixed element ids (the same file at every
#: build), and fonts no smaller than SMALLEST_FONT_PT.
BOOK_RC = {"svg.fonttype": "none", "svg.hashsalt": "rikin", "font.size": 10.0,
           "axes.titlesize": 10.0, "axes.labelsize": 9.0, "xtick.labelsize": SMALLEST_FONT_PT,
           "ytick.labelsize": SMALLEST_FONT_PT, "legend.fontsize": SMALLEST_FONT_PT,
           "figure.titlesize": 11.0}


def book_style() -> None:
    """Draw the following figures as the book does: SVG with text, no smaller than 8 pt.

    Sets :data:`BOOK_RC` in matplotlib's rcParams and, inside IPython with the
    inline backend (a notebook, the book's build), makes figures SVG without a
    timestamp, so that a rebuilt page is byte for byte the same and its text
    stays sharp at any zoom. Outside IPython only the rcParams change.

    Examples
    --------
    >>> book_style()
    >>> plt.rcParams["svg.fonttype"]
    'none'
    """
    cast(Any, plt.rcParams).update(BOOK_RC)  # (its stubs type every key)
    try:
        from IPython import get_ipython
        from matplotlib_inline.backend_inline import set_matplotlib_formats
    except ImportError:  # no IPython: figures are saved by the caller, rcParams suffice
        return
    if get_ipython() is None:
        return
    set_matplotlib_formats("svg", bbox_inches="tight", metadata={"Date": None})


# ------------------------------------------------------------------ helpers
def _check_arm(arm: Any) -> SerialArm:
    return check_arm(arm)


def _check_ax(ax: Any) -> Axes | None:
    """``ax``: None (a new figure) or a matplotlib Axes, else InputError."""
    if ax is not None and not isinstance(ax, Axes):
        raise InputError(f"ax must be a matplotlib Axes (e.g. fig.add_subplot()) or None, "
                         f"got {type(ax).__name__}")
    return ax


def _check_colour(color: Any) -> Any:
    if color is not None and not matplotlib.colors.is_color_like(color):
        raise InputError(f"color must be a matplotlib colour (a name such as 'k' or 'tab:blue', "
                         f"'#rrggbb', or an (r, g, b) of numbers 0..1), got {color!r:.80}")
    return color


def _check_view(view: Any) -> Any:
    if view is None:
        return None
    v = as_float_array(view, "view")
    if v.shape != (2,):
        raise InputError(f"view must be (elevation, azimuth) in degrees, got shape {v.shape}")
    return v


def _frame_scale(frame_scale: Any) -> float | None:
    """None (the default length) or a positive length rikin handles."""
    return None if frame_scale is None else as_length(frame_scale, "frame_scale", positive=True)


def _check_frames(arm: SerialArm, F: Any) -> FloatArray:
    """``F``: the frames ``arm.fk(q, frames=True)`` of one configuration, (n + 2, 4, 4)."""
    Fv = as_pose(F, "F")
    if Fv.shape != (arm.n + 2, 4, 4):
        raise InputError(f"F must be the frames arm.fk(q, frames=True) of one configuration, "
                         f"shape ({arm.n + 2}, 4, 4), got shape {Fv.shape}")
    return Fv


def is_planar(arm: SerialArm) -> bool:
    """True when the arm moves in the world's xy plane, so it is drawn in 2D.

    Every joint is revolute with ``alpha = 0`` and ``d = 0`` (all axes
    parallel to z_0, all links in one plane), and the base keeps z_0 along
    the world's z axis.

    Parameters
    ----------
    arm : SerialArm

    Returns
    -------
    bool

    Examples
    --------
    >>> from rikin import robots
    >>> is_planar(robots.planar_3r()), is_planar(robots.angular_3r())
    (True, False)
    """
    _check_arm(arm)
    links_flat = all(lk.is_revolute and abs(float(lk.alpha)) <= PLANAR_TOL
                     and abs(float(lk.d)) <= PLANAR_TOL for lk in arm.links)
    base_z = arm.base[:3, 2]
    return bool(links_flat and abs(abs(base_z[2]) - 1.0) <= PLANAR_TOL)


def _check_q(arm: SerialArm, q: Any, name: str = "q") -> FloatArray:
    qv = arm.check_q(q, name)
    if qv.ndim != 1:
        raise InputError(f"{name} must be one configuration of shape ({arm.n},), got shape "
                         f"{qv.shape}; use plot_solutions for several")
    return qv


def _units(arm: SerialArm) -> str:
    return f" ({arm.units})" if arm.units else ""


def _square_limits(points: FloatArray, dims: int, min_half: float) -> FloatArray:
    """Limits ``(dims, 2)`` of a square (cube) view holding every point, with a margin."""
    pts = points[:, :dims]
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre = (lo + hi) / 2
    half = max(float((hi - lo).max()) / 2, min_half) * (1 + 2 * MARGIN)
    return np.stack([centre - half, centre + half], axis=1)


def _make_axes(three_d: bool, ax: Axes | None, figsize: tuple[float, float] = (5.5, 5.5)) -> Axes:
    if ax is None:
        fig = plt.figure(figsize=figsize)
        return fig.add_subplot(projection="3d" if three_d else None)
    if three_d and ax.name != "3d":
        raise InputError("this arm is spatial and needs 3D axes: create them with "
                         "fig.add_subplot(projection='3d'), or pass ax=None")
    return ax


def _azimuth(arm: SerialArm, points: FloatArray) -> float:
    """A view azimuth (degrees) that sees the arm's vertical plane obliquely, not edge-on.

    The arm's horizontal direction is that of the point farthest from the
    base's z axis; the camera sits 60 degrees round from it.
    """
    d = points[:, :2] - arm.base[:2, 3]
    far = d[int(np.argmax(np.hypot(d[:, 0], d[:, 1])))]
    psi = np.degrees(np.arctan2(far[1], far[0])) if np.hypot(*far) > 0 else 0.0
    return float(psi - VIEW_OFFSET_DEG)


def _view(arm: SerialArm, points: FloatArray, view: Any) -> tuple[float, float]:
    """The 3D camera ``(elevation, azimuth)``: ``view`` when given, else the default."""
    if view is None:
        return VIEW_ELEVATION_DEG, _azimuth(arm, points)
    v = as_float_array(view, "view")
    if v.shape != (2,):
        raise InputError(f"view must be (elevation, azimuth) in degrees, got shape {v.shape}")
    return float(v[0]), float(v[1])


def _apply_limits(ax: Axes, lim: FloatArray, arm: SerialArm, azim: float = -60.0,
                  elev: float = VIEW_ELEVATION_DEG, zoom: float = 1.0) -> None:
    u = _units(arm)
    ax.set_xlim(*lim[0])
    ax.set_ylim(*lim[1])
    ax.set_xlabel(f"x{u}")
    ax.set_ylabel(f"y{u}")
    if isinstance(ax, Axes3D):
        ax.set_zlim(*lim[2])
        ax.set_zlabel(f"z{u}")
        ax.set_box_aspect((1.0, 1.0, 1.0), zoom=zoom)
        ax.view_init(elev=elev, azim=azim)
    else:
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, lw=0.4, alpha=0.5)


def _view_points(arm: SerialArm, F: FloatArray, extra: FloatArray | None = None) -> FloatArray:
    pts = F[..., :3, 3].reshape(-1, 3)
    if extra is not None:
        pts = np.vstack([pts, extra.reshape(-1, 3)])
    return pts


def _min_half(arm: SerialArm) -> float:
    return 0.15 * arm.scale


def joint_points(arm: SerialArm, F: FloatArray) -> FloatArray:
    """Where the joint dots go: on each joint's axis, where the links meet it.

    Standard DH: joint i moves about ``z_{i-1}``; its dot is where the common
    normal to the next axis leaves it, ``o_{i-1} + d_i z_{i-1}`` (the shoulder
    of Aula 10 at height l1, not the floor), and for the last joint ``o_{n-1}``
    (so the three axes of a spherical wrist share the wrist centre).
    Modified DH: joint i's dot is the origin of frame i, which lies on its axis.

    Parameters
    ----------
    arm : SerialArm
    F : ndarray, shape (n + 2, 4, 4)
        ``arm.fk(q, frames=True)``.

    Returns
    -------
    ndarray, shape (n, 3)
        World coordinates, length units.
    """
    F = _check_frames(_check_arm(arm), F)
    return _joint_points(arm, F)


def _joint_points(arm: SerialArm, F: FloatArray) -> FloatArray:
    o = F[:, :3, 3]
    if arm.convention == "modified":
        return o[1:arm.n + 1].copy()
    pts = _corners(arm, F)                   # o_{i-1} + d_i z_{i-1}, on joint i's axis
    pts[-1] = o[arm.n - 1]
    return pts


def _corners(arm: SerialArm, F: FloatArray) -> FloatArray:
    """Per link, (n, 3): where its first piece ends (see :func:`link_path`)."""
    o = F[:, :3, 3]
    n = arm.n
    axis = F[:n, :3, 0] if arm.convention == "modified" else F[:n, :3, 2]
    return o[:n] + np.einsum("ij,ij->i", o[1:n + 1] - o[:n], axis)[:, None] * axis


def link_path(arm: SerialArm, F: FloatArray) -> FloatArray:
    """The arm's links as drawn: each DH link as its two straight pieces.

    Standard DH: link i runs ``d_i`` along ``z_{i-1}``, then ``a_i`` along
    ``x_i``; modified DH: ``a_{i-1}`` along ``x_{i-1}``, then ``d_i`` along
    ``z_i``. The corner between the pieces is the projection of
    ``o_i - o_{i-1}`` on ``z_{i-1}`` (standard) or ``x_{i-1}`` (modified), so
    the path needs only the frames. A SCARA's first link thus rises up the
    column, then reaches out, instead of cutting across.

    Parameters
    ----------
    arm : SerialArm
    F : ndarray, shape (n + 2, 4, 4)
        ``arm.fk(q, frames=True)``.

    Returns
    -------
    ndarray, shape (2 n + 2, 3)
        ``o_0, corner_1, o_1, ..., corner_n, o_n, TCP`` in world coordinates,
        length units (a corner equals an origin where a piece has length 0).
    """
    F = _check_frames(_check_arm(arm), F)
    return _link_path(arm, F)


def _link_path(arm: SerialArm, F: FloatArray) -> FloatArray:
    o = F[:, :3, 3]
    n = arm.n
    path = np.empty((2 * n + 2, 3))
    path[0:2 * n:2] = o[:n]
    path[1:2 * n:2] = _corners(arm, F)
    path[2 * n:] = o[n:]
    return path


def _group_joints(origins: FloatArray, tol: float) -> list[tuple[FloatArray, list[int]]]:
    """Joints (numbered from 1) that sit at the same point share one label."""
    groups: list[tuple[FloatArray, list[int]]] = []
    for i, p in enumerate(origins, 1):
        for g in groups:
            if np.linalg.norm(g[0] - p) <= tol:
                g[1].append(i)
                break
        else:
            groups.append((p, [i]))
    return groups


def gripper_path(T_tcp: FloatArray, size: float, planar: bool = False) -> FloatArray:
    """A two-finger gripper at the TCP pose, as one polyline (NaN rows break it).

    The fingers end at the TCP and open along the tool's y axis; the palm is
    ``size`` behind the TCP along the approach direction, the tool's z axis
    (x for a planar arm, whose tool direction is x), with a stub towards the
    wrist. It shows the tool's orientation, not only its position.

    Parameters
    ----------
    T_tcp : ndarray, shape (4, 4)
        The TCP pose in the world frame.
    size : float
        Finger length, length units.
    planar : bool
        Approach along the tool's x axis instead of z.

    Returns
    -------
    ndarray, shape (7, 3)
        ``stub, palm centre, NaN, tip_a, palm_a, palm_b, tip_b`` (world, length units).
    """
    T_tcp = as_pose(T_tcp, "T_tcp")
    if T_tcp.shape != (4, 4):
        raise InputError(f"T_tcp must be one pose of shape (4, 4), got shape {T_tcp.shape}")
    size = as_length(size, "size", positive=True)
    planar = as_flag(planar, "planar")
    p = T_tcp[:3, 3]
    approach = T_tcp[:3, 0] if planar else T_tcp[:3, 2]
    opening = T_tcp[:3, 1]
    palm = p - size * approach
    half = 0.5 * size * opening
    nan = np.full(3, np.nan)
    return np.stack([palm - 0.6 * size * approach, palm, nan,
                     p + half, palm + half, palm - half, p - half])


def _draw_arm(ax: Axes, arm: SerialArm, q: FloatArray, *, frames: bool, frame_scale: float,
              color: Any, label_joints: bool, gripper: bool = True) -> None:
    three_d = ax.name == "3d"
    dims = 3 if three_d else 2
    # the callers set the limits afterwards: rescaling after every line (in 3D a
    # millisecond each) would be wasted
    ax.set_autoscale_on(False)
    F = arm._fk(q, frames=True)            # (n + 2, 4, 4): base, frames 1..n, TCP
    P = F[:, :3, 3]
    col = ARM_COLOUR if color is None else color
    ax.plot(*_link_path(arm, F)[:, :dims].T, "-", color=col, lw=3.0, solid_capstyle="round",
            gid="arm", zorder=2)
    origins = _joint_points(arm, F)
    rev = arm.revolute
    for mask, marker in ((rev, "o"), (np.logical_not(rev), "s")):
        if mask.any():
            ax.plot(*origins[mask, :dims].T, marker, ms=8, mfc="white", mec=col, mew=2.0,
                    ls="none", gid="joints", zorder=4)
    if gripper:
        size = (0.9 if three_d else 0.55) * frame_scale
        ax.plot(*gripper_path(F[-1], size, planar=not three_d)[:, :dims].T, "-",
                color="tab:orange", lw=2.2, solid_capstyle="round", gid="gripper", zorder=5)
    ax.plot(*P[-1, :dims], "*", ms=14, color="tab:orange", mec="k", mew=0.6, ls="none",
            gid="tcp", zorder=5)
    if label_joints:
        for p, idx in _group_joints(origins, 1e-9 * arm.scale):
            text = "J" + ",".join(map(str, idx))
            box = {"fc": "white", "ec": "none", "alpha": 0.75, "pad": 1.0}
            if three_d:
                _as_3d(ax).text(p[0], p[1], p[2] + 1.1 * frame_scale, text, fontsize=8,
                                zorder=6, ha="center", va="bottom", bbox=box)
            else:
                ax.annotate(text, (p[0], p[1]), xytext=(6, 6), textcoords="offset points",
                            fontsize=8, bbox=box)
    if frames:
        # one line per colour, the segments separated by NaN (one artist draws faster)
        for k in range(dims):
            seg = np.full((3 * len(F), 3), np.nan)
            seg[0::3] = F[:, :3, 3]
            seg[1::3] = F[:, :3, 3] + frame_scale * F[:, :3, k]
            ax.plot(*seg[:, :dims].T, "-", color=AXIS_COLOURS[k], lw=1.6,
                    gid=f"frame-{'xyz'[k]}", zorder=3)
    if not three_d:
        # the tool's direction (its x axis): the lessons' wrist angle phi
        tip = P[-1, :2] + 2.0 * frame_scale * F[-1, :2, 0]
        ax.annotate("", xy=(tip[0], tip[1]), xytext=(P[-1, 0], P[-1, 1]),
                    arrowprops={"arrowstyle": "->", "color": "tab:orange", "lw": 1.8},
                    gid="tool")


def _q_text(arm: SerialArm, q: FloatArray) -> str:
    parts = [f"{np.degrees(v):.1f}°" if r else f"{v:.3g}"
             for v, r in zip(q, arm.revolute, strict=True)]
    return "(" + ", ".join(parts) + ")"


# ------------------------------------------------------------------ one arm
def plot_arm(arm: SerialArm, q: Any, ax: Axes | None = None, frames: bool = True,
             frame_scale: float | None = None, title: str | None = None, color: Any = None,
             label_joints: bool = True, limits: Any = None, gripper: bool = True,
             view: tuple[float, float] | None = None) -> Axes:
    """Stick figure of the arm at ``q``: its links, frames, joints and TCP.

    The links run from frame 0 (the base) through frames 1..n to the TCP,
    each DH link drawn as its ``d`` and ``a`` pieces (:func:`link_path`).
    Joints are dots (revolute) or squares (prismatic) on their axes (see
    :func:`joint_points`), the TCP a star. Planar arms are drawn in 2D with
    an arrow for the tool direction; spatial arms in 3D.

    Parameters
    ----------
    arm : SerialArm
    q : array_like, shape (n,)
        Joint values: radians (revolute), length units (prismatic).
    ax : matplotlib Axes, optional
        Where to draw (3D axes for a spatial arm). A new figure when None.
    frames : bool
        Draw every frame's axes: x red, y green, z blue (z omitted in 2D).
    frame_scale : float, optional
        Triad length, length units. Default: 9% of the view's side.
    title : str, optional
        Default: the arm's name and q (degrees for revolute joints).
    color : matplotlib colour, optional
        Colour of the links.
    label_joints : bool
        Write J1..Jn beside the joints (joints at one point share a label,
        e.g. "J4,5,6" for a spherical wrist).
    limits : array_like, shape (2, 2) or (3, 2), optional
        Axis limits ``[[xmin, xmax], [ymin, ymax](, [zmin, zmax])]``, length
        units. Default: a square (cube) around the drawing, or around the
        whole reach for a planar arm.
    gripper : bool
        Draw a two-finger gripper at the TCP (:func:`gripper_path`), so the
        tool's orientation shows.
    view : (float, float), optional
        3D camera ``(elevation, azimuth)`` in degrees. Default: 22° up,
        60° round from the arm's horizontal direction.

    Returns
    -------
    matplotlib.axes.Axes
        2D Axes for a planar arm, 3D Axes otherwise (equal scale).

    Raises
    ------
    InputError
        Bad ``q`` (shape, NaN, degrees), or 2D axes for a spatial arm.

    Examples
    --------
    >>> from rikin import robots
    >>> ax = plot_arm(robots.planar_3r(), [0.3, 0.5, -0.2])
    >>> ax.name
    'rectilinear'
    """
    _check_arm(arm)
    qv = _check_q(arm, q)
    _check_ax(ax)
    frames, label_joints = as_flag(frames, "frames"), as_flag(label_joints, "label_joints")
    gripper = as_flag(gripper, "gripper")
    title, color = as_text(title, "title", optional=True), _check_colour(color)
    frame_scale, view = _frame_scale(frame_scale), _check_view(view)
    three_d = not is_planar(arm) or (ax is not None and ax.name == "3d")
    ax = _make_axes(three_d, ax)
    F = arm._fk(qv, frames=True)
    elev, azim = _view(arm, F[:, :3, 3], view)
    lim = _arm_limits(arm, F, three_d, limits)
    fs = _frame_length(lim, FRAME_FRACTION) if frame_scale is None else frame_scale
    _draw_arm(ax, arm, qv, frames=frames, frame_scale=fs, color=color, label_joints=label_joints,
              gripper=gripper)
    _apply_limits(ax, lim, arm, azim, elev)
    if three_d:
        _few_ticks(ax, 5, labelsize=None)
    ax.set_title(phrase("{name} at q = {q}", name=arm.name, q=_q_text(arm, qv))
                 if title is None else title, fontsize=10)
    return ax


def _arm_limits(arm: SerialArm, F: FloatArray, three_d: bool, limits: Any) -> FloatArray:
    """Axis limits ``(dims, 2)`` of one drawn configuration (frames ``F``): ``limits`` when
    given, else a cube around the drawing (3D) or a square around a planar arm's reach."""
    if limits is not None:
        dims = 3 if three_d else 2
        lim = as_float_array(limits, "limits")
        if lim.shape != (dims, 2):
            raise InputError(f"limits must have shape ({dims}, 2), got {lim.shape}")
        return lim
    if three_d:
        return _square_limits(_view_points(arm, F), 3, _min_half(arm))
    return _planar_limits(arm)


def _frame_length(lim: FloatArray, fraction: float) -> float:
    """A frame triad's length: ``fraction`` of the view's side (its x extent)."""
    return float(fraction * (lim[0, 1] - lim[0, 0]))


def _planar_reach(arm: SerialArm) -> float:
    return sum(abs(float(lk.a)) for lk in arm.links) + float(np.linalg.norm(arm.tool[:2, 3]))


def _planar_limits(arm: SerialArm) -> FloatArray:
    c = arm.base[:2, 3]
    half = _planar_reach(arm) * (1 + MARGIN)
    return np.stack([c - half, c + half], axis=1)


# ------------------------------------------------------------------ all IK solutions
def same_joint_points(arm: SerialArm, Q: Any) -> list[list[int]]:
    """For each solution, the other solutions whose joints sit at the same points.

    Without a shoulder offset, turning joint 1 by pi and mirroring joints 2
    and 3 puts every joint where another solution has one (Aula 10's front
    and back branches): the stick figures coincide and only the joint frames
    and angles differ. A wrist flip moves no joint at all.

    Parameters
    ----------
    arm : SerialArm
    Q : array_like, shape (k, n)
        Solutions, one per row.

    Returns
    -------
    list of list of int
        ``twins[i]``: the solutions (numbered from 1) other than ``i + 1``
        whose joint points (:func:`joint_points`) and drawn link path all lie
        within ``SAME_POINT_TOL * arm.scale`` of solution ``i + 1``'s.
    """
    _check_arm(arm)
    Qv = arm.check_q(Q, "Q")
    Qv = Qv[None] if Qv.ndim == 1 else Qv
    F = arm._fk(Qv, frames=True)
    shapes = np.stack([np.vstack([_joint_points(arm, f), _link_path(arm, f)]) for f in F])
    tol = SAME_POINT_TOL * arm.scale
    gap = np.abs(shapes[:, None] - shapes[None]).max(axis=(2, 3))
    return [[int(j) + 1 for j in np.flatnonzero(row <= tol) if j != i] for i, row in enumerate(gap)]


def turned_axes(arm: SerialArm, q: Any, q_other: Any) -> list[int]:
    """The joints (numbered from 1) whose axis points the other way in ``q_other``.

    Two solutions whose stick figures coincide (:func:`same_joint_points`: a
    wrist flip, or a front and a back branch without shoulder offset) still
    differ: some joint axes are reversed, and those joints turn the other way
    to reach the same pose. :func:`plot_solutions` draws these axes.

    Parameters
    ----------
    arm : SerialArm
    q, q_other : array_like, shape (n,)

    Returns
    -------
    list of int
        The revolute joints whose axis directions (world frame) point more
        than 90 degrees apart in the two configurations.

    Examples
    --------
    >>> from rikin import robots
    >>> arm = robots.pprrr()
    >>> res = arm.ik(arm.fk([1, 2, 0.5, 0.7, 0.2]))
    >>> turned_axes(arm, res.q[0], res.q[1])
    [4]
    """
    _check_arm(arm)
    a, b = _check_q(arm, q), _check_q(arm, q_other, "q_other")
    _, axes_a = arm.joint_axes(a)
    _, axes_b = arm.joint_axes(b)
    dots = np.einsum("ij,ij->i", axes_a, axes_b)
    return [i + 1 for i in range(arm.n) if arm.revolute[i] and dots[i] < 0.0]


def _as_3d(ax: Axes) -> Axes3D:
    """``ax`` as the 3D Axes it is (``ax.name == "3d"``), for its z axis and camera."""
    if not isinstance(ax, Axes3D):
        raise TypeError(f"3D Axes expected, got {type(ax).__name__}")
    return ax


def _zaxis(ax: Axes) -> Any:
    return _as_3d(ax).zaxis


def _few_ticks(ax: Axes, n: int = 3, labelsize: float | None = SMALLEST_FONT_PT) -> None:
    """At most ``n`` ticks per axis (small labels): tick labels never run together."""
    axes = (ax.xaxis, ax.yaxis, _zaxis(ax)) if ax.name == "3d" else (ax.xaxis, ax.yaxis)
    for axis in axes:
        axis.set_major_locator(MaxNLocator(n))
    if labelsize is not None:
        ax.tick_params(labelsize=labelsize, pad=0)


def _solutions_input(arm: SerialArm, result: Any,
                     target: Any) -> tuple[FloatArray, Sequence[str], Any, str | None]:
    """The solutions ``(k, n)``, their labels, the target to mark and a note."""
    if isinstance(result, IKResult):
        Q = np.asarray(result.q, dtype=np.float64)
        note = f"singular: {result.singularity}" if result.singular else None
        return Q, result.labels, result.target if target is None else target, note
    Q = arm.check_q(result, "result")
    Q = Q[None] if Q.ndim == 1 else Q
    return Q, [""] * len(Q), target, None


def _figsize(figsize: Any) -> tuple[float, float] | None:
    if figsize is None:
        return None
    size = as_float_array(figsize, "figsize")
    if size.shape != (2,) or not (size > 0).all() or size.max() > 100:
        raise InputError(f"figsize must be (width, height) in inches, each 0 to 100, got "
                         f"{figsize!r:.80}")
    return float(size[0]), float(size[1])


def _draw_ghosts(ax: Axes, arm: SerialArm, F: FloatArray, others: Sequence[int]) -> None:
    """The other solutions' links, faint, behind the panel's own arm."""
    dims = 3 if ax.name == "3d" else 2
    for j in others:
        ax.plot(*_link_path(arm, F[j])[:, :dims].T, "-", color=GHOST_COLOUR, lw=2.0,
                solid_capstyle="round", gid="ghost", zorder=1)


def _draw_turned_axes(ax: Axes, arm: SerialArm, F: FloatArray, joints: Sequence[int],
                      length: float) -> None:
    """Arrows along the given joints' axes from their joint points (purple)."""
    dims = 3 if ax.name == "3d" else 2
    points = _joint_points(arm, F)
    idx = np.arange(arm.n) if arm.convention == "standard" else np.arange(1, arm.n + 1)
    for j in joints:
        p, z = points[j - 1], F[idx[j - 1], :3, 2]
        seg = np.stack([p, p + length * z])
        ax.plot(*seg[:, :dims].T, "-", color=TWIN_COLOUR, lw=3.0, solid_capstyle="round",
                gid="turned-axis", zorder=5)
        ax.plot(*seg[1, :dims], "o", ms=6, color=TWIN_COLOUR, ls="none", gid="turned-axis",
                zorder=5)


def plot_solutions(arm: SerialArm, result: Any, ncols: int = 2,
                   figsize: tuple[float, float] | None = None, frames: bool = True,
                   target: Any = None, gripper: bool = True,
                   view: tuple[float, float] | None = None, key: bool = True,
                   ghosts: bool = True) -> Figure:
    """Every IK solution side by side: one subplot per solution, same view in all.

    Each subplot shows the links, the joints, every joint frame and a
    gripper at the TCP, with the other solutions' links faint behind it
    (``ghosts``), so that what changes from one solution to the next shows.
    Solutions whose stick figures coincide (a wrist flip, or a front and a
    back branch without shoulder offset) say so in their titles
    (:func:`same_joint_points`) and draw in purple the axes of the joints that
    point the other way in their twin (:func:`turned_axes`): those joints turn
    the other way to reach the same pose.

    Parameters
    ----------
    arm : SerialArm
    result : IKResult or array_like, shape (k, n)
        The solutions. Titles show the branch label (for an IKResult) and
        the joint values (degrees for revolute joints).
    ncols : int
        Subplots per row. The default 2 keeps the figure 7 inches wide, so
        that its smallest text (SMALLEST_FONT_PT) is still 9 px or more in
        the book's text column.
    figsize : (float, float), optional
        Inches; default 3.5 x 3.6 per subplot.
    frames : bool
        Draw the frame triads (x red, y green, z blue).
    target : array_like, shape (4, 4), optional
        The target pose to mark (red ring); default ``result.target`` for
        an IKResult, none for a plain array.
    gripper : bool
        Draw the gripper at the TCP (:func:`gripper_path`).
    view : (float, float), optional
        3D camera ``(elevation, azimuth)`` in degrees, the same in every subplot.
    key : bool
        Write :data:`MARKER_KEY` under the subplots.
    ghosts : bool
        Draw the other solutions' links faintly behind each subplot's arm.

    Returns
    -------
    matplotlib.figure.Figure
        With exactly k Axes.

    Raises
    ------
    InputError
        No solutions, wrong shape, or ``ncols < 1``.

    Examples
    --------
    >>> from rikin import robots
    >>> arm = robots.planar_2r()
    >>> fig = plot_solutions(arm, arm.ik([15.0, 5.0]))
    >>> len(fig.axes)
    2
    """
    _check_arm(arm)
    Q, labels, T_target, note = _checked_solutions(arm, result, target)
    ncols = as_count(ncols, "ncols", minimum=1)
    frames, gripper = as_flag(frames, "frames"), as_flag(gripper, "gripper")
    key, ghosts = as_flag(key, "key"), as_flag(ghosts, "ghosts")
    view, figsize, k = _check_view(view), _figsize(figsize), Q.shape[0]
    fig, rows, cols = _solutions_grid(k, int(ncols), figsize, key)
    three_d = not is_planar(arm)
    F = arm._fk(Q, frames=True)
    lim, camera = _solutions_view(arm, F, T_target, three_d, view)
    twins = same_joint_points(arm, Q)
    wrap = _titles_wrap(arm, Q, fig, cols)
    for i in range(k):
        ax = fig.add_subplot(rows, cols, i + 1, projection="3d" if three_d else None)
        _solution_panel(ax, arm, Q, F, i, labels[i], twins[i], lim, camera, ghosts=ghosts,
                        frames=frames, gripper=gripper, T_target=T_target, wrap=wrap)
    _lay_out_solutions(fig, arm.name, k, note, rows, three_d, key, wrap)
    if key:
        _solutions_key(fig, three_d, ghosts and k > 1, any(twins))
    return fig


def _solutions_grid(k: int, ncols: int, figsize: tuple[float, float] | None,
                    key: bool) -> tuple[Figure, int, int]:
    """A figure for k panels, ``ncols`` (at most k) to a row: (figure, rows, columns).

    Default size: 3.5 x 3.6 inches per panel, with room for the suptitle and the key."""
    cols = min(ncols, k)
    rows = math.ceil(k / cols)
    if figsize is None:
        figsize = (3.5 * cols, 3.6 * rows + 0.45 + (0.5 if key else 0.0))
    return plt.figure(figsize=figsize), rows, cols


def _checked_solutions(arm: SerialArm, result: Any, target: Any
                       ) -> tuple[FloatArray, Sequence[str], FloatArray | None, str | None]:
    """:func:`_solutions_input` checked: at least one solution, and a 4x4 target or None."""
    Q, labels, tgt, note = _solutions_input(arm, result, target)
    if Q.ndim != 2 or Q.shape[0] == 0:
        raise InputError("there are no solutions to draw (the IK result is empty)")
    Q = arm.check_q(Q, "result.q")
    if tgt is None:
        return Q, labels, None, note
    T_target = as_float_array(tgt, "target")
    if T_target.shape != (4, 4):
        raise InputError(f"target must be a 4x4 pose, got shape {T_target.shape}")
    return Q, labels, T_target, note


def _solutions_view(arm: SerialArm, F: FloatArray, T_target: FloatArray | None,
                    three_d: bool, view: Any) -> tuple[FloatArray, tuple[float, float]]:
    """The limits and the camera ``(elevation, azimuth)`` shared by every panel: a cube
    around all solutions ``F`` (k, n + 2, 4, 4) and the target (3D), or a square around a
    planar arm's reach; the camera ``view``, else the default for the target (or the
    first solution)."""
    if three_d:
        extra = None if T_target is None else T_target[:3, 3]
        lim = _square_limits(_view_points(arm, F, extra), 3, _min_half(arm))
    else:
        lim = _planar_limits(arm)
    points = F[0, :, :3, 3] if T_target is None else T_target[None, :3, 3]
    return lim, _view(arm, points, view)


def _solution_panel(ax: Axes, arm: SerialArm, Q: FloatArray, F: FloatArray, i: int,
                    label: str, twins: Sequence[int], lim: FloatArray,
                    camera: tuple[float, float], *, ghosts: bool, frames: bool, gripper: bool,
                    T_target: FloatArray | None, wrap: bool = False) -> None:
    """Solution ``i`` (from 0) in its panel: with ``ghosts`` the other solutions faint
    behind it (not its ``twins``, numbered from 1, :func:`same_joint_points`, which lie
    under it), the arm, the axes reversed in its twins, the target's ring, the shared
    limits and camera ``(elevation, azimuth)``, and its title (its joints on two lines
    with ``wrap``)."""
    fs = _frame_length(lim, SOLUTIONS_FRAME_FRACTION)
    if ghosts:
        _draw_ghosts(ax, arm, F, [j for j in range(len(Q)) if j != i and j + 1 not in twins])
    _draw_arm(ax, arm, Q[i], frames=frames, frame_scale=fs, color=None,
              label_joints=False, gripper=gripper)
    if twins:
        turned = sorted({j for t in twins for j in turned_axes(arm, Q[i], Q[t - 1])})
        _draw_turned_axes(ax, arm, F[i], turned, 1.5 * fs)
    if T_target is not None:
        p = T_target[:3, 3]
        ax.plot(*p[:3 if ax.name == "3d" else 2], "o", ms=13, mfc="none", mec="tab:red",
                mew=1.8, ls="none", gid="target", zorder=6)
    elev, azim = camera
    _apply_limits(ax, lim, arm, azim, elev, zoom=SOLUTIONS_ZOOM)
    ax.set_title(_solution_title(arm, Q[i], i, label, twins, wrap), fontsize=SOLUTION_TITLE_PT)
    _few_ticks(ax)
    if ax.name == "3d":
        for text in (ax.xaxis.label, ax.yaxis.label, _zaxis(ax).label):
            text.set_fontsize(SMALLEST_FONT_PT)


def _titles_wrap(arm: SerialArm, Q: FloatArray, fig: Figure, cols: int) -> bool:
    """Whether the solutions' joints take two lines in their titles: when one line of
    any of them is wider than its share of a column (:data:`TITLE_ROOM`), so that the
    titles of neighbouring panels do not run into each other."""
    room = fig.get_figwidth() * 72.0 / cols * TITLE_ROOM  # points
    font = FontProperties(size=SOLUTION_TITLE_PT)
    return any(text_to_path.get_text_width_height_descent(_q_text(arm, q), font,
                                                          ismath=False)[0] > room for q in Q)


def _solution_title(arm: SerialArm, q: FloatArray, i: int, label: str,
                    twins: Sequence[int], wrap: bool = False) -> str:
    """A panel's title: its number and branch, its joints (on two lines with ``wrap``),
    and its twins if any."""
    head = f"{i + 1}: {branch_name(label)}" if label else phrase("solution {n}", n=i + 1)
    joints = _q_text(arm, q)
    if wrap and arm.n > 1:
        parts, half = joints.split(", "), (arm.n + 1) // 2
        joints = ", ".join(parts[:half]) + ",\n" + ", ".join(parts[half:])
    title = f"{head}\n{joints}"
    if twins:
        verb = "has" if len(twins) == 1 else "have"
        title += "\n" + phrase(f"joints where #{{twins}} {verb} them",
                               twins=", #".join(map(str, twins)))
    return title


def _lay_out_solutions(fig: Figure, name: str, k: int, note: str | None, rows: int,
                       three_d: bool, key: bool, wrap: bool = False) -> None:
    """The suptitle (the arm's name, k solutions, the note), and the panels spaced to
    leave room for it, the 3D axis labels, the titles' extra line (``wrap``) and the key."""
    sup = phrase(f"{{name}}: {{k}} IK solution{'s' if k != 1 else ''}", name=name, k=k)
    fig.suptitle(sup if note is None else f"{sup}\n{note}", fontsize=11)
    height = fig.get_size_inches()[1]
    top = 1.0 - (0.45 + (0.2 if note else 0.0)) / height   # room for the suptitle
    fig.tight_layout(rect=(0.0, 0.5 / height if key else 0.0, 1.0, top))
    if three_d:
        # tight_layout ignores the 3D axis labels: leave room for them at both sides
        # and between rows, where the x tick labels hang below the panel into the titles
        fig.subplots_adjust(left=0.04, right=0.96, wspace=0.3,
                            hspace=fig.subplotpars.hspace + (0.6 if wrap else 0.45)
                            if rows > 1 else None,
                            bottom=fig.subplotpars.bottom + 0.55 / height if key else None)


def _solutions_key(fig: Figure, three_d: bool, ghosts: bool, twins: bool) -> None:
    words = phrase(MARKER_KEY)
    if not three_d:
        words = words.replace(phrase("approach along z"), phrase("approach along x"))
    extra = []
    if ghosts:
        extra.append(phrase("light grey: the other solutions"))
    if twins:
        extra.append(phrase("purple arrow: a joint axis reversed in the twin solution"))
    if extra:
        words += "  ·  " + "  ·  ".join(extra)
    fig.text(0.5, 0.005, words, ha="center", va="bottom", fontsize=SMALLEST_FONT_PT,
             color="0.25", wrap=True, gid="key")


# ------------------------------------------------------------------ the geometric method
def _positive_length(x: Any, name: str) -> float:
    return as_length(x, name, positive=True)


def _angle_arc(ax: Axes, centre: FloatArray, radius: float, a0: float, a1: float, label: str,
               color: str) -> None:
    """An arc from angle a0 to a1 (radians, either order) with a label at its middle."""
    lo, hi = sorted((a0, a1))
    ax.add_patch(Arc(tuple(centre), 2 * radius, 2 * radius, theta1=np.degrees(lo),
                     theta2=np.degrees(hi), color=color, lw=1.2, gid="angle"))
    mid = (lo + hi) / 2
    pos = centre + 1.3 * radius * np.array([np.cos(mid), np.sin(mid)])
    ax.text(pos[0], pos[1], f"${label}$", color=color, fontsize=11, ha="center", va="center")


def plot_two_link_triangle(L1: float, L2: float, target_uv: Any, elbow: str = "both",
                           ax: Axes | None = None, labels: tuple[str, str] = ("l_1", "l_2"),
                           angle_labels: tuple[str, str, str] = ("\\alpha", "\\phi",
                                                                  "\\theta_2")) -> Axes:
    """The law-of-cosines triangle of a planar two-link chain reaching a point.

    The geometric method of Aula 23 and the slides: the shoulder O, the
    elbow E and the target P form a triangle with sides ``l_1``, ``l_2`` and
    ``r = |OP|``. Then ``alpha = atan2(w, u)`` is the direction of OP,
    ``cos(theta_2) = (r^2 - l_1^2 - l_2^2) / (2 l_1 l_2)`` the elbow angle,
    ``phi = atan2(l_2 sin(theta_2), l_1 + l_2 cos(theta_2))`` the angle
    between OP and link 1, and ``theta_1 = alpha -/+ phi``. The numbers come
    from :func:`rikin.ik.kernels.two_link`.

    Parameters
    ----------
    L1, L2 : float
        Link lengths, length units, positive.
    target_uv : array_like, shape (2,)
        The point in the chain's plane, measured from the shoulder.
    elbow : {"both", "up", "down"}
        Which solutions to draw. With "both", elbow up is solid and elbow
        down dashed; angles are annotated on the first one drawn.
    ax : matplotlib Axes (2D), optional
    labels : (str, str)
        LaTeX (without $) for the two sides.
    angle_labels : (str, str, str)
        LaTeX names of alpha, phi and the elbow angle.

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    UnreachableError
        ``|OP|`` outside ``[|l_1 - l_2|, l_1 + l_2]``; ``.excess`` says by how much.
    InputError
        Non-positive lengths, a target that is not two finite numbers, or
        an unknown ``elbow``.

    Examples
    --------
    >>> ax = plot_two_link_triangle(10, 10, (15.0, 5.0))
    >>> len([l for l in ax.lines if l.get_gid() == "link1"])
    2
    """
    l1 = _positive_length(L1, "L1")
    l2 = _positive_length(L2, "L2")
    uv = as_float_array(target_uv, "target_uv")
    if uv.shape != (2,):
        raise InputError(f"target_uv must be a point (u, w) of shape (2,), got shape {uv.shape}")
    elbow = as_choice(elbow, "elbow", ("both", "up", "down"))
    _check_ax(ax)
    as_texts(labels, "labels", 2)
    as_texts(angle_labels, "angle_labels", 3)
    A, B, chosen, names = _triangle_chains(l1, l2, uv, elbow)
    if ax is None:
        ax = plt.figure(figsize=(6, 5.5)).add_subplot()
    P = uv
    _draw_reach(ax, P, l1 + l2)
    for n_drawn, s in enumerate(chosen):
        a, b = float(A[s]), float(B[s])
        E = l1 * np.array([np.cos(a), np.sin(a)])
        colour = "tab:blue" if names[s] == "up" else "tab:purple"
        text = (phrase("elbow {branch}", branch=word(names[s]))
                + f": $\\theta_1$ = {np.degrees(a):.2f}°, ${angle_labels[2]}$ = "
                f"{np.degrees(b):.2f}°")
        _draw_chain(ax, E, P, "-" if n_drawn == 0 else "--", colour, text)
        if n_drawn == 0:
            _annotate_triangle(ax, P, E, a, b, (l1, l2), colour, labels, angle_labels)
    ax.plot(0, 0, "ko", ms=6)
    ax.plot(*P, "*", color="tab:orange", mec="k", ms=14, gid="target")
    ax.annotate("O", (0, 0), xytext=(-12, -12), textcoords="offset points")
    ax.annotate("P", tuple(P), xytext=(8, 4), textcoords="offset points")
    elbows = [l1 * np.array([np.cos(A[s]), np.sin(A[s])]) for s in chosen]
    _triangle_frame(ax, np.vstack([np.zeros(2), P, *elbows]), l1 + l2)
    return ax


def _triangle_frame(ax: Axes, points: FloatArray, size: float) -> None:
    """Equal scale, a square view around ``points`` (k, 2), the u and w labels, the
    legend and the title."""
    ax.set_aspect("equal", adjustable="box")
    lim = _square_limits(points, 2, 0.1 * size)
    ax.set_xlim(*lim[0])
    ax.set_ylim(*lim[1])
    ax.set_xlabel("u")
    ax.set_ylabel("w")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(phrase("two-link triangle (law of cosines)"), fontsize=10)


def _draw_reach(ax: Axes, P: FloatArray, size: float) -> None:
    """The u and w axes, and the dotted line O-P with its length r beside it."""
    origin = np.zeros(2)
    r = float(np.hypot(P[0], P[1]))
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.plot(*np.stack([origin, P]).T, ":", color="0.35", lw=1.4, gid="reach")
    normal = np.array([-P[1], P[0]]) / max(r, 1e-300)
    at = P / 2 - 0.06 * size * normal
    ax.text(at[0], at[1], f"$r = {r:.4g}$", color="0.35", fontsize=10, ha="center",
            va="center")


def _draw_chain(ax: Axes, E: FloatArray, P: FloatArray, style: str, colour: str,
                label: str) -> None:
    """One chain O-E-P: its two links (``label`` in the legend) and its elbow E."""
    ax.plot(*np.stack([np.zeros(2), E]).T, style, color=colour, lw=2.5, gid="link1",
            label=label)
    ax.plot(*np.stack([E, P]).T, style, color=colour, lw=2.5, gid="link2")
    ax.plot(*E, "o", color=colour, ms=6, gid="elbow")


def _triangle_chains(l1: float, l2: float, uv: FloatArray,
                     elbow: str) -> tuple[FloatArray, FloatArray, list[int], dict[int, str]]:
    """The two-link solutions ``theta_1`` (A) and ``theta_2`` (B), shape (2,) each, the
    slots to draw (elbow up first) and each slot's name ("up" or "down").

    Raises UnreachableError, with ``.excess``, for a point out of the chain's reach."""
    u, w = np.array(uv[0]), np.array(uv[1])
    A, B, reachable, stretched = two_link(u, w, l1, l2)
    r = float(np.hypot(u, w))
    if not bool(reachable):
        ex = float(reach_excess(np.array(r), l1, l2))
        why = (f"{ex:.4g} beyond the reach l1 + l2 = {l1 + l2:.6g}" if r > l1 + l2 else
               f"{ex:.4g} too close: the folded chain reaches no closer than |l1 - l2| = "
               f"{abs(l1 - l2):.6g}")
        raise UnreachableError(f"the target ({uv[0]:.6g}, {uv[1]:.6g}) is at distance {r:.6g} "
                               f"from the shoulder, {why}", excess=ex)
    up = elbow_above(u, w, A, l1)
    order = [int(np.argmax(up)), int(np.argmin(up))] if up.any() and not up.all() else [0, 1]
    names = {order[0]: "up", order[1]: "down"}
    chosen = [s for s in order if elbow in ("both", names[s])]
    if bool(stretched):
        chosen = chosen[:1]  # both slots are the same chain
    return A, B, chosen, names


def _annotate_triangle(ax: Axes, P: FloatArray, E: FloatArray, a: float, b: float,
                       lengths: tuple[float, float], colour: str, labels: Sequence[str],
                       angle_labels: Sequence[str]) -> None:
    """The sides' names beside the links (outside the triangle) and the angles alpha, phi
    and theta_2 as arcs, for the chain with elbow E (``a``, ``b``: its joint angles)."""
    l1, l2 = lengths
    origin = np.zeros(2)
    r = float(np.hypot(P[0], P[1]))
    for p0, p1, lab in ((origin, E, labels[0]), (E, P, labels[1])):
        m = (p0 + p1) / 2
        d = p1 - p0
        nrm = np.array([-d[1], d[0]]) / np.linalg.norm(d)
        side = 1.0 if np.dot(nrm, m - P / 2) >= 0 else -1.0
        at = m + side * 0.06 * (l1 + l2) * nrm
        ax.text(at[0], at[1], f"${lab}$", color=colour, fontsize=12, ha="center",
                va="center")
    alpha = float(np.arctan2(P[1], P[0]))
    _angle_arc(ax, origin, 0.32 * min(l1, r), 0.0, alpha, angle_labels[0], "0.2")
    _angle_arc(ax, origin, 0.2 * min(l1, r), alpha, a, angle_labels[1], "tab:green")
    if abs(b) > 1e-9:
        _angle_arc(ax, E, 0.22 * min(l1, l2), a, a + b, angle_labels[2], "tab:red")
        ext = E + 0.35 * min(l1, l2) * np.array([np.cos(a), np.sin(a)])
        ax.plot(*np.stack([E, ext]).T, ":", color="tab:red", lw=1.0)


# ------------------------------------------------------------------ workspaces
def _annulus(centre: FloatArray, r_in: float, r_out: float, n: int, **kw: Any) -> PathPatch:
    t = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    outer = centre + r_out * np.stack([np.cos(t), np.sin(t)], axis=1)
    verts = [outer, outer[:1]]
    codes = [Path.MOVETO] + [Path.LINETO] * (n - 1) + [Path.CLOSEPOLY]
    if r_in > 0:
        inner = centre + r_in * np.stack([np.cos(-t), np.sin(-t)], axis=1)  # opposite winding
        verts += [inner, inner[:1]]
        codes += [Path.MOVETO] + [Path.LINETO] * (n - 1) + [Path.CLOSEPOLY]
    return PathPatch(Path(np.vstack(verts), codes), **kw)


def _radii(lengths: Sequence[float]) -> tuple[float, float]:
    """Inner and outer radius reached by a chain of freely turning links."""
    total = float(sum(lengths))
    return max(0.0, 2 * max(lengths) - total), total


def plot_workspace_planar(arm: SerialArm, ax: Axes | None = None, n: int = 256) -> Axes:
    """The reachable region of a planar arm (2R, 3R, ...), shaded.

    For free joints, a chain of links ``l_1..l_k`` reaches the annulus
    between ``max(0, 2 max l_i - sum l_i)`` and ``sum l_i`` (for the 2R,
    ``|l_1 - l_2|`` to ``l_1 + l_2``). For 3 or more links, the wrist point
    (the origin of the last link) has the annulus of the first k-1 links,
    drawn darker over the TCP region. A tool offset lengthens the last link.

    Parameters
    ----------
    arm : SerialArm
        Planar (:func:`is_planar`), at least 2 joints, no joint limits.
    ax : matplotlib Axes (2D), optional
    n : int
        Vertices per circle of the drawn boundary (>= 16).

    Returns
    -------
    matplotlib.axes.Axes
        With PathPatches ``gid="tcp-region"`` (and ``"wrist-region"``).

    Raises
    ------
    InputError
        Not planar, fewer than 2 joints, finite joint limits, or bad ``n``.
    """
    _check_arm(arm)
    if not is_planar(arm):
        raise InputError(f"{arm.name!r} is not planar (every joint revolute, alpha = d = 0)")
    if arm.n < 2:
        raise InputError("the workspace plot needs at least 2 joints")
    if np.isfinite(arm.qlim).any():
        raise InputError("the workspace plot assumes joints without limits; this arm has limits")
    n = as_count(n, "n", minimum=16, maximum=100_000, what="vertices per circle")
    _check_ax(ax)
    lengths = [abs(float(lk.a)) for lk in arm.links]
    last = np.array([float(arm.links[-1].a), 0.0]) + arm.tool[:2, 3]
    lengths[-1] = float(np.linalg.norm(last))
    if ax is None:
        ax = plt.figure(figsize=(5.5, 5.5)).add_subplot()
    centre = arm.base[:2, 3]
    r_in, r_out = _radii(lengths)
    ax.add_patch(_annulus(centre, r_in, r_out, int(n), facecolor="tab:blue", alpha=0.22,
                          edgecolor="tab:blue", lw=1.0, gid="tcp-region",
                          label=phrase("TCP: {r_in} ≤ r ≤ {r_out}", r_in=f"{r_in:.4g}",
                                       r_out=f"{r_out:.4g}")))
    if arm.n >= 3:
        w_in, w_out = _radii(lengths[:-1])
        # the face is translucent, the edge and hatch opaque and darker: one alpha for the
        # whole patch would draw the hatch in the face's own colour (invisible in SVG)
        ax.add_patch(_annulus(centre, w_in, w_out, int(n),
                              facecolor=matplotlib.colors.to_rgba("tab:orange", 0.35),
                              edgecolor="#b35806", lw=1.0, hatch="//", gid="wrist-region",
                              label=phrase("wrist point: {w_in} ≤ r ≤ {w_out}",
                                           w_in=f"{w_in:.4g}", w_out=f"{w_out:.4g}")))
    ax.plot(*centre, "k+", ms=10)
    lim = np.stack([centre - r_out * (1 + MARGIN), centre + r_out * (1 + MARGIN)], axis=1)
    _apply_limits(ax, lim, arm)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(phrase("{name}: reachable region", name=arm.name), fontsize=10)
    return ax


def _sample_joints(arm: SerialArm, n: int, seed: int) -> FloatArray:
    """``n`` seeded joint vectors inside the limits (revolute: all of (-pi, pi] if unlimited)."""
    lim = arm.qlim.copy()
    free = ~np.isfinite(lim)
    if np.any(free.any(axis=1) & np.logical_not(arm.revolute)):
        raise InputError("a prismatic joint without limits has no bounded workspace: give the arm "
                         "joint limits (qlim) to draw it")
    lim[:, 0] = np.where(free[:, 0], -np.pi, lim[:, 0])
    lim[:, 1] = np.where(free[:, 1], np.pi, lim[:, 1])
    rng = np.random.default_rng(seed)
    return rng.uniform(lim[:, 0], lim[:, 1], size=(n, arm.n))


def plot_workspace_3d(arm: SerialArm, ax: Axes | None = None, n: int = 4000, point: str = "tcp",
                      seed: int = 0, q: Any = None) -> Axes:
    """The reachable points of a spatial arm: a cloud of FK positions, coloured by height.

    ``n`` joint vectors are drawn uniformly inside the joint limits (seeded,
    so the figure is the same at every build); revolute joints without
    limits turn all the way round. With ``point="wrist"`` the cloud is of
    the wrist centre (:func:`wrist_centre`), which for a decoupled 6R
    depends on the first three joints only.

    Parameters
    ----------
    arm : SerialArm
    ax : 3D matplotlib Axes, optional
    n : int
        Number of sampled configurations (>= 100).
    point : {"tcp", "wrist"}
    seed : int
        Seed of the sample.
    q : array_like, shape (n,), optional
        Also draw the arm at this configuration, for scale.

    Returns
    -------
    matplotlib.axes.Axes
        3D Axes with a scatter ``gid="workspace"`` (its offsets are the points).

    Raises
    ------
    InputError
        Bad ``n``/``point``/``q``, 2D axes, or a prismatic joint without limits.
    """
    _check_arm(arm)
    n = as_count(n, "n", minimum=100, maximum=10_000_000, what="sampled configurations")
    point = as_choice(point, "point", ("tcp", "wrist"))
    seed = as_count(seed, "seed")
    _check_ax(ax)
    if q is not None:
        _check_q(arm, q)
    Q = _sample_joints(arm, int(n), int(seed))
    F = arm._fk(Q, frames=True)
    pts = (np.stack([_wrist_centre(arm, f) for f in F]) if point == "wrist"
           else F[:, -1, :3, 3])
    ax = _make_axes(True, ax)
    sc = _as_3d(ax).scatter(pts[:, 0], pts[:, 1], pts[:, 2], c=pts[:, 2], cmap="viridis",
                            s=2.0, alpha=0.35, depthshade=False, gid="workspace",
                            linewidths=0)
    lim = _square_limits(np.vstack([pts, arm.base[None, :3, 3]]), 3, _min_half(arm))
    if q is not None:
        qv = _check_q(arm, q)
        _draw_arm(ax, arm, qv, frames=False, frame_scale=float(FRAME_FRACTION * np.ptp(lim[0])),
                  color=None, label_joints=False)
    _apply_limits(ax, lim, arm, azim=-60.0)
    cb = ax.figure.colorbar(sc, ax=ax, shrink=0.6, pad=0.12)
    cb.set_label(f"z{_units(arm)}", fontsize=8)
    if cb.solids is not None:  # (None only before the colorbar is drawn)
        cb.solids.set_alpha(1.0)
    what = "wrist centre" if point == "wrist" else "TCP"
    ax.set_title(phrase(f"{{name}}: {{n}} reachable {what} positions", name=arm.name, n=n),
                 fontsize=10)
    return ax


def wrist_centre(arm: SerialArm, F: FloatArray) -> FloatArray:
    """The wrist centre of a drawn configuration: ``p - l z_n``, back from the TCP.

    ``l`` is how far the TCP lies ahead of the last joint's point (for a
    spherical wrist, the point where the three wrist axes meet) along the
    TCP's z axis (the approach direction), so ``p - l z_n`` is that point
    whenever the TCP is straight ahead of it.

    Parameters
    ----------
    arm : SerialArm
    F : ndarray, shape (n + 2, 4, 4)
        ``arm.fk(q, frames=True)``.

    Returns
    -------
    ndarray, shape (3,)
        World coordinates, length units.
    """
    F = _check_frames(_check_arm(arm), F)
    return _wrist_centre(arm, F)


def _wrist_centre(arm: SerialArm, F: FloatArray) -> FloatArray:
    p, z = F[-1, :3, 3], F[-1, :3, 2]
    last = _joint_points(arm, F)[-1]
    return p - float(np.dot(p - last, z)) * z


def plot_wrist_centre(arm: SerialArm, q: Any, ax: Axes | None = None,
                      title: str | None = None) -> Axes:
    """The arm at ``q`` with its wrist centre ``p_w = p - l z`` and the approach vector drawn.

    The first step of kinematic decoupling: from the TCP position ``p``
    step back the tool length ``l`` along the approach direction ``z`` (the
    TCP's z axis) to the wrist centre, which the first three joints alone
    must reach.

    Parameters
    ----------
    arm : SerialArm
        Spatial.
    q : array_like, shape (n,)
    ax : 3D matplotlib Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.axes.Axes
        With lines ``gid="approach"`` (from ``p_w`` to ``p``) and
        ``gid="wrist-centre"`` (the marked point).
    """
    _check_arm(arm)
    qv = _check_q(arm, q)
    _check_ax(ax)
    title = as_text(title, "title", optional=True)
    F = arm._fk(qv, frames=True)
    w = _wrist_centre(arm, F)
    p = F[-1, :3, 3]
    length = float(np.linalg.norm(p - w))
    ax = plot_arm(arm, qv, ax=ax, frames=False, label_joints=False,
                  title=title if title is not None else
                  phrase("{name}: wrist centre p_w = p − l·z (l = {l})", name=arm.name,
                         l=f"{length:.4g}{_units(arm)}"))
    three_d = ax.name == "3d"
    dims = 3 if three_d else 2
    z = F[-1, :3, 2]
    ax.plot(*np.stack([w, p])[:, :dims].T, "--", color="tab:blue", lw=2.0, gid="approach",
            zorder=6)
    tip = p + 0.25 * max(length, 0.1 * arm.scale) * z
    ax.plot(*np.stack([p, tip])[:, :dims].T, "-", color="tab:blue", lw=2.0, zorder=6)
    ax.plot(*w[:dims], "X", ms=12, color="tab:red", mec="k", mew=0.6, ls="none",
            gid="wrist-centre", zorder=7)
    box = {"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1.0}
    if three_d:
        ax3 = _as_3d(ax)
        for at, label, colour in ((w, "  p_w", "tab:red"), (p, "  p", "tab:orange"),
                                  (tip, "  z", "tab:blue")):
            ax3.text(at[0], at[1], at[2], label, color=colour, fontsize=9, zorder=8, bbox=box)
    else:
        ax.annotate("p_w", (w[0], w[1]), xytext=(6, -12), textcoords="offset points",
                    color="tab:red")
    return ax


def plot_dh_frames(arm: SerialArm, q: Any = None, ax: Axes | None = None,
                   title: str | None = None, view: tuple[float, float] | None = None,
                   frame_scale: float | None = None) -> Axes:
    """The DH frame assignment: every frame's x and z axes, labelled ``x_i``, ``z_i``.

    Frame 0 is the base, frames 1..n follow the links, and the TCP frame
    ends the chain. Each joint i turns (or slides) about ``z_{i-1}``
    (standard DH) and ``x_i`` points along the common normal from
    ``z_{i-1}`` to ``z_i``, so the figure is the picture a DH table is read
    from.

    Parameters
    ----------
    arm : SerialArm
    q : array_like, shape (n,), optional
        Joint values; default all zero (the home pose the DH table describes).
    ax : matplotlib Axes, optional
    title : str, optional
    view : (float, float), optional
        3D camera ``(elevation, azimuth)`` in degrees.
    frame_scale : float, optional
        Triad length, length units; default 9% of the view's side.

    Returns
    -------
    matplotlib.axes.Axes
        With texts ``gid="frame-label"``.
    """
    _check_arm(arm)
    qv = _check_q(arm, np.zeros(arm.n) if q is None else q)
    _check_ax(ax)
    title = as_text(title, "title", optional=True)
    frame_scale = _frame_scale(frame_scale)
    view = _check_view(view)
    F = arm._fk(qv, frames=True)
    ax = plot_arm(arm, qv, ax=ax, frames=True, label_joints=False, gripper=False, view=view,
                  frame_scale=frame_scale, title=title if title is not None else
                  phrase("{name}: DH frames ({convention}) at q = {q}", name=arm.name,
                         convention=word(arm.convention), q=_q_text(arm, qv)))
    three_d = ax.name == "3d"
    fs = float(FRAME_FRACTION * np.ptp(ax.get_xlim())) if frame_scale is None else frame_scale
    names = ["0"] + [str(i) for i in range(1, arm.n + 1)] + ["TCP"]
    seen: list[tuple[FloatArray, int]] = []
    for T, name in zip(F, names, strict=True):
        o = T[:3, 3]
        # frames at the same origin: push the labels of later ones further out
        stack = sum(1 for p, _ in seen if np.linalg.norm(p - o) <= 1e-9 * arm.scale)
        seen.append((o, 0))
        reach = fs * (1.15 + 0.45 * stack)
        for k in ((0, 2) if three_d else (0, 1)):
            tip = o + reach * T[:3, k]
            text = f"{'xyz'[k]}{name}" if name == "TCP" else f"${'xyz'[k]}_{{{name}}}$"
            kw: dict[str, Any] = {"color": AXIS_COLOURS[k], "fontsize": 8,
                                  "gid": "frame-label", "ha": "center", "va": "center"}
            if three_d:
                _as_3d(ax).text(tip[0], tip[1], tip[2], text, **kw)
            else:
                ax.text(tip[0], tip[1], text, **kw)
    return ax


# ------------------------------------------------------------------ orthographic views
#: The world axes of each view of :func:`plot_view` (horizontal, vertical on the page).
VIEWS = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def _dimension(ax: Axes, start: FloatArray, end: FloatArray, text: str, offset: FloatArray,
               colour: str) -> None:
    """A dimension line ("cota"): from start to end, moved by offset, arrows at both ends."""
    a, b = start + offset, end + offset
    for p in (start, end):  # extension lines from the measured points
        ax.plot(*np.stack([p, p + 1.08 * offset]).T, color=colour, lw=0.8, gid="dimension")
    ax.annotate("", xy=(float(b[0]), float(b[1])), xytext=(float(a[0]), float(a[1])),
                gid="dimension", arrowprops={"arrowstyle": "<->", "color": colour, "lw": 1.2,
                                             "shrinkA": 0, "shrinkB": 0})
    mid = (a + b) / 2
    ax.text(float(mid[0]), float(mid[1]), text, color=colour, fontsize=9, ha="center",
            va="center", gid="dimension-text", bbox={"fc": "white", "ec": "none", "pad": 1.0})


def _draw_projection(ax: Axes, arm: SerialArm, F: FloatArray, h: int, v: int,
                     colour: Any) -> tuple[FloatArray, FloatArray]:
    """The links, joints and TCP projected on the world axes ``h`` (across) and ``v`` (up).

    Returns the projected link path ``(2 n + 2, 2)`` and the TCP ``(2,)``."""
    path = _link_path(arm, F)[:, [h, v]]
    ax.plot(*path.T, "-", color=colour, lw=3.0, solid_capstyle="round", gid="arm", zorder=2)
    joints = _joint_points(arm, F)[:, [h, v]]
    ax.plot(*joints.T, "o", ms=7, mfc="white", mec=colour, mew=2.0, ls="none", gid="joints",
            zorder=4)
    tcp = F[-1, :3, 3][[h, v]]
    ax.plot(tcp[0], tcp[1], "*", ms=14, color="tab:orange", mec="k", mew=0.6, ls="none",
            gid="tcp", zorder=5)
    return path, tcp


def _dimension_tcp(ax: Axes, tcp: FloatArray, pts: FloatArray, span: float, across: str,
                   up: str) -> FloatArray:
    """The TCP's two coordinates as dimension lines from the origin, below and right of
    the drawn points ``pts``; returns two points ``(2, 2)`` the view must also hold."""
    low = pts[:, 1].min() - 0.12 * span
    right = pts[:, 0].max() + 0.12 * span
    _dimension(ax, np.array([0.0, 0.0]), np.array([tcp[0], 0.0]),
               f"{across} = {tcp[0]:.4g}", np.array([0.0, low]), "tab:blue")
    _dimension(ax, np.array([0.0, 0.0]), np.array([0.0, tcp[1]]),
               f"{up} = {tcp[1]:.4g}", np.array([right, 0.0]), "tab:blue")
    return np.array([[0.0, low * 1.1], [right * 1.1, 0.0]])


def plot_view(arm: SerialArm, q: Any, view: str = "xz", ax: Axes | None = None,
              dimensions: bool = True, color: Any = None, title: str | None = None) -> Axes:
    """The arm at ``q`` seen along a world axis, with the TCP's coordinates dimensioned.

    An orthographic drawing, as a technical drawing or the lab's GUI shows:
    ``"xz"`` looks along the world y axis (front view), ``"yz"`` along x (side
    view), ``"xy"`` down the z axis (the view from above). The links, joints and
    TCP are FK's, projected; with ``dimensions`` the TCP's two coordinates in the
    view are marked as dimension lines from the world origin.

    Parameters
    ----------
    arm : SerialArm
    q : array_like, shape (n,)
    view : {"xz", "yz", "xy"}
    ax : matplotlib Axes, optional
        2D Axes; a new figure when None.
    dimensions : bool
        Draw the dimension lines of the TCP's two coordinates.
    color : matplotlib colour, optional
        Colour of the links.
    title : str, optional
        Default: which view it is.

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    InputError
        Bad ``q`` or ``view``, or 3D Axes.

    Examples
    --------
    >>> from rikin import robots
    >>> ax = plot_view(robots.epson_c4(), [0, 0, 0, 0, 0, 0], "xz")
    >>> ax.get_xlabel()
    'x (mm)'
    """
    _check_arm(arm)
    qv = _check_q(arm, q)
    _check_ax(ax)
    view = as_choice(view, "view", tuple(VIEWS))
    dimensions = as_flag(dimensions, "dimensions")
    color = _check_colour(color)
    title = as_text(title, "title", optional=True)
    if ax is not None and ax.name == "3d":
        raise InputError("plot_view draws on 2D Axes (it is a flat view), got 3D Axes")
    if ax is None:
        ax = plt.figure(figsize=(4.5, 4.5)).add_subplot()
    h, v = VIEWS[view]
    F = arm._fk(qv, frames=True)
    path, tcp = _draw_projection(ax, arm, F, h, v, ARM_COLOUR if color is None else color)
    names = "xyz"
    u = _units(arm)
    pts = np.vstack([path, [[0.0, 0.0]], [tcp]])
    span = float(np.ptp(pts, axis=0).max()) or 1.0
    if dimensions:
        pts = np.vstack([pts, _dimension_tcp(ax, tcp, pts, span, names[h], names[v])])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * span
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(f"{names[h]}{u}")
    ax.set_ylabel(f"{names[v]}{u}")
    ax.grid(True, lw=0.4, alpha=0.5)
    across = "xyz"[3 - h - v]
    default = phrase("view from above") if view == "xy" else phrase("view along {axis}",
                                                                    axis=across)
    ax.set_title(default if title is None else title, fontsize=10)
    return ax
