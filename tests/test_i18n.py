"""Tables and figures in the book's two languages (rikin.i18n): headers, branch names and
figure titles translated, the data (branch labels, joint values, coordinates) the same in both."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import rikin
from rikin import InputError, robots
from rikin.tables import dh_table, solutions_table

Q_AULA10 = rikin.rad([99.6, 9, 26.4, 68.4, 30, 151])


@pytest.fixture
def spanish():
    rikin.i18n.set_language("es")
    yield
    rikin.i18n.set_language(None)


def _result() -> rikin.IKResult:
    arm = robots.aula10_6r()
    return arm.ik(arm.fk(Q_AULA10))


def test_english_is_the_default(monkeypatch):
    monkeypatch.delenv("RIKIN_LANG", raising=False)
    assert rikin.i18n.language() == "en"
    assert "branch" in _result().table(2)


def test_spanish_tables_translate_headers_and_branch_names(spanish):
    res = _result()
    text = res.table(2)
    assert text.splitlines()[0].split()[:2] == ["#", "rama"]
    assert "delante/abajo/sin voltear" in text and "detrás/arriba/volteada" in text
    html = solutions_table(res)._repr_html_()
    assert ">rama<" in html and "delante/arriba/sin voltear" in html
    header = str(dh_table(robots.aula10_6r())).splitlines()[0].split()
    assert header[:2] == ["articulación", "tipo"] and header[-1] == "desfase"


def test_every_branch_label_word_has_its_spanish(spanish):
    """Every word a label can hold (LABEL_WORDS) reads in Spanish, also inside a root's
    name ("root 2 of 4"), whose numbers stay."""
    from rikin.ik.result import LABEL_WORDS

    words = [w for field in LABEL_WORDS.values() for w in field]
    missing = [w for w in words if rikin.i18n.branch_name(w) == w and w != "singular"]
    assert not missing, f"no Spanish for branch words {missing}"
    assert rikin.i18n.branch_name("root 2 of 4/up") == "raíz 2 de 4/arriba"
    assert rikin.i18n.branch_name("front/down/no-flip") == "delante/abajo/sin voltear"


def test_the_data_stays_english_in_spanish(spanish):
    """Code that picks a branch by its label works in both editions."""
    res = _result()
    assert res.labels[0] == "front/down/no-flip"
    assert res.branches[0].label == "front/down/no-flip"


def test_same_numbers_in_both_languages(spanish):
    res = _result()
    spanish_rows = [line.split()[-6:] for line in res.table(4).splitlines()[1:]]
    rikin.i18n.set_language("en")
    english_rows = [line.split()[-6:] for line in res.table(4).splitlines()[1:]]
    assert spanish_rows == english_rows
    assert np.allclose(np.array(english_rows, float), np.degrees(res.q), atol=1e-4)


def test_the_columns_stay_aligned_with_longer_spanish_names(spanish):
    lines = _result().table(2).splitlines()
    ends = {len(line) for line in lines}
    assert len(ends) == 1, lines


def test_the_environment_chooses_the_language(monkeypatch):
    monkeypatch.setenv("RIKIN_LANG", "es")
    assert rikin.i18n.language() == "es"
    monkeypatch.setenv("RIKIN_LANG", "fr")
    with pytest.raises(InputError, match="RIKIN_LANG must be one of en, es, got 'fr'"):
        rikin.i18n.language()
    rikin.i18n.set_language("en")  # an explicit choice wins over the environment
    try:
        assert rikin.i18n.language() == "en"
    finally:
        rikin.i18n.set_language(None)


@pytest.mark.parametrize("bad", ["fr", "", 3, ["es"]])
def test_a_language_rikin_does_not_speak_is_refused(bad):
    with pytest.raises(InputError, match="language must be one of en, es"):
        rikin.i18n.set_language(bad)


def _figure_texts(fig) -> list[str]:
    return [fig._suptitle.get_text()] + [ax.get_title() for ax in fig.axes if ax.get_title()]


def _numbers(texts) -> list[str]:
    return [n for t in texts for n in re.findall(r"-?\d+(?:\.\d+)?", t)]


def test_solution_figures_speak_spanish_with_the_same_numbers(spanish):
    """plot_solutions' titles: branch names and words in Spanish, every number as in English."""
    import matplotlib.pyplot as plt

    from rikin import plot as rplot

    arm, res = robots.aula10_6r(), _result()
    spanish_texts = _figure_texts(rplot.plot_solutions(arm, res))
    rikin.i18n.set_language("en")
    english_texts = _figure_texts(rplot.plot_solutions(arm, res))
    plt.close("all")
    assert spanish_texts[0] == "Aula 10 6R: 8 soluciones"
    assert english_texts[0] == "Aula 10 6R: 8 IK solutions"
    assert spanish_texts[1].startswith("1: delante/abajo/sin voltear\n")
    assert "mismos puntos articulares que #" in "".join(spanish_texts)
    assert not any(w in "".join(spanish_texts) for w in ("front", "IK solution", "joints where"))
    assert _numbers(spanish_texts) == _numbers(english_texts)


