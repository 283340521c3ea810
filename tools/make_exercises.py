#!/usr/bin/env python3
"""Generate exercises/ from solutions/ (the solution notebooks are the single source).

    python3 tools/make_exercises.py                  write exercises/*.ipynb
    python3 tools/make_exercises.py --check          exit 1 and list what is out of date
    python3 tools/make_exercises.py --run-solutions  execute solutions/ first, store their
                                                     checked outputs and the arm drawing
    python3 tools/make_exercises.py --translations   refresh the translation catalogues
                                                     (solutions/locales/) from the sources

Exit codes: 0 done (or, with --check, up to date); 1 only with --check: something is out
of date (listed); 2 an error (a malformed solution notebook, a bad _config.yml, ...).
Any ``python3`` works: without nbformat it re-runs itself under the repository's ``.venv``
(created by ``python3 tools/dev.py book`` if missing).

What it does to each ``solutions/<arm>.ipynb``:

1. The cells tagged ``setup`` and ``checks`` get their source from
   ``tools/exercise_checks.py`` (one copy for all notebooks); solutions/ is
   rewritten if they differ.
2. The exercise is the solution with
   * code between ``### BEGIN SOLUTION (task N)`` and ``### END SOLUTION``
     replaced by ``raise NotImplementedError("task N: <function>")`` at the
     same indentation (regions sit inside function bodies);
   * markdown between ``<!-- BEGIN SOLUTION -->`` and ``<!-- END SOLUTION -->``
     removed;
   * cells tagged ``solution-only`` removed;
   * every output cleared, ``nbval-check-output`` tags dropped, and cells that
     call a stubbed function at top level tagged ``raises-exception`` (so
     ``pytest --nbval-lax exercises/`` expects their NotImplementedError);
   * a first cell, tagged ``rikin-install``, that installs rikin when it is missing from
     the book at ``html.baseurl`` (``_config.yml``; see ``book/_ext/rikin_site.py``). The
     book build replaces it, in the copies it publishes, by one pinned to the sha256 of
     the wheel it publishes.

``--run-solutions`` executes each solution notebook with nbclient
(PYTHONHASHSEED=0), keeps the outputs of cells tagged ``nbval-check-output``
(numbered in order, as nbval needs), moves the image drawn by the cell tagged
``figure-source`` into the attachments of the markdown cell tagged
``arm-figure`` (so the exercise shows the drawing without the DH table that
made it) and clears every other output.

**Other languages** (``exercises/<lang>/<arm>.ipynb``, now Spanish: ``exercises/es/``): the
same exercise made from the solution with every text translated from the gettext catalogue
``solutions/locales/<lang>/LC_MESSAGES/exercises.po`` (see ``tools/exercise_i18n.py``: what
is a message, what must stay the same). Code, function names, task numbers and test values
are the English notebook's, so one grader grades either; the notebook's metadata carries
``language`` and its setup cell sets rikin's language, so the checks and the grader answer
in it. ``--translations`` refreshes the catalogues from the sources (new text gets an empty
translation, changed text keeps its old one marked fuzzy). A message with no current
translation (empty or fuzzy) is refused: the translated notebook is not written (exit 2),
and ``--check`` lists it as out of date, as it does a catalogue not refreshed since the
English changed.
"""

from __future__ import annotations

import argparse
import ast
import copy
import os
import re
import subprocess
import sys
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXIT_OUT_OF_DATE = 1
EXIT_ERROR = 2


def _reexec_under_venv() -> None:
    """No nbformat here (e.g. the system python3): run this script with .venv's Python."""
    venv_py = ROOT / ".venv" / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    if os.environ.get("RIKIN_MAKE_EXERCISES_REEXEC") or Path(sys.prefix).resolve() == (
        ROOT / ".venv"
    ).resolve():
        print("make_exercises: nbformat is not installed in .venv: run python3 tools/dev.py book",
              file=sys.stderr)
        sys.exit(EXIT_ERROR)
    if not venv_py.exists():
        print("make_exercises: no nbformat here and no .venv yet: creating it "
              "(python3 tools/dev.py book's set-up)", file=sys.stderr, flush=True)
        sys.path.insert(0, str(ROOT / "tools"))
        import dev

        dev.ensure_venv("book")
    env = dict(os.environ, RIKIN_MAKE_EXERCISES_REEXEC="1")
    sys.exit(subprocess.call([str(venv_py), str(Path(__file__).resolve()), *sys.argv[1:]],
                             env=env))


