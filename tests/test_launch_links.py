"""Launch links and the local-preview guard (issue 28 item 4), without building the book.

The built book's pages are checked in ``tests/test_student_download.py`` (the site built for
a loopback address, with the launch key set): a banner on every page, launch links on
every chapter and exercise page.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402


@pytest.mark.parametrize("url,loopback", [
    ("http://127.0.0.1:8000/", True), ("http://127.5.0.1/", True), ("http://localhost:8000/", True),
    ("http://LOCALHOST/", True), ("http://[::1]:8000/", True), ("http://0.0.0.0:8000/", True),
    ("http://book.localhost/", True), ("https://user.github.io/course/", False),
    ("http://10.1.2.3/", False), ("https://moodle.example.edu/pluginfile.php/1/", False),
])
def test_loopback_addresses_are_recognised(url: str, loopback: bool) -> None:
    assert rikin_site.is_loopback(url) is loopback


def test_one_key_gives_colab_and_binder_links() -> None:
    repo = rikin_site.read_launch_repository("https://github.com/rikin-course/book/tree/gh-pages")
    links = rikin_site.launch_links(repo, "_sources/book/epson_c4.ipynb")
    assert links == {
        "Colab": "https://colab.research.google.com/github/rikin-course/book/blob/gh-pages/"
                 "_sources/book/epson_c4.ipynb",
        "JupyterLab (Binder)": "https://mybinder.org/v2/gh/rikin-course/book/gh-pages"
                               "?urlpath=lab%2Ftree%2F_sources%2Fbook%2Fepson_c4.ipynb",
    }
    # a site published from a folder of a branch
    repo = rikin_site.read_launch_repository("https://github.com/me/ik/tree/main/docs/")
    assert rikin_site.launch_links(repo, "_static/exercises/scara.ipynb")["Colab"].endswith(
        "/me/ik/blob/main/docs/_static/exercises/scara.ipynb")
    assert rikin_site.read_launch_repository("") is None
    assert rikin_site.read_launch_repository(None) is None


@pytest.mark.parametrize("bad", ["github.com/me/ik", "https://github.com/me/ik",
                                 "https://gitlab.com/me/ik/tree/main",
                                 "https://github.com/me/ik/blob/main/x.ipynb"])
def test_a_launch_key_that_is_not_a_github_folder_is_refused_saying_how(bad: str) -> None:
    with pytest.raises(rikin_site.SiteError, match=r"like https://github.com/<user>/<repo>/tree"):
        rikin_site.read_launch_repository(bad)


def _release_module():
    spec = importlib.util.spec_from_file_location("release", ROOT / "tools" / "release.py")
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _config(tmp_path: Path, base: str) -> Path:
    cfg = tmp_path / "_config.yml"
    cfg.write_text(f'title: t\nhtml:\n  baseurl: "{base}"\n', encoding="utf-8")
    return cfg


def test_release_refuses_a_loopback_base_url_and_changes_nothing(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    rel = _release_module()
    changelog = tmp_path / "CHANGELOG.md"
    changelog.write_text("# Changelog\n\n## [Unreleased]\n\n- a fix\n", encoding="utf-8")
    monkeypatch.setattr(rel, "CONFIG", _config(tmp_path, "http://127.0.0.1:8000/"))
    monkeypatch.setattr(rel, "CHANGELOG", changelog)
    monkeypatch.setattr(rel, "INIT", tmp_path / "missing-init.py")
    monkeypatch.setattr(rel, "_venv_python", lambda: pytest.fail("the release went on"))
    assert rel.main(["9.9.9"]) == 1
    err = capsys.readouterr().err
    assert "html.baseurl is http://127.0.0.1:8000/, a loopback address" in err, err
    assert "public URL" in err
    assert "## [Unreleased]\n\n- a fix" in changelog.read_text(encoding="utf-8")
    assert rel.check_public_url(_config(tmp_path, "https://me.github.io/ik/")) == (
        "https://me.github.io/ik/")
