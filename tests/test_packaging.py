"""rikin is installed (editable) from this repository, and the documented commands are the
ones CI runs."""

from __future__ import annotations

import json
import os
import re
from importlib import metadata
from pathlib import Path
from urllib.parse import unquote, urlparse

import rikin

ROOT = Path(__file__).resolve().parents[1]
BOOK_CMD = "python3 tools/dev.py book"
TEST_CMD = "python3 tools/dev.py test"


def _pip_installed_rikin() -> metadata.Distribution:
    """The rikin distribution pip installed (its .dist-info has direct_url.json).

    An editable install also leaves rikin.egg-info in the repo root, which shadows the
    installed metadata when the repo root is on sys.path (as under ``python -m pytest``).
    """
    found = [d for d in metadata.distributions(name="rikin") if d.read_text("direct_url.json")]
    assert found, "rikin was not installed by pip from a local directory (no direct_url.json)"
    return found[0]


def test_installed_version_matches_package() -> None:
    assert metadata.version("rikin") == rikin.__version__
    assert _pip_installed_rikin().version == rikin.__version__


def test_rikin_is_editable_install_of_this_repo() -> None:
    direct = json.loads(_pip_installed_rikin().read_text("direct_url.json") or "{}")
    assert direct.get("dir_info", {}).get("editable") is True, direct
    url = urlparse(direct["url"])
    assert url.scheme == "file"
    assert Path(unquote(url.path)).resolve() == ROOT
    # and the imported module is the working tree, not a copy
    assert Path(rikin.__file__).resolve().parent == ROOT / "rikin"


def test_py_typed_marker_present() -> None:
    assert (ROOT / "rikin" / "py.typed").is_file()


def _bash_block_lines(markdown: str) -> list[str]:
    blocks = re.findall(r"^```bash[ \t]*\n(.*?)^```", markdown, flags=re.M | re.S)
    return [line.strip() for block in blocks for line in block.splitlines()]


def test_readme_quick_start_commands() -> None:
    lines = _bash_block_lines((ROOT / "README.md").read_text(encoding="utf-8"))
    assert BOOK_CMD in lines
    assert TEST_CMD in lines


def test_ci_runs_the_readme_test_command() -> None:
    ci = ROOT / ".ci" / "run"
    lines = [ln.strip() for ln in ci.read_text(encoding="utf-8").splitlines()]
    assert TEST_CMD in lines
    assert "set -euo pipefail" in lines
    assert os.access(ci, os.X_OK), ".ci/run must be executable"


# --- the book hosts rikin: one URL, reproducible distributions, the install cell -------------

import shutil  # noqa: E402
import socket  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tarfile  # noqa: E402
import zipfile  # noqa: E402

import pytest  # noqa: E402
import yaml  # noqa: E402

sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402


def test_site_url_is_configured_in_one_place() -> None:
    text = (ROOT / "_config.yml").read_text(encoding="utf-8")
    config = yaml.safe_load(text)
    url = config["html"]["baseurl"]
    assert rikin_site.read_base_url() == url.rstrip("/") + "/"
    assert len(re.findall(r"(?m)^\s+baseurl:", text)) == 1
    assert "rikin_pip_spec" not in text and "example.invalid" not in text
    # the code reads it from there: no copy of it elsewhere (exercises/ is generated from it)
    for path in [*(ROOT / "tools").glob("*.py"), *(ROOT / "book" / "_ext").glob("*.py"),
                 *(ROOT / "rikin").rglob("*.py")]:
        assert url not in path.read_text(encoding="utf-8"), path
    for nb in (ROOT / "exercises").glob("*.ipynb"):
        assert f"RIKIN_BOOK = {rikin_site.read_base_url()!r}" in nb.read_text(encoding="utf-8")


