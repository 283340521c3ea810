"""rikin.interactive (offline plotly figures) and rikin.tables: what they draw, from FK."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import rikin
from rikin import InputError, interactive, robots
from rikin.tables import Table, dh_table, solutions_table, table

AULA10_Q_DEG = [99.6, 9, 26.4, 68.4, 30, 151]


def _aula10():
    arm = robots.aula10_6r()
    return arm, arm.ik(arm.fk(rikin.rad(AULA10_Q_DEG)))


def _links(fig, name):
    (tr,) = [t for t in fig.data if t.name == name]
    return np.column_stack([np.array(tr.x, dtype=float), np.array(tr.y, dtype=float),
                            np.array(tr.z, dtype=float)])


def test_solutions_figure_draws_every_solution_and_steps_through_them():
    arm, res = _aula10()
    f = interactive.solutions_figure(arm, res)
    fig = f.figure
    k = len(res)
    assert len(fig.data) == k * interactive.TRACES_PER_ARM + 1   # + the target ring
    # each solution's link trace is that solution's DH path from FK (independent: origins)
    for i, (q, lab) in enumerate(zip(res.q, res.labels, strict=True)):
        o = arm.fk(q, frames=True)[:, :3, 3]
        drawn = _links(fig, f"{i + 1}: {lab}")
        assert np.allclose(drawn[0::2], o[:-1], atol=1e-5) and np.allclose(drawn[-1], o[-1])
    # one solution visible at first, the buttons show each in turn, and "all"
    vis0 = [bool(t.visible) for t in fig.data]
    assert sum(vis0) == interactive.TRACES_PER_ARM + 1
    (menu,) = fig.layout.updatemenus
    assert [b.label for b in menu.buttons] == [str(i + 1) for i in range(k)] + ["all"]
    for i, b in enumerate(menu.buttons[:k]):
        vis = b.args[0]["visible"]
        on = [j for j, v in enumerate(vis[:-1]) if v]
        assert on == list(range(i * interactive.TRACES_PER_ARM,
                                (i + 1) * interactive.TRACES_PER_ARM))
        assert res.labels[i] in b.args[1]["title.text"]
    assert all(menu.buttons[-1].args[0]["visible"])


def test_solutions_figure_html_is_offline_and_deterministic():
    arm, res = _aula10()
    a = interactive.solutions_figure(arm, res).to_html()
    b = interactive.solutions_figure(arm, res).to_html()
    assert a == b
    assert interactive.HTML_MARKER in a and "Plotly.newPlot" in a
    assert not re.search(r"https?://(?!www\.w3\.org)", a), "the figure names a URL"
    bundle = interactive.solutions_figure(arm, res)._repr_mimebundle_()
    # HTML only (no plotly mime type: it would need plotly's front-end extension), with the
    # text a figure shows until its script has run (an output saved in a file not yet run)
    assert set(bundle) == {"text/html", "text/plain"}
    assert interactive.NOT_DRAWN in bundle["text/html"]
    json.dumps(bundle)


def test_the_book_build_gets_figures_without_plotly_js(monkeypatch):
    """In the book's build (rikin_book sets the variable) a figure's HTML is the div and
    its script alone: the page loads plotly.js from _static."""
    arm, res = _aula10()
    monkeypatch.setenv(interactive.BOOK_BUILD_ENV, "1")
    monkeypatch.setattr(interactive, "_frontend_session", lambda: "a-session")
    interactive._PLOTLY_SENT.clear()
    html = interactive.solutions_figure(arm, res)._repr_mimebundle_()["text/html"]
    assert html == interactive.solutions_figure(arm, res).to_html()
    monkeypatch.delenv(interactive.BOOK_BUILD_ENV)
    html = interactive.solutions_figure(arm, res)._repr_mimebundle_()["text/html"]
    assert "plotly.js v" in html and html.index("window.Plotly") < html.index("Plotly.newPlot")


def test_plotly_js_is_the_bundled_file():
    path = interactive.plotly_js()
    assert path.is_file() and path.name == "plotly.min.js"
    assert path.stat().st_size > 1_000_000


def test_planar_figure_is_2d_and_rejects_bad_input():
    arm = robots.planar_3r()
    res = arm.ik([27.071, 7.071, np.radians(45)])
    fig = interactive.solutions_figure(arm, res).figure
    assert all(t.type == "scatter" for t in fig.data)
    with pytest.raises(InputError, match="selected"):
        interactive.solutions_figure(arm, res, selected=3)
    with pytest.raises(InputError, match="no solutions"):
        interactive.solutions_figure(arm, np.zeros((0, 3)))
    with pytest.raises(InputError, match="height"):
        interactive.solutions_figure(arm, res, height=10)


def test_path_figure_keeps_branches_and_reports_unreachable_steps():
    arm = robots.angular_3r()
    xs = np.linspace(5.0, 35.0, 7)            # the last ones are beyond the reach of 20
    targets = [np.array([x, 4.0, 12.0]) for x in xs]
    f = interactive.path_figure(arm, targets)
    fig = f.figure
    assert len(fig.frames) == len(targets)
    names = {t.legendgroup for t in fig.data if t.legendgroup}
    assert len(names) == 4                    # front/back x up/down along the path
    for fr, t in zip(fig.frames, targets, strict=True):
        title = fr.layout.title.text
        try:
            res = arm.ik(t)
        except rikin.UnreachableError as exc:
            assert "unreachable" in title and f"{exc.excess:.4g}"[:3] in title
            assert all(len(d.x or ()) == 0 for d in fr.data[:-1])
            continue
        assert f"{len(res)} solution" in title
        # the moving target sits at this step's target
        assert np.allclose([fr.data[-1].x[0], fr.data[-1].y[0], fr.data[-1].z[0]], t)
    (slider,) = fig.layout.sliders
    assert len(slider.steps) == len(targets)
    with pytest.raises(InputError, match="at least 2"):
        interactive.path_figure(arm, targets[:1])


def test_arm_figure_one_configuration():
    arm = robots.epson_c4()
    q = rikin.rad([20, -30, 40, 10, 30, 0])
    fig = interactive.arm_figure(arm, q).figure
    o = arm.fk(q, frames=True)[:, :3, 3]
    drawn = _links(fig, arm.name)
    assert np.allclose(drawn[-1], o[-1], atol=1e-5)
    with pytest.raises(InputError, match="one configuration"):
        interactive.arm_figure(arm, np.zeros((2, 6)))


# ---------------------------------------------------------------- tables
def test_solutions_table_html_and_text():
    arm, res = _aula10()
    t = solutions_table(res, decimals=2)
    html = t._repr_html_()
    assert html.count("<tr>") == len(res) + 1
    assert "front/down/no-flip" in html and "99.60" in html and "<th" in html
    text = str(t)
    assert text.splitlines()[0].split()[:3] == ["#", "branch", "q1"]
    assert "np." not in html + text


def test_table_formats_numpy_scalars_without_their_type():
    t = table(["n", "value"], [[np.int64(2), np.float64(300.0)], [3, -0.0]], decimals=1)
    assert "np." not in str(t) + t._repr_html_()
    assert str(t).splitlines()[1].split() == ["2", "300.0"]
    assert str(t).splitlines()[2].split() == ["3", "0.0"]
    with pytest.raises(InputError, match="row 1"):
        Table(["a", "b"], [[1]])


def test_dh_table_rows_follow_the_arm_in_degrees():
    """The HTML DH table shows what the arm's links hold, angles in degrees: checked
    against the lab's and the notes' tables (C4: modified, mm; RPRRR: a slide)."""
    c4 = dh_table(rikin.robots.epson_c4())
    assert c4.header[:6] == ["joint", "type", "α(i−1)", "a(i−1) (mm)", "θ(i)", "d(i) (mm)"]
    assert [r[2:] for r in c4.cells[:4]] == [["0°", "0", "q1", "320", "0°"],
                                             ["90°", "100", "q2", "0", "90°"],
                                             ["0°", "250", "q3", "0", "0°"],
                                             ["-90°", "0", "q4", "-250", "0°"]]
    rp = dh_table(rikin.robots.rprrr())  # a1 + a3 = 4 + 6 on the slide
    assert rp.header[2:6] == ["θ(i)", "d(i)", "a(i)", "α(i)"]
    assert rp.cells[1][1:4] == ["P", "0°", "q2 + 10"]
    assert c4._repr_html_().count("<tr>") == 7 and "np." not in str(c4) + str(rp)
    with pytest.raises(InputError, match="SerialArm"):
        dh_table([1, 2])
