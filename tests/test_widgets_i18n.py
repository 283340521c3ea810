"""The live panels in the Spanish edition (rikin.widgets, rikin.interactive): every word a
panel shows (a field's name, a button, a menu's entries, a placeholder, the help line, the
example tables' comments, the status) goes through rikin.i18n.phrase and has its Spanish;
what the panel computes from is the same in both languages."""

from __future__ import annotations

import ast
import html
import re
from pathlib import Path
from typing import Any

import ipywidgets  # the panels' front end: a test of them fails, not skips, without it
import pytest

import rikin
from rikin import interactive, widgets

RIKIN = Path(rikin.__file__).resolve().parent

#: English a Spanish panel must not show (whole words, as the English panel shows them).
ENGLISH = ("Solve", "start from", "target as", "DH table", "name", "units", "tool", "target",
           "convention", "standard", "modified", "joints", "pose", "your table", "your arm",
           "press", "one row per joint", "Your own arm", "and degrees", "the lab's arm",
           "or", "deg", "no spherical wrist", "modified DH", "type", "offset", "solutions",
           "each put back through FK", "the joints you typed", "still picture")


@pytest.fixture
def spanish():
    rikin.i18n.set_language("es")
    yield
    rikin.i18n.set_language(None)


def _texts(w: Any) -> list[str]:
    """Every text a widget and its children show: descriptions, option labels, placeholders,
    text values and HTML (its words, tags and code left out: ``type d a alpha offset`` is
    the table's syntax)."""
    out: list[str] = []
    for attr in ("description", "placeholder", "tooltip"):
        value = getattr(w, attr, None)
        if isinstance(value, str):
            out.append(value)
    labels = getattr(w, "_options_labels", None)
    value = getattr(w, "value", None)
    if labels is not None:  # a menu shows its labels; its value is what the code reads
        out += [str(label) for label in labels]
    elif isinstance(w, ipywidgets.HTML) and isinstance(value, str):
        out.append(html.unescape(re.sub(r"<code>.*?</code>|<[^>]+>", " ", value)))
    elif isinstance(value, str):
        out.append(value)
    for child in getattr(w, "children", ()):
        out += _texts(child)
    return out


def _english_left(texts: list[str]) -> set[str]:
    return {word for word in ENGLISH for text in texts
            if re.search(rf"(?<![\w-]){re.escape(word)}(?![\w-])", text)}


def _panel_texts(panel: widgets.DHPanel) -> list[str]:
    """The panel's texts without rikin's own words, which stay English (classify's verdict
    and reason, quoted in «»)."""
    return [re.sub(r"«[^»]*»", "", t) for t in _texts(panel.widget())]


def test_the_english_panel_shows_the_english_words():
    """The check below would see them (the words listed are the English panel's)."""
    rikin.i18n.set_language("en")
    try:
        panel = widgets.dh_panel(**widgets.EXAMPLES["KUKA KR5"])
        left = _english_left(_panel_texts(panel))
    finally:
        rikin.i18n.set_language(None)
    assert {"Solve", "start from", "target as", "DH table", "tool", "and degrees"} <= left


def test_the_spanish_dh_panel_shows_no_english(spanish):
    panel = widgets.dh_panel()
    texts = _panel_texts(panel)
    assert not _english_left(texts), texts
    assert "Resolver" in texts and "Tabla DH" in texts and "tu brazo" in texts
    # the values the panel computes from stay English (and so do the arm's data)
    assert panel._fields["mode"].value == "joints"
    assert panel._fields["convention"].value == "standard"
    assert panel.state.result is not None and len(panel.state.result) == 8