def test_base_url_reader_agrees_with_yaml(tmp_path: Path) -> None:
    cfg = tmp_path / "_config.yml"
    for value, want in (('"https://a.b/c"', "https://a.b/c/"),
                        ("https://a.b/c/  # x", "https://a.b/c/"),
                        ("'http://127.0.0.1:9/'", "http://127.0.0.1:9/")):
        cfg.write_text(f"title: t\nhtml:\n  favicon: x.svg\n  baseurl: {value}\n"
                       "  use_edit_page_button: false\nsphinx:\n  config:\n    baseurl: nope\n")
        assert rikin_site.read_base_url(cfg) == want
        assert yaml.safe_load(cfg.read_text())["html"]["baseurl"].rstrip("/") + "/" == want
    cfg.write_text("html:\n  favicon: x.svg\n")
    with pytest.raises(rikin_site.SiteError, match="html.baseurl is not set"):
        rikin_site.read_base_url(cfg)
    cfg.write_text('html:\n  baseurl: "www.example.org"\n')
    with pytest.raises(rikin_site.SiteError, match="absolute http"):
        rikin_site.read_base_url(cfg)


@pytest.fixture(scope="module")
def dists(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("dist") / "dist"
    return out, rikin_site.build_distributions(out)


def test_wheel_and_sdist_are_built_with_their_sha256(dists: tuple[Path, dict]) -> None:
    out, manifest = dists
    assert manifest["version"] == rikin.__version__
    assert json.loads((out / rikin_site.MANIFEST).read_text()) == manifest
    sums = dict(line.split("  ")[::-1] for line in (out / "SHA256SUMS").read_text().splitlines())
    for kind in ("wheel", "sdist"):
        f = out / manifest[kind]["file"]
        assert sums[f.name] == manifest[kind]["sha256"] == rikin_site.sha256_of(f)
        assert manifest[kind]["size"] == f.stat().st_size
    assert manifest["wheel"]["file"] == f"rikin-{rikin.__version__}-py3-none-any.whl"
    with zipfile.ZipFile(out / manifest["wheel"]["file"]) as whl:
        names = set(whl.namelist())
        meta = whl.read(f"rikin-{rikin.__version__}.dist-info/METADATA").decode()
    sources = {p.relative_to(ROOT).as_posix() for p in (ROOT / "rikin").rglob("*")
               if p.is_file() and "__pycache__" not in p.parts}
    assert sources <= names, sources - names
    assert not {n for n in names if not n.startswith(("rikin/", "rikin-"))}, "only rikin in it"
    assert f"rikin-{rikin.__version__}.dist-info/licenses/LICENSE" in names
    for dep in ("numpy", "sympy", "matplotlib"):
        assert re.search(rf"(?m)^Requires-Dist: {dep}\b", meta), dep
    assert re.search(r"(?m)^License-Expression: MIT$", meta)
    with tarfile.open(out / manifest["sdist"]["file"]) as sdist:
        members = {m.name.split("/", 1)[1] for m in sdist.getmembers() if "/" in m.name}
    assert {"LICENSE", "pyproject.toml", "README.md", "rikin/__init__.py"} <= members
    assert not any(m.startswith(("tests/", "grader/", "book/")) for m in members)


def test_wheel_is_reproducible(dists: tuple[Path, dict], tmp_path: Path) -> None:
    """Same sources, same wheel bytes: the hash a notebook pins does not change by rebuilding."""
    _, first = dists
    again = rikin_site.build_distributions(tmp_path / "again")
    assert again["wheel"] == first["wheel"]


def test_pip_refuses_a_wheel_whose_hash_differs(dists: tuple[Path, dict], tmp_path: Path) -> None:
    out, manifest = dists
    url = (out / manifest["wheel"]["file"]).as_uri() + "#sha256=" + "0" * 64
    proc = subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "--dest",
                           tmp_path, f"rikin @ {url}"], capture_output=True, text=True)
    assert proc.returncode != 0 and "DO NOT MATCH THE HASHES" in proc.stdout + proc.stderr