try:
    import nbformat
except ImportError:
    if __name__ != "__main__":
        raise
    _reexec_under_venv()

sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402  (the book's URL and the install cell; standard library only)

sys.path.insert(0, str(Path(__file__).resolve().parent))
import exercise_i18n as i18n  # noqa: E402  (the catalogues of the other languages)

SOLUTIONS = ROOT / "solutions"
EXERCISES = ROOT / "exercises"
CHECKS_FILE = ROOT / "tools" / "exercise_checks.py"
GRADER_PACKAGE = ROOT / "grader" / "rikingrade"
CONFIG_FILE = ROOT / "_config.yml"

BEGIN = re.compile(r"^(?P<indent>[ \t]*)### BEGIN SOLUTION(?: \(task (?P<task>[^)]+)\))?\s*$")
END = re.compile(r"^[ \t]*### END SOLUTION\s*$")
MD_REGION = re.compile(r"<!-- BEGIN SOLUTION -->.*?<!-- END SOLUTION -->\n?", re.S)
DEF = re.compile(r"^\s*def (\w+)\(")
SHARED_TAGS = ("setup", "checks")


class GenerationError(Exception):
    """A solution notebook is malformed (unbalanced markers, missing shared cell, ...)."""


def shared_sources(path: Path | None = None) -> dict[str, str]:
    """The sections of tools/exercise_checks.py, by tag ('setup', 'checks')."""
    path = CHECKS_FILE if path is None else path
    out: dict[str, list[str]] = {}
    current = None
    for line in path.read_text(encoding="utf-8").splitlines():
        m = re.match(r"^# %% \[(\w+)\]\s*$", line)
        if m:
            current = m.group(1)
            out[current] = []
        elif current is not None:
            out[current].append(line)
    missing = [t for t in SHARED_TAGS if t not in out]
    if missing:
        raise GenerationError(f"{path} has no section(s) {missing}")
    return {k: "\n".join(v).strip("\n") for k, v in out.items()}


def tags(cell) -> list[str]:
    return list(cell.get("metadata", {}).get("tags", []))


def sync_shared(nb, shared: dict[str, str], name: str) -> bool:
    """Put the shared cells' source into ``nb``; True if anything changed."""
    changed = False
    for tag in SHARED_TAGS:
        cells = [c for c in nb.cells if tag in tags(c)]
        if len(cells) != 1:
            raise GenerationError(f"{name}: expected exactly one cell tagged {tag!r}, "
                                  f"found {len(cells)}")
        if cells[0].source != shared[tag]:
            cells[0].source = shared[tag]
            changed = True
    return changed


def stub_code(source: str, where: str) -> tuple[str, list[str]]:
    """Replace the solution regions of a code cell; return the new source and stubbed names."""
    lines = source.split("\n")
    out: list[str] = []
    names: list[str] = []
    i = 0
    while i < len(lines):
        m = BEGIN.match(lines[i])
        if not m:
            if END.match(lines[i]):
                raise GenerationError(f"{where}: '### END SOLUTION' without a BEGIN")
            out.append(lines[i])
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not END.match(lines[j]):
            if BEGIN.match(lines[j]):
                raise GenerationError(f"{where}: nested '### BEGIN SOLUTION'")
            j += 1
        if j == len(lines):
            raise GenerationError(f"{where}: '### BEGIN SOLUTION' without an END")
        func = next((DEF.match(x).group(1) for x in reversed(out) if DEF.match(x)), None)
        if func is None or not m.group("indent"):
            raise GenerationError(f"{where}: solution regions must sit inside a function body")
        task = m.group("task")
        label = f"task {task}: {func}" if task else func
        out.append(f'{m.group("indent")}raise NotImplementedError("{label}")')
        names.append(func)
        i = j + 1
    return "\n".join(out), names


def top_level_names(source: str) -> set[str]:
    """Names a cell uses outside function and class bodies (what runs when the cell runs)."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return set()
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            for d in getattr(node, "decorator_list", []):
                visit(d)
            return
        if isinstance(node, ast.Name):
            found.add(node.id)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    return found


def clean_metadata(nb) -> None:
    nb.metadata = nbformat.from_dict({
        "kernelspec": {"display_name": "Python 3 (ipykernel)", "language": "python",
                       "name": "python3"},
        "language_info": {"name": "python"},
    })


def install_cell(texts: dict[str, str] | None = None, lang: str | None = None):
    """The exercises' first cell: install rikin from the book at html.baseurl when missing.

    Not pinned to a wheel's sha256 (that changes with every edit of rikin/, and exercises/ is
    in git): it asks the book's manifest. The book build pins the copies it publishes.
    ``texts``: its title and comment translated (``rikin_site.INSTALL_TEXTS``); ``lang``:
    the notebook's language, whose edition of the book (``<baseurl><lang>/``) it names as
    the page to download it again from.
    """
    base = rikin_site.read_base_url(CONFIG_FILE)
    page = base + (f"{lang}/" if lang else "") + rikin_site.EXERCISES_PAGE
    cell = rikin_site.install_cell(base, rikin_site.read_version(), page=page, texts=texts)
    return nbformat.from_dict(cell)


def make_exercise(solution, name: str, texts: dict[str, str] | None = None,
                  lang: str | None = None):
    """The exercise notebook made from one solution notebook (not written); ``texts`` and
    ``lang`` make its install cell in another language (:func:`install_cell`)."""
    nb = copy.deepcopy(solution)
    cells = [install_cell(texts, lang)]
    stubbed: list[str] = []
    for k, cell in enumerate(nb.cells):
        t = tags(cell)
        if "solution-only" in t or rikin_site.INSTALL_TAG in t:
            continue
        where = f"{name} cell {k}"
        if cell.cell_type == "code":
            cell.source, names = stub_code(cell.source, where)
            stubbed += names
            cell.outputs = []
            cell.execution_count = None
            t = [x for x in t if x not in ("nbval-check-output", "raises-exception")]
        elif cell.cell_type == "markdown":
            if "<!-- BEGIN SOLUTION -->" in cell.source or "<!-- END SOLUTION -->" in cell.source:
                cell.source = MD_REGION.sub("", cell.source).rstrip()
                if "SOLUTION -->" in cell.source:
                    raise GenerationError(f"{where}: unbalanced markdown solution markers")
        cell.metadata["tags"] = t
        cells.append(cell)
    for cell in cells:
        if cell.cell_type != "code" or "setup" in tags(cell) or "checks" in tags(cell):
            continue
        if top_level_names(cell.source) & set(stubbed):
            cell.metadata["tags"] = tags(cell) + ["raises-exception"]
    for cell in cells:
        if not cell.metadata.get("tags"):
            cell.metadata.pop("tags", None)
    nb.cells = cells
    clean_metadata(nb)
    return nb


def dumps(nb) -> str:
    return nbformat.writes(nb) + "\n"


def run_solution(path: Path) -> None:
    """Execute one solution notebook and store only the outputs that belong in git."""
    import base64

    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4)
    os.environ["PYTHONHASHSEED"] = "0"
    os.environ.pop("MPLBACKEND", None)     # the kernel must render figures inline
    NotebookClient(nb, timeout=300, kernel_name="python3", record_timing=False,
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
    figure = None
    count = 0
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        t = tags(cell)
        if "figure-source" in t:
            pngs = [o["data"]["image/png"] for o in cell.outputs
                    if o.get("output_type") == "display_data" and "image/png" in o.get("data", {})]
            if len(pngs) != 1:
                raise GenerationError(f"{path.name}: the figure-source cell drew "
                                      f"{len(pngs)} images, expected 1")
            figure = pngs[0]
        if "nbval-check-output" in t:
            count += 1
            cell.execution_count = count
            kept = []
            for o in cell.outputs:
                if o.get("output_type") == "stream":
                    kept.append(nbformat.v4.new_output("stream", name=o["name"], text=o["text"]))
                elif o.get("output_type") == "execute_result":
                    kept.append(nbformat.v4.new_output("execute_result", data={
                        "text/plain": o["data"]["text/plain"]}, execution_count=count))
                elif o.get("output_type") == "error":
                    raise GenerationError(f"{path.name}: a checked cell raised {o['ename']}")
            cell.outputs = kept
        else:
            cell.outputs = []
            cell.execution_count = None
    targets = [c for c in nb.cells if "arm-figure" in tags(c)]
    if figure is not None:
        if len(targets) != 1:
            raise GenerationError(f"{path.name}: expected one markdown cell tagged arm-figure")
        base64.b64decode(figure)  # validate
        targets[0]["attachments"] = {f"{path.stem}.png": {"image/png": figure}}
    clean_metadata(nb)
    path.write_text(dumps(nb), encoding="utf-8")


def _write_if_changed(path: Path, text: str, check: bool, differ: list[str]) -> None:
    """Write ``text`` to ``path`` unless it is there already; note the file if it differs."""
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        differ.append(str(path.relative_to(ROOT)))
        if not check:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")


def _stale_notebooks(folder: Path, wanted: set[str]) -> list[str]:
    return [f"{p.relative_to(ROOT)} (no solution notebook of that name)"
            for p in sorted(folder.glob("*.ipynb")) if p.name not in wanted]


def generate(check: bool) -> list[str]:
    """Sync and generate; return the files that differ (written unless ``check``).

    Raises :class:`GenerationError` when a language's notebooks cannot be made (a message
    without a current translation) and ``check`` is false; with ``check`` that is listed.
    """
    shared = shared_sources()
    differ: list[str] = []
    solutions: dict[str, object] = {}
    for path in sorted(SOLUTIONS.glob("*.ipynb")):
        nb = nbformat.read(path, as_version=4)
        if sync_shared(nb, shared, path.name) or path.read_text(encoding="utf-8") != dumps(nb):
            differ.append(str(path.relative_to(ROOT)))
            if not check:
                path.write_text(dumps(nb), encoding="utf-8")
        solutions[path.name] = nb
        _write_if_changed(EXERCISES / path.name, dumps(make_exercise(nb, path.name)), check,
                          differ)
    if SOLUTIONS.exists():
        differ += _stale_notebooks(EXERCISES, set(solutions))
    for lang in i18n.LANGUAGES:
        differ += _generate_language(lang, solutions, shared, check)
        differ += _check_grader_catalogue(lang, check)
    return differ


def _grader_catalogue(lang: str) -> Path:
    return GRADER_PACKAGE / i18n.GRADER_CATALOGUE.format(lang=lang)


def _check_grader_catalogue(lang: str, check: bool) -> list[str]:
    """The grader's catalogue of ``lang``, if it is not current and complete (an
    untranslated message is refused unless ``check``)."""
    path = _grader_catalogue(lang)
    wanted = [m for ms in i18n.grader_messages(GRADER_PACKAGE).values() for m in ms]
    cat = i18n.read_catalogue(path, lang)
    stale = {m.id for m in cat if m.id} != set(wanted)
    try:
        i18n.translations(cat, wanted, lang)
    except i18n.Untranslated as exc:
        if not check:
            raise GenerationError(f"{path.relative_to(ROOT)}: {exc}") from None
        return [f"{path.relative_to(ROOT)} ({exc})"]
    if stale:
        return [f"{path.relative_to(ROOT)} (not current with the grader's messages: run "
                "python3 tools/make_exercises.py --translations, then translate)"]
    return []


def catalogue_sources(solutions: dict, shared: dict[str, str]) -> dict[str, list[str]]:
    """Every message to translate, by the file it comes from."""
    sources = {str(CHECKS_FILE.relative_to(CHECKS_FILE.parents[1])):
               list(i18n.shared_messages(shared)),
               "book/_ext/rikin_site.py": list(rikin_site.INSTALL_TEXTS)}
    for name, nb in solutions.items():
        sources[f"solutions/{name}"] = list(i18n.notebook_messages(nb, SHARED_TAGS))
    return sources


def _localized_shared(shared: dict[str, str], tr: dict[str, str], lang: str) -> dict[str, str]:
    """The shared cells in ``lang``: messages translated, rikin's language set to it."""
    out = {tag: i18n.translate_shared(src, tr) for tag, src in shared.items()}
    if 'set_language("en")' not in out["setup"]:
        raise GenerationError('the setup section of tools/exercise_checks.py must call '
                              'rikin.i18n.set_language("en") (the other languages set theirs)')
    out["setup"] = out["setup"].replace('set_language("en")', f'set_language("{lang}")')
    return out


