"""The exercises in Spanish: made from the one source, refused when a translation is missing
or stale, the same code as the English ones, checks and grader answering in Spanish.

(``tests/test_exercises_generated.py`` checks that exercises/es/ is what make_exercises.py
makes, and runs the Spanish stubs like the English ones.)
"""

from __future__ import annotations

import importlib.util
import io
import json
import re
import shutil
import sys
import tokenize
from pathlib import Path

import _hidden_harness as H
import nbformat
import numpy as np
import pytest
from exercise_tree import copy_exercise_tree
from grader_fixtures.helpers import FAST, require_bwrap
from rikingrade import grade, i18n
from rikingrade.assignment import load_assignment
from rikingrade.notebook import parse_notebook
from rikingrade.outputs import feedback_html, feedback_markdown
from rikingrade.reference import cartesian, cylindrical, scara, spherical

ROOT = Path(__file__).resolve().parent.parent
ARMS = ("cartesian", "cylindrical", "spherical", "scara")
CATALOGUE = Path("solutions/locales/es/LC_MESSAGES/exercises.po")


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


mx = _load("make_exercises_i18n", ROOT / "tools" / "make_exercises.py")
ei = sys.modules.get("exercise_i18n") or _load("exercise_i18n", ROOT / "tools" / "exercise_i18n.py")


def tags(cell) -> list[str]:
    return list(cell.get("metadata", {}).get("tags", []))


# ----------------------------------------------------------------------------- generation
@pytest.fixture
def tree(tmp_path, monkeypatch):
    """A copy of solutions/, exercises/ (both languages) and the checks, for the generator."""
    return copy_exercise_tree(mx, tmp_path, monkeypatch)


def _edit_catalogue(root: Path, msgid_part: str, change) -> None:
    cat = ei.read_catalogue(root / CATALOGUE, "es")
    hits = [m for m in cat if m.id and msgid_part in m.id]
    assert hits, msgid_part
    for m in hits:
        change(m)
    ei.write_catalogue(root / CATALOGUE, cat)


@pytest.mark.parametrize("how", ["empty", "fuzzy"])
def test_an_untranslated_message_is_refused(tree, how):
    def untranslate(m):
        if how == "empty":
            m.string = ""
        else:
            m.flags.add("fuzzy")

    _edit_catalogue(tree, "## Task 2: forward kinematics of the positioning arm", untranslate)
    differ = mx.generate(check=True)
    assert any(d.startswith("exercises/es/") and "Task 2" in d for d in differ), differ
    assert mx.main(["--check"]) == 1
    with pytest.raises(mx.GenerationError, match="without a current 'es' translation"):
        mx.generate(check=False)
    assert mx.main([]) == 2


def test_a_message_of_the_checks_untranslated_is_refused(tree):
    _edit_catalogue(tree, "does not reach the target: your {fk}",
                    lambda m: setattr(m, "string", ""))
    with pytest.raises(mx.GenerationError, match="does not reach the target"):
        mx.generate(check=False)


def test_a_stale_translation_is_out_of_date(tree):
    """The English changed: the catalogue is not current, and the new text untranslated."""
    path = tree / "solutions" / "scara.ipynb"
    path.write_text(path.read_text().replace("Run the two cells below first.",
                                             "Run the two cells below before anything else."))
    differ = mx.generate(check=True)
    assert any(str(CATALOGUE) in d and "not current" in d for d in differ), differ
    assert any("Run the two cells below before anything else." in d for d in differ), differ
    # --translations keeps the old Spanish, marked fuzzy: still refused until checked
    assert mx.update_translations() == [str(CATALOGUE)]
    cat = ei.read_catalogue(tree / CATALOGUE, "es")
    m = cat.get("Run the two cells below before anything else.")
    assert m is not None and m.fuzzy and m.string == "Ejecuta primero las dos celdas de abajo."
    with pytest.raises(mx.GenerationError):
        mx.generate(check=False)


def test_a_translation_that_changes_the_code_is_refused(tree):
    _edit_catalogue(tree, 'L = dict(l1=4.0, l2=3.0, l3=2.0)',
                    lambda m: setattr(m, "string", m.string.replace("l3=2.0", "l3=2.5")))
    with pytest.raises(mx.GenerationError, match="not the same code"):
        mx.generate(check=False)


