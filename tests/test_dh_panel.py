"""rikin.widgets.dh_panel and arm_from_table: a DH table typed as text, every solution.

The panel is driven as a user would (text typed into its fields, the Solve button
clicked); every solution it shows is put back through FK here, independently of the
solver's own check.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_widgets_kernel import kernel  # noqa: F401  (the live-kernel fixture)

import rikin
from rikin import InputError, Link, SerialArm, widgets

pi = np.pi

PUMA = SerialArm((
    Link(d=0.67183, alpha=pi / 2), Link(a=0.4318), Link(d=0.15005, a=0.0203, alpha=-pi / 2),
    Link(d=0.4318, alpha=pi / 2), Link(alpha=-pi / 2), Link(),
), units="m", name="Puma 560")

UR5_TABLE = """\
d         a         alpha
0.089159  0          90
0        -0.425       0
0        -0.39225     0
0.10915   0          90
0.09465   0         -90
0.0823    0           0
"""
# the UR5 with axis 1 turned parallel to axes 2-4 (alpha1 = 0): outside every family of
# rikin.ik.classify (no spherical wrist, four parallel axes, two joints doing one motion)
NO_FORM_TABLE = UR5_TABLE.replace("0.089159  0          90", "0.089159  0           0")


def fk_error(arm, Q, T):
    F = arm.fk(Q)
    pos = np.linalg.norm(F[..., :3, 3] - T[:3, 3], axis=-1) / arm.scale
    rot = np.abs(F[..., :3, :3] - T[:3, :3]).max(axis=(-1, -2))
    return float(np.max(np.maximum(pos, rot)))


def test_classify_is_public_in_rikin_ik():
    assert rikin.ik.classify(PUMA).closed_form
    assert "quadratic" in str(rikin.ik.classify(PUMA))


def test_the_default_table_is_the_puma():
    arm = widgets.arm_from_table(widgets.PUMA560_TABLE, units="m")
    Q = np.random.default_rng(1).uniform(-pi, pi, size=(50, 6))
    assert np.abs(arm.fk(Q) - PUMA.fk(Q)).max() < 1e-12


@pytest.mark.parametrize("text", [
    "R 0.67183 0 90 0\nR 0 0.4318 0 0\nR 0.15005 0.0203 -90\nR 0.4318 0 90\nR 0 0 -90\nR 0 0 0",
    "type d a alpha offset\n0.67183, 0, 90, 0\n0, 0.4318, 0, 0\n0.15005, 0.0203, -90, 0\n"
    "0.4318, 0, 90, 0\n0, 0, -90, 0\n0, 0, 0, 0\n",
    "| R | 0,67183 | 0 | 90 |\n| R | 0 | 0,4318 | 0 |\n| R | 0,15005 | 0,0203 | -90 |\n"
    "| R | 0,4318 | 0 | 90 |\n| R | 0 | 0 | -90 |\n| R | 0 | 0 | 0 |",  # a pasted markdown table
    "# my Puma\n\nr\t0.67183\t0\t90  # base\nr 0 0.4318 0\nR 0.15005 0.0203 -90\n"
    "R 0.4318 0 90\nR 0 0 -90\nR 0 0 0\n",
])
def test_tables_as_people_type_them(text):
    arm = widgets.arm_from_table(text, units="m")
    assert arm.n == 6 and arm.joint_types == "RRRRRR"
    Q = np.random.default_rng(2).uniform(-pi, pi, size=(20, 6))
    assert np.abs(arm.fk(Q) - PUMA.fk(Q)).max() < 1e-12


def test_modified_prismatic_offsets_and_tool():
    arm = widgets.arm_from_table("R 0 0 0 30\nP 0.2 0.5 90 0.1", convention="modified",
                                 tool=rikin.transl(0, 0, 0.05))
    ref = SerialArm((Link(offset=pi / 6), Link("P", d=0.2, a=0.5, alpha=pi / 2, offset=0.1)),
                    convention="modified", tool=rikin.transl(0, 0, 0.05))
    q = np.array([0.3, 0.25])
    assert np.abs(arm.fk(q) - ref.fk(q)).max() < 1e-12


@pytest.mark.parametrize("text, match", [
    ("R 0 1 x 0", r"line 1 .*alpha = 'x' is not a number"),
    ("R 0 1 90\nR 0 1", r"line 2 .*3 or 4 numbers.*got 2"),
    ("R 0 1 90 0 7", r"line 1 .*got 5"),
    ("# nothing\n\n", r"no rows"),
    ("Q 0 1 90 0", r"line 1 .*got 5|is not a number"),
])
def test_bad_rows_name_the_line_and_column(text, match):
    with pytest.raises(InputError, match=match):
        widgets.arm_from_table(text)


#: The Puma 560 as books and data sheets print it (issue 28 item 8): columns in another
#: order under a header, joint variables, pi/2, degrees marked ° or deg, Greek letters.
BOOK_TABLES = [
    "| joint | theta | d | a | alpha |\n|---|---|---|---|---|\n"
    "| 1 | q1 | 0.67183 | 0 | pi/2 |\n| 2 | q2 | 0 | 0.4318 | 0 |\n"
    "| 3 | q3 | 0.15005 | 0.0203 | -pi/2 |\n| 4 | q4 | 0.4318 | 0 | pi/2 |\n"
    "| 5 | q5 | 0 | 0 | -pi/2 |\n| 6 | q6 | 0 | 0 | 0 |",
    "i  α_{i}   a_i     d_i      θ_i\n1  90°     0       0.67183  θ1\n"
    "2  0°      0.4318  0        θ2\n3  -90°    0.0203  0.15005  θ3\n"
    "4  90°     0       0.4318   θ4\n5  -90°    0       0        θ5\n"
    "6  0°      0       0        θ6",
    "θ ; d ; a ; α (rad)\nq1 ; 0,67183 ; 0 ; 1.5707963267948966\nq2 ; 0 ; 0,4318 ; 0\n"
    "q3 ; 0,15005 ; 0,0203 ; -π/2\nq4 ; 0,4318 ; 0 ; π/2\nq5 ; 0 ; 0 ; -π/2\nq6 ; 0 ; 0 ; 0",
    "type d a alpha\nR 0.67183 0 90 deg\nR 0 0.4318 0\nR 0.15005 0.0203 -90 deg\n"
    "R 0.4318 0 90deg\nR 0 0 -90 deg\nR 0 0 0",
]


@pytest.mark.parametrize("text", BOOK_TABLES)
def test_tables_as_books_print_them(text):
    arm = widgets.arm_from_table(text, units="m")
    assert arm.n == 6 and arm.joint_types == "RRRRRR"
    Q = np.random.default_rng(3).uniform(-pi, pi, size=(20, 6))
    assert np.abs(arm.fk(Q) - PUMA.fk(Q)).max() < 1e-12


def test_joint_variables_carry_offsets_and_the_joint_type():
    """q2 + 90° is a revolute joint with an offset; d3 in the d column a prismatic joint."""
    arm = widgets.arm_from_table("| θ | d | a | α |\n|--|--|--|--|\n| θ1 | 0.5 | 0 | -90° |\n"
                                 "| θ2 + 90° | 0 | 0.3 | 0 |\n| 0 | d3 | 0 | 0 |\n"
                                 "| theta_4 - pi/2 | 0 | 0 | 0 |")
    ref = SerialArm((Link(d=0.5, alpha=-pi / 2), Link(a=0.3, offset=pi / 2), Link("P"),
                     Link(offset=-pi / 2)))
    assert arm.joint_types == "RRPR"
    Q = np.random.default_rng(4).uniform(-1, 1, size=(10, 4))
    assert np.abs(arm.fk(Q) - ref.fk(Q)).max() < 1e-12
    typed = widgets.arm_from_table("type alpha a d offset\nP 0 0 0.2 0.1\nR -pi/2 0.4 0 45")
    ref = SerialArm((Link("P", d=0.2, offset=0.1), Link(a=0.4, alpha=-pi / 2, offset=pi / 4)))
    assert np.abs(typed.fk(Q[:, :2]) - ref.fk(Q[:, :2])).max() < 1e-12


@pytest.mark.parametrize("text, match", [
    ("theta d a alpha\nq1 0 1 ninety", r"line 2 .*column alpha = 'ninety' is not a number: "
                                         r"write a number of degrees \(90, -90°, 90 deg\)"),
    ("theta d a alpha\nq1 d1 1 0", r"line 2 .*column d = 'd1', a symbol: write its value"),
    ("theta d a alpha\n0 0 1 0", r"line 2 .*no joint variable: write the joint variable"),
    ("theta d a alpha\nq1 0 1", r"line 2 .*3 values under a header of 4 columns"),
    ("theta d a beta\nq1 0 1 0", r"column 'beta' is not one rikin knows; name the columns"),
    ("R 0 __import__('os').getcwd() 0", r"line 1 .*column a = .* is not a number: write a "
                                         r"number in the arm's units"),
    ("R 0 2**999 0", r"column a = '2\*\*999' is not a number"),
    ("R 0 pi/2 0", r"column a = 'pi/2' is an angle"),
])
def test_a_refusal_says_which_cell_and_how_to_write_it(text, match):
    with pytest.raises(InputError, match=match):
        widgets.arm_from_table(text)


def test_panel_gives_every_solution_of_the_typed_joints():
    panel = widgets.dh_panel()
    st = panel.state
    # an arm typed with its limits shows the solutions they allow and counts the others
    assert st.verdict.closed_form and len(st.result) + st.result.discarded == 8
    assert fk_error(st.arm, st.result.q, st.target) < 1e-12
    q = np.radians([20, -30, 40, 10, 50, 60])
    k = int(np.argmin(np.abs(rikin.wrap_angle(st.result.q - q)).max(axis=1)))
    assert np.abs(rikin.wrap_angle(st.result.q[k] - q)).max() < 1e-9
    assert f"the joints you typed are solution {k + 1}" in st.message
    html = panel.html()
    assert all(lab in html for lab in st.result.labels) and "quadratic" in html


def test_panel_pose_target_and_unreachable():
    panel = widgets.dh_panel(mode="pose", target="0.5 0.2 0.6 0 90 0")
    st = panel.state
    T = rikin.homogeneous(rikin.rpy_to_r(0, 90, 0, degrees=True), [0.5, 0.2, 0.6])
    assert np.allclose(st.target, T) and len(st.result) == 8
    assert fk_error(st.arm, st.result.q, T) < 1e-12
    panel.set(target="3 0 0 0 0 0")
    assert panel.state.result is None and panel.state.message.startswith("Unreachable")
    assert "out of reach" in panel.state.message
    panel.set(target="1 2 3")
    msg = panel.state.message
    assert msg.startswith("The target cannot be read") and "6 finite numbers" in msg


def test_panel_without_closed_form_says_why_and_solves_numerically():
    panel = widgets.dh_panel(NO_FORM_TABLE, target="30 -60 80 -110 -90 20")
    st = panel.state
    assert not st.verdict.closed_form and st.result is None
    assert "axis 6 passes 0.09465 m" in st.message and "ik_numerical" in st.message
    assert st.numerical.success and fk_error(st.arm, st.numerical.q, st.target) < 1e-9
    assert "ik_numerical" in panel.html() and panel.figure() is not None


def test_panel_bad_table_is_a_message_not_a_traceback():
    panel = widgets.dh_panel("R 0 1 x")
    assert panel.state.arm is None and "line 1" in panel.state.message
    assert panel.figure() is None and "cannot be read" in panel.static_html()
    with pytest.raises(InputError, match="no input 'colour'"):
        panel.set(colour="red")


def test_static_html_embeds_the_drawing_and_the_table():
    panel = widgets.dh_panel(name="Puma 560")
    out = panel.static_html(alt="eight arms")
    assert out.count("<img") == 1 and 'alt="eight arms"' in out and "base64," in out
    assert "0.4318" in out and all(lab in out for lab in panel.state.result.labels)


def test_text_html_is_the_still_picture_without_the_drawing():
    """The book shows the drawing as an SVG figure of its own, and the text beside it."""
    panel = widgets.dh_panel(name="Puma 560")
    text = panel.text_html()
    assert "<img" not in text and "0.4318" in text
    assert all(lab in text for lab in panel.state.result.labels)
    still = panel.static_html(alt="eight arms")
    assert still.startswith(text.removesuffix("</div>")) and still.count("<img") == 1


def test_widget_typing_a_table_and_pressing_solve():
    pytest.importorskip("ipywidgets")
    panel = widgets.dh_panel()
    panel.widget()
    first = panel._image.value
    assert first[:4] == b"\x89PNG"
    panel._fields["table"].value = NO_FORM_TABLE
    panel._fields["target"].value = "30 -60 80 -110 -90 20"
    (button,) = [c for c in panel.widget().children if type(c).__name__ == "Button"]
    button.click()
    assert "0.09465" in panel._out.value and panel.state.result is None
    assert panel._image.value[:4] == b"\x89PNG" and panel._image.value != first
    # the Puma in modified DH (Craig): a and alpha move down a row
    panel._fields["table"].value = ("R 0.67183 0 0\nR 0 0 90\nR 0.15005 0.4318 0\n"
                                    "R 0.4318 0.0203 -90\nR 0 0 90\nR 0 0 -90")
    panel._fields["convention"].value = "modified"
    button.click()
    st = panel.state
    assert st.arm.convention == "modified" and st.result is not None and len(st.result) == 8
    assert fk_error(st.arm, st.result.q, st.target) < 1e-12
    Q = np.random.default_rng(3).uniform(-pi, pi, size=(20, 6))
    assert np.abs(st.arm.fk(Q) - PUMA.fk(Q)).max() < 1e-12


def test_ik_panel_takes_an_arm_typed_from_its_table():
    panel = widgets.ik_panel(PUMA)
    assert [s[0] for s in panel.spec] == ["x", "y", "z", "roll", "pitch", "yaw"]
    st = panel.state
    assert st.result is not None and len(st.result) == 8
    assert fk_error(PUMA, st.result.q, st.target) < 1e-12
    with pytest.raises(InputError, match="0.09465"):
        widgets.ik_panel(widgets.arm_from_table(NO_FORM_TABLE, units="m"))


@pytest.mark.parametrize("name", list(widgets.EXAMPLES))
def test_every_example_table_is_the_arm_it_names(name):
    panel = widgets.dh_panel(**widgets.EXAMPLES[name])
    st = panel.state
    # an arm typed with its limits shows the solutions they allow and counts the others
    assert st.verdict.closed_form and len(st.result) + st.result.discarded == 8
    assert fk_error(st.arm, st.result.q, st.target) < 1e-12
    assert "the joints you typed are solution" in st.message
    if name.startswith("Epson"):  # the lab's arm: the same FK as rikin.robots.epson_c4, tool too
        ref = rikin.robots.epson_c4()
        Q = np.random.default_rng(4).uniform(-pi, pi, size=(30, 6))
        assert np.abs(st.arm.fk(Q) - ref.fk(Q)).max() < 1e-9 * ref.scale
        ref_res = ref.ik(st.target)  # with the C4's joint limits: it may drop some
        assert len(ref_res) + ref_res.discarded == len(st.result)
        for q in ref_res.q:  # the lesson solver's solutions, each among the table's
            assert np.abs(rikin.wrap_angle(st.result.q - q)).max(axis=1).min() < 1e-9


def test_the_start_from_menu_fills_the_fields_and_solves():
    pytest.importorskip("ipywidgets")
    panel = widgets.dh_panel()
    panel.widget()
    panel._example.value = "Epson C4 (modified DH)"
    assert panel._fields["convention"].value == "modified"
    assert panel._fields["tool"].value == "0 0 -65 180 0 0"
    st = panel.state
    assert st.arm.name == "Epson C4" and st.arm.units == "mm" and len(st.result) == 8
    assert np.allclose(st.arm.tool, rikin.robots.epson_c4().tool, atol=1e-12)
    panel._example.value = "UR5 (no spherical wrist)"
    assert "0.09465" in panel._out.value


def test_tool_as_position_or_pose():
    panel = widgets.dh_panel(tool="0 0 0.1 0 0 90")
    T_tool = panel.state.arm.tool
    assert np.allclose(T_tool, rikin.homogeneous(rikin.rotz(pi / 2), [0, 0, 0.1]), atol=1e-12)
    panel.set(tool="0 0")
    msg = panel.state.message
    assert msg.startswith("The table cannot be read") and "tool" in msg


# ------------------------------------------------------------------ in a live kernel
@pytest.mark.slow
def test_dh_panel_in_a_live_kernel_types_a_table_and_solves(kernel):  # noqa: F811
    """As a browser does it: type a table into the text area (a comm 'update'), press
    Solve (a comm 'custom' click); the kernel sends the verdict, the table and a drawing."""
    from test_widgets_kernel import _iopub_until_idle, _models, _run, _said

    msgs = _run(kernel, "from rikin import widgets\npanel = widgets.dh_panel()\npanel")
    models = _models(msgs)
    by_kind = {}
    for cid, s in models.items():
        by_kind.setdefault(s.get("_model_name"), []).append((cid, s))
    (area,) = [cid for cid, s in by_kind["TextareaModel"] if s["description"] == "DH table"]
    (target,) = [cid for cid, s in by_kind["TextModel"] if s["description"] == "target"]
    (solve,) = [cid for cid, s in by_kind["ButtonModel"] if s["description"] == "Solve"]
    (image,) = [cid for cid, _ in by_kind["ImageModel"]]
    for cid, value in ((area, NO_FORM_TABLE), (target, "30 -60 80 -110 -90 20")):
        msg = kernel.session.msg("comm_msg", {"comm_id": cid, "data": {
            "method": "update", "state": {"value": value}, "buffer_paths": []}})
        kernel.shell_channel.send(msg)
        _iopub_until_idle(kernel, msg["header"]["msg_id"])
    click = kernel.session.msg("comm_msg", {"comm_id": solve, "data": {
        "method": "custom", "content": {"event": "click"}}})
    kernel.shell_channel.send(click)
    answer = _iopub_until_idle(kernel, click["header"]["msg_id"])
    said = _said(answer)
    assert "axis 6 passes 0.09465 m" in said and "ik_numerical" in said, said
    drawn = [m for m in answer if m["msg_type"] == "comm_msg"
             and m["content"]["comm_id"] == image and m.get("buffers")]
    assert drawn and bytes(drawn[-1]["buffers"][0])[:4] == b"\x89PNG"