def _run_install_cell(source: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith("PIP_")}
    env.update(PIP_RETRIES="0", PIP_TIMEOUT="5", PIP_NO_INDEX="1", PIP_CONFIG_FILE=os.devnull)
    return subprocess.run([sys.executable, "-c", source], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=120)


def test_install_cell_installs_only_the_pinned_wheel() -> None:
    wheel = f"http://h.test/_static/dist/rikin-1.2.3-py3-none-any.whl#sha256={'a' * 64}"
    src = rikin_site.install_cell_source("http://h.test/", "1.2.3", wheel, ("interactive",))
    compile(src, "install-cell", "exec")
    assert f"RIKIN_WHEEL = {wheel!r}" in src
    # the one pip call installs "rikin[extras] @ <wheel>"; no bare name ever reaches pip
    calls = re.findall(r'"pip", "install",(.*?)\]', src, re.S)
    assert len(calls) == 1 and 'f"rikin{extras} @ {wheel}"' in calls[0]
    assert '"rikin"]' not in src and "'rikin']" not in src
    cell = rikin_site.install_cell("http://h.test/", "1.2.3", wheel)
    assert cell["cell_type"] == "code" and rikin_site.INSTALL_TAG in cell["metadata"]["tags"]


def test_install_cell_is_a_no_op_where_rikin_is_installed(tmp_path: Path) -> None:
    src = rikin_site.install_cell_source("http://127.0.0.1:9/", rikin.__version__,
                                         None, rikin_site.CHAPTER_EXTRAS)
    proc = _run_install_cell(src, tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == f"rikin {rikin.__version__} is installed"


def test_install_cell_uses_the_checkout_inside_the_repository() -> None:
    src = rikin_site.install_cell_source("http://127.0.0.1:9/", "999.0", None)
    proc = _run_install_cell(src, ROOT / "book")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == f"rikin from the checkout at {ROOT}"


def test_install_cell_says_what_failed_when_the_book_is_unreachable(tmp_path: Path) -> None:
    with socket.socket() as s:  # a port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    book = f"http://127.0.0.1:{port}/"
    proc = _run_install_cell(rikin_site.install_cell_source(book, "999.0", None), tmp_path)
    assert proc.returncode != 0
    assert "could not tell which rikin to install" in proc.stderr and book in proc.stderr
    wheel = f"{book}_static/dist/rikin-999.0-py3-none-any.whl#sha256={'0' * 64}"
    proc = _run_install_cell(rikin_site.install_cell_source(book, "999.0", wheel), tmp_path)
    assert proc.returncode != 0
    assert "is older than this notebook needs (999.0): installing it from" in proc.stdout
    assert "could not install rikin: pip could not download" in proc.stderr


# --- what each command installs ---------------------------------------------------------------


def _requirement_lines(name: str) -> list[str]:
    return [ln.split("#")[0].strip() for ln in (ROOT / name).read_text().splitlines()
            if ln.split("#")[0].strip()]


def test_the_book_needs_only_the_book_requirements() -> None:
    book = _requirement_lines("requirements-book.txt")
    names = {re.split(r"[<>=\[ ]", ln)[0].lower() for ln in book}
    assert {"jupyter-book", "sphinx-mathjax-offline", "ipykernel", "build"} <= names
    for heavy in ("pytest", "hypothesis", "selenium", "nbval", "jupyterlab", "jupytext",
                  "pytest-xdist", "./grader", "-r"):
        assert not any(ln.lower().startswith(heavy) or heavy in ln for ln in book), heavy
    assert _requirement_lines("requirements-grader.txt") == ["-e ./grader"]
    full = _requirement_lines("requirements.txt")
    assert "-r requirements-book.txt" in full and "-r requirements-grader.txt" in full
    sys.path.insert(0, str(ROOT / "tools"))
    import dev

    assert dev.REQUIREMENTS == {"book": "requirements-book.txt", "all": "requirements.txt"}


def test_licences() -> None:
    mit = (ROOT / "LICENSE").read_text()
    assert mit.startswith("MIT License") and "Permission is hereby granted" in mit
    cc = (ROOT / "LICENSES" / "CC-BY-4.0.txt").read_text()
    assert cc.startswith("Attribution 4.0 International")
    for n in range(1, 9):
        assert f"Section {n} -- " in cc
    assert "CC BY 4.0" in (ROOT / "_config.yml").read_text()


# --- tools/make_exercises.py: any python3, distinct exit codes --------------------------------


def _base_python() -> str:
    for name in ("python3", "python"):
        exe = Path(sys.base_prefix) / "bin" / name
        if exe.exists():
            return str(exe)
    pytest.fail(f"no python under {sys.base_prefix}")


def test_make_exercises_runs_under_a_python_without_nbformat(tmp_path: Path) -> None:
    # -S: no site-packages, so surely no nbformat: the script must re-run itself under .venv
    proc = subprocess.run([_base_python(), "-S", str(ROOT / "tools" / "make_exercises.py"),
                           "--check"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "up to date" in proc.stdout


def test_make_exercises_exit_codes(tmp_path: Path) -> None:
    import importlib.util

    spec = importlib.util.spec_from_file_location("mx", ROOT / "tools" / "make_exercises.py")
    mx = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mx)
    assert mx.main(["--check"]) == 0
    bad = tmp_path / "solutions"
    bad.mkdir()
    (bad / "broken.ipynb").write_text("{ not json")
    mx.ROOT, mx.SOLUTIONS, mx.EXERCISES = tmp_path, bad, tmp_path / "exercises"
    assert mx.main(["--check"]) == mx.EXIT_ERROR == 2
    (bad / "broken.ipynb").unlink()
    shutil.copy(ROOT / "solutions" / "scara.ipynb", bad)
    (tmp_path / "exercises").mkdir()
    assert mx.main(["--check"]) == mx.EXIT_OUT_OF_DATE == 1
    with pytest.raises(SystemExit) as exc:
        mx.main(["--no-such-option"])
    assert exc.value.code == 2


# --- releasing: tools/release.py ---------------------------------------------------------------


def _release_module():
    import importlib.util

    spec = importlib.util.spec_from_file_location("release", ROOT / "tools" / "release.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_release_turns_unreleased_into_the_version_section() -> None:
    rel = _release_module()
    text = ("# Changelog\n\nintro\n\n## [Unreleased]\n\n- a fix\n- a feature\n\n"
            "## [0.1.0] - 2026-01-02\n\n- first\n")
    out = rel.changelog_released(text, "0.2.0", "2026-12-24")
    assert out == ("# Changelog\n\nintro\n\n## [Unreleased]\n\n## [0.2.0] - 2026-12-24\n\n"
                   "- a fix\n- a feature\n\n## [0.1.0] - 2026-01-02\n\n- first\n")
    with pytest.raises(rel.ReleaseError, match="nothing under"):
        rel.changelog_released(out, "0.3.0", "2026-12-25")
    with pytest.raises(rel.ReleaseError, match="already has a section"):
        rel.changelog_released(text, "0.1.0", "2026-12-25")
    init = '"""doc"""\n\n__version__ = "0.1.0"\n\nfrom . import x\n'
    assert rel.version_set(init, "0.2.0") == init.replace("0.1.0", "0.2.0")
    assert rel.main(["0.0.1"]) == 1  # older than the current version: refused, nothing changed
    assert rel.main(["two"]) == 1


def test_the_changelog_has_entries_to_release() -> None:
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert "## [Unreleased]" in text
    # the current version is either released in it or about to be (Unreleased has entries)
    rel = _release_module()
    if f"## [{rikin.__version__}]" not in text:
        rel.changelog_released(text, rikin.__version__, "2000-01-01")