def test_a_translation_that_changes_a_placeholder_is_refused(tree):
    _edit_catalogue(tree, "dh_table has {n} rows",
                    lambda m: setattr(m, "string", m.string.replace("{n}", "{rows}")))
    with pytest.raises(mx.GenerationError, match="placeholders"):
        mx.generate(check=False)


def test_the_catalogues_are_complete_and_current():
    """The committed catalogues: every message translated, none fuzzy, none left over."""
    shared = mx.shared_sources()
    sols = {p.name: nbformat.read(p, as_version=4)
            for p in sorted((ROOT / "solutions").glob("*.ipynb"))}
    for source, path in (
        (mx.catalogue_sources(sols, shared), ROOT / CATALOGUE),
        (ei.grader_messages(ROOT / "grader" / "rikingrade"),
         ROOT / "grader" / "rikingrade" / ei.GRADER_CATALOGUE.format(lang="es")),
    ):
        wanted = [m for ms in source.values() for m in ms]
        cat = ei.read_catalogue(path, "es")
        ei.translations(cat, wanted, "es")  # raises when one is empty or fuzzy
        assert {m.id for m in cat if m.id} == set(wanted), path


# ----------------------------------------------------------------------------- the notebooks
@pytest.mark.parametrize("name", ARMS)
def test_spanish_exercise_is_the_english_one_translated(name):
    en = nbformat.read(ROOT / "exercises" / f"{name}.ipynb", as_version=4)
    es = nbformat.read(ROOT / "exercises" / "es" / f"{name}.ipynb", as_version=4)
    assert es.metadata["language"] == "es" and "language" not in en.metadata
    assert [(c.cell_type, tags(c)) for c in en.cells] == [(c.cell_type, tags(c)) for c in es.cells]
    for a, b in zip(en.cells, es.cells, strict=True):
        if a.cell_type == "code":
            same = a.source.replace('set_language("en")', 'set_language("es")')
            # the install cell names the Spanish edition's exercises page (make_exercises)
            same = same.replace("/book/exercises.html'", "/es/book/exercises.html'")
            # and carries its messages' translations (RIKIN_SAYS; test_book_spanish_text)
            assert ei.same_code(_no_says(same), _no_says(b.source)), a.source[:200]
        else:
            assert a.source != b.source or not ei.WORD.search(a.source)
        assert a.get("attachments") == b.get("attachments")
    checks = next(c.source for c in es.cells if "checks" in tags(c))
    strings = [tok.string for tok in tokenize.generate_tokens(io.StringIO(checks).readline)
               if tok.type == tokenize.STRING]
    text = "".join(s.strip("\"'") for s in strings)  # a long message spans several literals
    assert "no alcanza el objetivo" in text and "soluciones encontradas; faltan:" in text
    assert "does not reach the target" not in text and "solutions found" not in text


def _no_says(source: str) -> str:
    """An install cell's code with its ``RIKIN_SAYS = {...}`` emptied."""
    return re.sub(r"(?ms)^RIKIN_SAYS = \{(?:\}|\s.*?^\})$", "RIKIN_SAYS = {}", source)


def _run(nb):
    """Run the notebook's code cells in one namespace, as Jupyter would: (stdout, error) each."""
    import contextlib

    ns: dict = {"__name__": "__main__"}
    runs = []
    for index, source, _ in H.code_cells(nb):
        buf, err = io.StringIO(), None
        with contextlib.redirect_stdout(buf):
            try:
                exec(compile(source, f"<cell {index}>", "exec"), ns)
            except Exception as exc:  # noqa: BLE001 - a notebook cell may raise anything
                err = exc
        runs.append((index, buf.getvalue(), err))
    import matplotlib.pyplot as plt

    plt.close("all")
    return runs