def _generate_language(lang: str, solutions: dict, shared: dict[str, str],
                       check: bool) -> list[str]:
    """Write exercises/<lang>/ from the solutions and the catalogue; return what differs."""
    path = i18n.catalogue_path(SOLUTIONS, lang)
    sources = catalogue_sources(solutions, shared)
    cat = i18n.read_catalogue(path, lang)
    differ = []
    wanted = [m for messages in sources.values() for m in messages]
    have = {m.id for m in cat if m.id}
    if have != set(wanted) or any(m.fuzzy for m in cat if m.id):
        differ.append(f"{path.relative_to(ROOT)} (not current with the English: run "
                      "python3 tools/make_exercises.py --translations, then translate)")
    try:
        tr = i18n.translations(cat, wanted, lang)
        localized = _localized_shared(shared, tr, lang)
        for name, nb in solutions.items():
            translated = i18n.translate_notebook(nb, tr, SHARED_TAGS)
            sync_shared(translated, localized, f"{lang}/{name}")
            exercise = make_exercise(translated, name, tr, lang)
            exercise.metadata["language"] = lang
            _write_if_changed(EXERCISES / lang / name, dumps(exercise), check, differ)
    except i18n.Untranslated as exc:
        if not check:
            raise GenerationError(f"{path.relative_to(ROOT)}: {exc}; exercises/{lang}/ not "
                                  "written") from None
        differ.append(f"exercises/{lang}/ ({exc})")
    except i18n.BadTranslation as exc:
        raise GenerationError(f"{path.relative_to(ROOT)}: {exc}") from None
    differ += _stale_notebooks(EXERCISES / lang, set(solutions))
    return differ


