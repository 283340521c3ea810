"""Tables in the book's two languages (rikin.i18n): headers and branch names translated,
the data (branch labels, joint values) the same in both."""

from __future__ import annotations

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