@pytest.mark.parametrize("name", ["scara", "spherical"])
def test_spanish_checks_pass_a_solution_in_spanish_and_fail_a_wrong_one_in_spanish(name):
    nb = mx.translated_solution(f"{name}.ipynb", "es")
    runs = _run(nb)
    assert [(i, e) for i, _, e in runs if e] == []
    out = "\n".join(o for _, o, _ in runs)
    assert f"✓ ik_{name}: " in out and "de 2 soluciones, y cada una alcanza el objetivo" in out
    assert "los 3 objetivos inalcanzables lanzan ValueError" in out or \
        "objetivos inalcanzables lanzan ValueError" in out
    assert "solutions, each reaching" not in out
    # a wrong IK (one branch only): the message is Spanish
    code = next(c for c in nb.cells if c.cell_type == "code" and f"def ik_{name}(" in c.source)
    code.source += (f"\n\n_right = ik_{name}\n\n\ndef ik_{name}(p, *lengths, **named):\n"
                    "    return _right(p, *lengths, **named)[:1]\n")
    failed = [e for _, _, e in _run(nb) if type(e).__name__ == "CheckFailed"]
    assert failed
    assert "soluciones encontradas; faltan:" in str(failed[0]), str(failed[0])


def test_the_spanish_notebook_sets_rikins_language():
    import rikin

    nb = nbformat.read(ROOT / "exercises" / "es" / "scara.ipynb", as_version=4)
    setup = next(c.source for c in nb.cells if "setup" in tags(c))
    assert 'rikin.i18n.set_language("es")' in setup
    try:
        exec(compile(setup.split("#@title", 1)[1].split("\n", 1)[1], "setup", "exec"), {})
        assert rikin.i18n.language() == "es"
    finally:
        rikin.i18n.set_language(None)


# ----------------------------------------------------------------------------- the grader
def test_notebook_language():
    def nb(metadata, code):
        return json.dumps({"nbformat": 4, "nbformat_minor": 5, "metadata": metadata,
                           "cells": [{"cell_type": "code", "metadata": {}, "outputs": [],
                                      "execution_count": None, "source": code}]}).encode()

    assert parse_notebook(nb({"language": "es"}, "x = 1")).language == "es"
    assert parse_notebook(nb({}, 'rikin.i18n.set_language("es")')).language == "es"
    assert parse_notebook(nb({}, "x = 1")).language == "en"
    assert parse_notebook(nb({"language": "fr"}, "x = 1")).language == "en"
    assert parse_notebook(nb({"language": "en"}, 'set_language("es")')).language == "en"


def test_every_grader_message_and_branch_label_has_a_spanish_translation():
    """Fails when a message the grader writes with t()/N_(), or a part of a branch label the
    reference solutions give, has no Spanish translation."""
    es = i18n.catalogue("es")
    for where, messages in ei.grader_messages(ROOT / "grader" / "rikingrade").items():
        missing = [m for m in messages if m not in es]
        assert not missing, (where, missing)
    rng = np.random.default_rng(7)
    parts: set[str] = set()
    for mod in (cartesian, cylindrical, scara, spherical):
        arm = mod.ARM
        for i in range(40):
            L = arm.sample_lengths(rng)
            tool = arm.sample_tool(rng)
            if i % 3 == 0 and arm.sample_special_q(rng, L, i) is not None:
                kind, q = arm.sample_special_q(rng, L, i)
                parts.add(kind)
            else:
                q = arm.sample_q(rng, L)
            q6 = np.concatenate([q, rng.uniform(-3, 3, 3)])
            if i % 5 == 1:
                q6[4] = 0.0
            for label in arm.ik_6dof(arm.fk_6dof(q6, tool, **L), tool, **L).labels:
                parts.update(i18n.label_parts(label))
    assert "wrist singular (q5 = 0)" in parts and "elbow left (q2 < 0)" in parts
    assert sorted(p for p in parts if p not in es) == []


def test_feedback_headings_follow_the_result_language():
    from rikingrade.report import SubmissionResult, TestResult

    res = SubmissionResult("ana", "a.ipynb", "x", "ok", max_score=1.0,
                           tests=[TestResult("fk", 1.0, 1.0, "bien")])
    assert "## Tests" in feedback_markdown(res, "scara")
    res.language = "es"
    md = feedback_markdown(res, "scara")
    assert "## Pruebas" in md and "[bien]" in md and "retroalimentación para ana" in md
    page = feedback_html(res, "scara")
    assert '<html lang="es">' in page and "<h2>Pruebas</h2>" in page