def translated_solution(name: str, lang: str):
    """The solution notebook ``name`` in ``lang`` (not written: the grader's tests grade it)."""
    shared = shared_sources()
    nb = nbformat.read(SOLUTIONS / name, as_version=4)
    cat = i18n.read_catalogue(i18n.catalogue_path(SOLUTIONS, lang), lang)
    sources = catalogue_sources({name: nb}, shared)
    tr = i18n.translations(cat, [m for ms in sources.values() for m in ms], lang)
    localized = _localized_shared(shared, tr, lang)
    nb = i18n.translate_notebook(nb, tr, SHARED_TAGS)
    sync_shared(nb, localized, f"{lang}/{name}")
    nb.metadata["language"] = lang
    return nb


def update_translations() -> list[str]:
    """Refresh every language's catalogue from the sources; return the files written."""
    shared = shared_sources()
    solutions = {p.name: nbformat.read(p, as_version=4) for p in sorted(SOLUTIONS.glob("*.ipynb"))}
    for nb in solutions.values():
        sync_shared(nb, shared, "")
    templates = [(i18n.template(catalogue_sources(solutions, shared)),
                  lambda lang: i18n.catalogue_path(SOLUTIONS, lang)),
                 (i18n.template(i18n.grader_messages(GRADER_PACKAGE)), _grader_catalogue)]
    written = []
    for lang in i18n.LANGUAGES:
        for tmpl, where in templates:
            path = where(lang)
            before = path.read_text(encoding="utf-8") if path.exists() else None
            i18n.write_catalogue(path, i18n.updated(i18n.read_catalogue(path, lang), tmpl))
            if path.read_text(encoding="utf-8") != before:
                written.append(str(path.relative_to(ROOT)))
    return written


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true",
                    help="write nothing; exit 1 listing the files that differ from what "
                         "would be generated (exit 2 is an error, never 'out of date')")
    ap.add_argument("--translations", action="store_true",
                    help="refresh the translation catalogues (solutions/locales/) from the "
                         "sources, then generate")
    ap.add_argument("--run-solutions", action="store_true",
                    help="execute solutions/ first and store their checked outputs and the drawing")
    args = ap.parse_args(argv)
    if (args.run_solutions or args.translations) and args.check:
        ap.error("--run-solutions and --translations write files; they cannot be combined "
                 "with --check")
    try:
        if args.run_solutions:
            shared = shared_sources()
            for path in sorted(SOLUTIONS.glob("*.ipynb")):
                nb = nbformat.read(path, as_version=4)
                if sync_shared(nb, shared, path.name):
                    path.write_text(dumps(nb), encoding="utf-8")
                print(f"running {path.relative_to(ROOT)}", flush=True)
                run_solution(path)
        if args.translations:
            for written in update_translations():
                print(f"wrote {written}")
        differ = generate(args.check)
    except (GenerationError, rikin_site.SiteError) as exc:
        print(f"make_exercises: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except Exception:  # noqa: BLE001 - any other failure is an error, never "out of date"
        traceback.print_exc()
        print("make_exercises: failed (see the traceback above)", file=sys.stderr)
        return EXIT_ERROR
    if args.check:
        if differ:
            print("out of date (run python3 tools/make_exercises.py):")
            print("\n".join(f"  {d}" for d in differ))
            return EXIT_OUT_OF_DATE
        print("exercises/ and the shared cells are up to date")
        return 0
    for d in differ:
        print(f"wrote {d}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