def test_interactive_figures_speak_spanish_with_the_same_data(spanish):
    """The buttons, titles and legend of an interactive figure in Spanish; its data identical."""
    from rikin import interactive

    arm, res = robots.aula10_6r(), _result()
    spanish_fig = interactive.solutions_figure(arm, res).figure
    rikin.i18n.set_language("en")
    english_fig = interactive.solutions_figure(arm, res).figure
    buttons = [b["label"] for b in spanish_fig.layout.updatemenus[0].buttons]
    assert buttons[-1] == "todas" and buttons[:-1] == [str(i) for i in range(1, 9)]
    title = spanish_fig.layout.title.text.replace("<br>", " ")
    assert title.startswith("Aula 10 6R: 8 soluciones 1: ") and "delante/abajo/sin voltear" in title
    names = {t.name for t in spanish_fig.data if t.showlegend is not False}
    assert "1: delante/abajo/sin voltear" in names and not any("front" in n for n in names)
    for s, e in zip(spanish_fig.data, english_fig.data, strict=True):
        for axis in ("x", "y", "z"):
            assert np.array_equal(np.asarray(s[axis], float), np.asarray(e[axis], float),
                                  equal_nan=True)
    assert _numbers([title]) == _numbers([english_fig.layout.title.text])


def test_path_figure_speaks_spanish(spanish):
    from rikin import interactive

    arm = robots.aula10_6r()
    T = arm.fk(Q_AULA10)
    steps = np.repeat(T[None], 3, axis=0)
    steps[:, 0, 3] += np.array([0.0, 1.0, 2.0])
    fig = interactive.path_figure(arm, steps).figure
    html = json.dumps(fig.to_plotly_json(), ensure_ascii=False).replace("<br>", " ")
    assert "el objetivo a lo largo de una trayectoria" in html and "paso 1: 8 soluciones" in html
    assert "reproducir" in html and "the target along" not in html


def test_every_phrase_keeps_its_fields():
    """A translated phrase fills in the same values as the English (so the same numbers)."""
    import string

    def fields(text: str) -> list[str]:
        return sorted(f for _, f, _, _ in string.Formatter().parse(text) if f is not None)

    phrases = rikin.i18n._PHRASES["es"]
    assert len(phrases) > 20
    bad = {en: es for en, es in phrases.items() if fields(en) != fields(es)}
    assert not bad


def test_the_two_link_triangles_legend_speaks_spanish(spanish):
    """The law-of-cosines figure (chapter planar, Figure 4) named its chains "elbow up" and
    "elbow down" in the Spanish edition too; the angles stay as in English."""
    import matplotlib.pyplot as plt

    from rikin import plot as rplot

    def legend(lang):
        rikin.i18n.set_language(lang)
        ax = rplot.plot_two_link_triangle(10, 10, [15.0, 5.0])
        return [t.get_text() for t in ax.get_legend().get_texts()]

    spanish_texts, english_texts = legend("es"), legend("en")
    plt.close("all")
    assert [t.split(":")[0] for t in english_texts] == ["elbow up", "elbow down"]
    assert [t.split(":")[0] for t in spanish_texts] == ["codo arriba", "codo abajo"]
    assert _numbers(spanish_texts) == _numbers(english_texts)


def test_drawings_of_one_arm_speak_spanish(spanish):
    import matplotlib.pyplot as plt

    from rikin import plot as rplot

    arm = robots.aula10_6r()
    assert rplot.plot_arm(arm, Q_AULA10).get_title().startswith("Aula 10 6R en q = (99.6°, 9.0°")
    assert "sistemas DH (estándar) en q" in rplot.plot_dh_frames(arm, Q_AULA10).get_title()
    plt.close("all")