@pytest.mark.parametrize("name", list(widgets.EXAMPLES))
def test_every_example_table_reads_in_spanish_and_still_solves(spanish, name):
    panel = widgets.dh_panel()
    panel.widget()
    panel._example.value = name  # the menu's value is the English name; its label Spanish
    texts = _panel_texts(panel)
    assert not _english_left(texts), texts
    table = panel._fields["table"].value
    english = widgets.EXAMPLES[name]["table"].rstrip().splitlines()
    for row, typed in zip(table.splitlines(), english, strict=True):
        if typed.lstrip().startswith("#") and re.search(r"[a-z]{3}", typed):
            assert row != typed, f"an English comment in the Spanish panel: {row!r}"
        else:  # the rows as typed
            assert row == typed
    if re.search(r"\([^)]*[a-z]{3}", name):  # the menu's label says more than a name
        assert name in rikin.i18n._PHRASES["es"], name
    st = panel.state
    assert st.result is not None and len(st.result) + st.result.discarded == 8, st.message
    assert "las articulaciones que escribiste son la solución" in st.message
    text = html.unescape(re.sub(r"<[^>]+>", " ", panel.text_html()))
    assert not _english_left([re.sub(r"«[^»]*»", "", text)]), text
    assert "Tabla DH" in text and re.search(r"\(DH (estándar|modificado), ", text)
    assert ("grados" in text) == ("degrees" in widgets.EXAMPLES[name]["table"])


def test_the_spanish_panels_messages(spanish):
    """The status lines the panels write around rikin's (English) reasons."""
    panel = widgets.dh_panel(table="R 0 1\nR")
    assert panel.state.message.startswith("No se puede leer la tabla: ")
    panel.set(table=widgets.PUMA560_TABLE, target="1 2")
    assert panel.state.message.startswith("No se puede leer el objetivo: ")
    # an arm outside every family: no closed form, the reason quoted
    panel.set(table="R 0.4 0 1.5 0\nR 0 0.3 0 0\nR 0 0.3 0 0", target="10 20 30",
              units="m")
    msg = panel.state.message
    assert msg.startswith("Sin forma cerrada: «"), msg
    assert "para la posición del TCP" in msg and "ik_numerical_multistart encuentra" in msg
    ik = widgets.ik_panel(rikin.robots.aula10_6r())
    assert ik.state.message == "8 soluciones"
    ik.set(x=1000.0)
    assert ik.state.message.startswith("fuera de alcance por ")
    assert "objetivo x = 1000" in ik.still_html() and "target" not in ik.still_html()
    labels = [c.description for c in ik.widget().children[1].children]
    assert labels[3:] == ["roll (°)", "pitch (°)", "yaw (°)"]
    assert "Imagen fija del panel interactivo" in widgets._still_bundle(ik)["text/html"]


def _phrase_keys(path: Path) -> list[str]:
    """The templates a module gives :func:`rikin.i18n.phrase`: a string literal, either
    branch of a conditional of literals, or a module constant named there."""
    module = ast.parse(path.read_text(encoding="utf-8"))
    constants = {t.id: n.value.value for n in module.body if isinstance(n, ast.Assign)
                 for t in n.targets if isinstance(t, ast.Name)
                 and isinstance(n.value, ast.Constant) and isinstance(n.value.value, str)}
    keys: list[str] = []

    def literal(node: ast.expr) -> None:
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            keys.append(node.value)
        elif isinstance(node, ast.IfExp):
            literal(node.body)
            literal(node.orelse)
        elif isinstance(node, ast.Name) and node.id in constants:
            keys.append(constants[node.id])

    for node in ast.walk(module):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id == "phrase" and node.args):
            literal(node.args[0])
    return keys


@pytest.mark.parametrize("module", ["widgets.py", "interactive.py"])
def test_every_phrase_of_the_panels_has_its_spanish(module):
    keys = _phrase_keys(RIKIN / module)
    assert len(keys) > 5  # the walk finds them
    spanish = rikin.i18n._PHRASES["es"]
    assert not [k for k in keys if k not in spanish]


def test_the_interactive_figures_target_in_spanish(spanish):
    arm = rikin.robots.aula10_6r()
    res = arm.ik(arm.fk(rikin.rad([99.6, 9, 26.4, 68.4, 30, 151])))
    names = {tr.name for tr in interactive.solutions_figure(arm, res).figure.data}
    assert "objetivo" in names and "target" not in names
    fig = interactive.arm_figure(arm, res.q[0]).figure
    assert fig.layout.title.text.startswith("Aula 10 6R en q = ")