@pytest.mark.parametrize("exercise", ["scara", "spherical"])
def test_grader_full_marks_for_the_spanish_solution_feedback_in_its_language(exercise, tmp_path):
    require_bwrap()
    a = load_assignment(exercise)
    cls = tmp_path / "class"
    cls.mkdir()
    es = mx.translated_solution(a.notebook, "es")
    nbformat.write(es, cls / "espanol.ipynb")
    shutil.copy(ROOT / "solutions" / a.notebook, cls / "english.ipynb")
    # a Spanish notebook whose IK returns one branch only: its per-task message is Spanish
    wrong = nbformat.read(cls / "espanol.ipynb", as_version=4)
    wrong.cells.append(nbformat.v4.new_code_cell(
        f"_right = ik_{exercise}\n\n\ndef ik_{exercise}(p, *lengths, **named):\n"
        "    return _right(p, *lengths, **named)[:1]\n"))
    nbformat.write(wrong, cls / "incompleto.ipynb")
    report = grade(exercise, [cls], tmp_path / "out", workers=2, **dict(FAST, cell_timeout=30.0))
    res = report.by_student()
    for who in ("espanol", "english"):
        assert res[who].score == pytest.approx(a.max_score), res[who].tests
        assert res[who].status == "ok", res[who].problems
    assert res["espanol"].language == "es" and res["english"].language == "en"
    ik = {t.name: t for t in res["espanol"].tests}["ik"]
    assert "totalmente correctos" in ik.feedback and "fully right" not in ik.feedback
    assert "fully right" in {t.name: t for t in res["english"].tests}["ik"].feedback
    bad = {t.name: t for t in res["incompleto"].tests}["ik"]
    assert bad.fraction < 1 and "Faltan: " in bad.feedback or "faltan: " in bad.feedback, \
        bad.feedback
    assert "missing" not in bad.feedback and "q2" in bad.feedback or "pluma" in bad.feedback
    page = (tmp_path / "out" / "feedback" / "espanol.md").read_text()
    assert "## Pruebas" in page and "Nota:" in page
    assert "## Tests" in (tmp_path / "out" / "feedback" / "english.md").read_text()


# ----------------------------------------------------------------------------- the book
@pytest.mark.parametrize("language", ["es", "en"])
def test_the_spanish_edition_offers_the_spanish_notebooks(tmp_path, language):
    """A {download} of exercises/<arm>.ipynb gives exercises/es/<arm>.ipynb in the Spanish
    edition (book/_ext/rikin_i18n.py), the English notebook in the English one; a real
    Sphinx build of a small project with the book's extension."""
    from sphinx.application import Sphinx

    src = tmp_path / "src"
    (src / "book").mkdir(parents=True)
    (src / "exercises" / "es").mkdir(parents=True)
    (src / "exercises" / "scara.ipynb").write_text('{"lang": "en"}')
    (src / "exercises" / "es" / "scara.ipynb").write_text('{"lang": "es"}')
    (src / "exercises" / "cartesian.ipynb").write_text('{"lang": "en"}')  # no translation
    (src / "conf.py").write_text(
        f"import sys\nsys.path.insert(0, {str(ROOT / 'book' / '_ext')!r})\n"
        f"extensions = ['rikin_i18n']\nlanguage = {language!r}\n"
        "exclude_patterns = ['exercises']\n")
    (src / "index.rst").write_text(".. toctree::\n\n   book/page\n")
    (src / "book" / "page.rst").write_text(
        "Page\n====\n\n:download:`scara.ipynb <../exercises/scara.ipynb>` and "
        ":download:`cartesian.ipynb <../exercises/cartesian.ipynb>`\n")
    out = tmp_path / "html"
    app = Sphinx(str(src), str(src), str(out), str(tmp_path / "doctrees"), "html",
                 status=None, warning=None, freshenv=True)
    app.build()
    got = {p.name: json.loads(p.read_text())["lang"] for p in (out / "_downloads").rglob("*.ipynb")}
    assert got == {"scara.ipynb": language, "cartesian.ipynb": "en"}
