"""The install cell's edge cases (issue 28 item 5): each gives one clear line.

The cell (``book/_ext/rikin_site.py``) runs here as a student's kernel runs it, in a fresh
virtual environment, against small stand-in wheels of rikin (versions 0.0.1 and 9.0.0,
no dependencies) served by a local web server, with pip cut off from any index:

* rikin missing: pip's progress is shown while it runs, then one line;
* run again: one line, nothing installed;
* an older rikin installed: replaced, one line; the older rikin already imported by the
  kernel: the cell raises (Run All stops) saying to restart the kernel, and says so
  again when run once more without the restart;
* the wheel's hash differs, or the book no longer has that wheel (the book was rebuilt
  after the download): "this notebook is older than the book: download it again";
* the book unreachable (offline): "are you online?";
* in IPython, such a stop shows as its message, not a traceback.
"""

from __future__ import annotations

import base64
import functools
import hashlib
import http.server
import io
import os
import re
import socket
import subprocess
import sys
import threading
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import rikin_site  # noqa: E402

PAGE = "http://book.example/book/exercises.html"


def _wheel(version: str) -> bytes:
    """A minimal wheel of a package called rikin at ``version`` (no dependencies)."""
    dist = f"rikin-{version}.dist-info"
    files = {
        "rikin/__init__.py": f'__version__ = "{version}"\n',
        f"{dist}/METADATA": f"Metadata-Version: 2.1\nName: rikin\nVersion: {version}\n",
        f"{dist}/WHEEL": "Wheel-Version: 1.0\nGenerator: test\nRoot-Is-Purelib: true\n"
                         "Tag: py3-none-any\n",
    }
    record = []
    for name, text in files.items():
        digest = base64.urlsafe_b64encode(hashlib.sha256(text.encode()).digest()).rstrip(b"=")
        record.append(f"{name},sha256={digest.decode()},{len(text.encode())}")
    record.append(f"{dist}/RECORD,,")
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name, text in {**files, f"{dist}/RECORD": "\n".join(record) + "\n"}.items():
            z.writestr(name, text)
    return buf.getvalue()


@dataclass
class Book:
    url: str           # the served folder, as RIKIN_BOOK
    folder: Path
    venv_python: Path
    closed: str        # a URL where nothing listens

    def wheel_url(self, version: str, sha: str | None = None) -> str:
        name = f"rikin-{version}-py3-none-any.whl"
        data = (self.folder / name).read_bytes() if (self.folder / name).exists() else b""
        return f"{self.url}{name}#sha256={sha or hashlib.sha256(data).hexdigest()}"


@pytest.fixture(scope="module")
def book(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Book]:
    folder = tmp_path_factory.mktemp("book")
    for version in ("0.0.1", "9.0.0"):
        (folder / f"rikin-{version}-py3-none-any.whl").write_bytes(_wheel(version))

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, format: str, *args: object) -> None:  # noqa: A002
            pass

    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0),
                                            functools.partial(Quiet, directory=str(folder)))
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    # bound, never listening: a connection is refused at once, as on a machine offline (a
    # listening socket never served would hold pip and urllib until their timeouts)
    closed = socket.socket()
    closed.bind(("127.0.0.1", 0))
    venv = tmp_path_factory.mktemp("venv")
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    try:
        yield Book(f"http://127.0.0.1:{httpd.server_address[1]}/", folder,
                   venv / "bin" / "python", f"http://127.0.0.1:{closed.getsockname()[1]}/")
    finally:
        httpd.shutdown()
        httpd.server_close()
        closed.close()


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PIP_", "PYTHON"))}
    env.update(PIP_NO_INDEX="1", PIP_CONFIG_FILE=os.devnull, PIP_RETRIES="0",
               PIP_TIMEOUT="5", PIP_DISABLE_PIP_VERSION_CHECK="1")
    return env


def _run(book: Book, code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(book.venv_python), "-c", code], cwd=cwd, env=_env(),
                          capture_output=True, text=True, timeout=300)


def _cell(book: Book, needed: str, wheel: str | None) -> str:
    return rikin_site.install_cell_source(book.url, needed, wheel, (), page=PAGE)


def _pip(book: Book, *args: str) -> None:
    subprocess.run([str(book.venv_python), "-m", "pip", *args], env=_env(), check=True,
                   capture_output=True, timeout=300)


def _last_error(proc: subprocess.CompletedProcess[str]) -> str:
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert lines and lines[-1].startswith("RikinSetupError: "), proc.stderr[-2000:]
    return lines[-1].removeprefix("RikinSetupError: ")


def test_missing_rikin_is_installed_with_progress_then_one_line(book: Book,
                                                                tmp_path: Path) -> None:
    _pip(book, "uninstall", "--yes", "rikin")
    proc = _run(book, _cell(book, "9.0.0", book.wheel_url("9.0.0")), tmp_path)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.strip().splitlines()
    assert lines[0].startswith(f"rikin is not installed: installing it from {book.url}"), lines
    progress = [ln for ln in lines[1:-1] if re.match(r"\s+\[\s*\d+ s\] ", ln)]
    assert progress and any("rikin" in ln for ln in progress), lines
    assert lines[-1] == "rikin 9.0.0 installed", lines
    # run again: one line, nothing installed
    again = _run(book, _cell(book, "9.0.0", book.wheel_url("9.0.0")), tmp_path)
    assert again.returncode == 0 and again.stdout.strip() == "rikin 9.0.0 is installed", again


def test_an_older_rikin_is_replaced_or_the_kernel_is_restarted(book: Book,
                                                                tmp_path: Path) -> None:
    _pip(book, "install", "--force-reinstall", str(book.folder / "rikin-0.0.1-py3-none-any.whl"))
    proc = _run(book, _cell(book, "9.0.0", book.wheel_url("9.0.0")), tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[0].startswith(
        "rikin 0.0.1 is older than this notebook needs (9.0.0): installing it from")
    assert proc.stdout.strip().splitlines()[-1] == "rikin 9.0.0 installed"
    # the kernel imported the older rikin before the cell ran: Run All must stop here
    _pip(book, "install", "--force-reinstall", str(book.folder / "rikin-0.0.1-py3-none-any.whl"))
    cell = _cell(book, "9.0.0", book.wheel_url("9.0.0"))
    code = (f"import rikin\nCELL = {cell!r}\ntry:\n    exec(CELL)\nexcept Exception as exc:\n"
            "    print(f'FIRST {type(exc).__name__}: {exc}')\nexec(CELL)\n")
    proc = _run(book, code, tmp_path)
    first = [ln for ln in proc.stdout.splitlines() if ln.startswith("FIRST ")]
    assert first and first[0].startswith("FIRST RikinSetupError: rikin 9.0.0 is installed, over "
                                         "packages this kernel had imported"), proc.stdout
    assert "restart the kernel" in first[0]
    said = _last_error(proc)  # run again without the restart: still says to restart
    assert "still runs the one it imported first" in said and "restart the kernel" in said


def test_a_notebook_older_than_the_book_is_told_to_download_again(book: Book,
                                                                  tmp_path: Path) -> None:
    _pip(book, "uninstall", "--yes", "rikin")
    for wheel in (book.wheel_url("9.0.0", sha="0" * 64),            # the hash differs
                  book.wheel_url("8.0.0", sha="1" * 64)):            # no longer in the book
        proc = _run(book, _cell(book, "9.0.0", wheel), tmp_path)
        assert proc.returncode != 0
        said = _last_error(proc)
        assert said.startswith("could not install rikin: this notebook is older than the book")
        assert f"Download this notebook again from {PAGE}" in said, said


def test_offline_says_are_you_online(book: Book, tmp_path: Path) -> None:
    _pip(book, "uninstall", "--yes", "rikin")
    wheel = f"{book.closed}rikin-9.0.0-py3-none-any.whl#sha256={'0' * 64}"
    said = _last_error(_run(book, _cell(book, "9.0.0", wheel), tmp_path))
    assert said.startswith("could not install rikin: pip could not download") and (
        "are you online?" in said), said
    manifest = rikin_site.install_cell_source(book.closed, "9.0.0", None, (), page=PAGE)
    said = _last_error(_run(book, manifest, tmp_path))
    assert "could not tell which rikin to install" in said and "Are you online?" in said, said


def test_a_stop_shows_as_its_message_in_ipython(book: Book, tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """In IPython (here this test's own, where rikin is installed and too old for the cell):
    the stop is an error, shown as one line, not a traceback."""
    from IPython.core.interactiveshell import InteractiveShell
    from IPython.utils.capture import capture_output

    monkeypatch.chdir(tmp_path)  # not inside the repository: no checkout to use
    for k, v in _env().items():
        if k.startswith("PIP_"):
            monkeypatch.setenv(k, v)
    wheel = f"{book.closed}rikin-999.0.0-py3-none-any.whl#sha256={'0' * 64}"
    shell = InteractiveShell.instance()
    try:
        with capture_output() as out:
            result = shell.run_cell(_cell(book, "999.0.0", wheel), store_history=False)
        assert result.error_in_exec is not None
        text = re.sub(r"\x1b\[[0-9;]*m", "", out.stdout + out.stderr)
        assert "RikinSetupError: could not install rikin: pip could not download" in text, text
        assert "Traceback" not in text and "_rikin_" not in text, text
    finally:
        shell.set_custom_exc((), None)
        InteractiveShell.clear_instance()


def test_a_notebook_in_another_language_sets_it_and_hands_over_its_cell_texts(
        tmp_path: Path) -> None:
    """A chapter's notebook of the Spanish edition, run alone (rikin installed, no
    ``locales`` beside it, no RIKIN_LANG): after its install cell, rikin prints in Spanish
    and the cells' ``BookText("locales").tr`` says the texts the cell handed over."""
    import importlib.metadata as md

    cell = rikin_site.install_cell_source(
        "http://book.example/es/", md.version("rikin"), None, (), page=PAGE,
        language="es", cell_texts={"✓ the gap is {gap:.0e}": "✓ la diferencia es {gap:.0e}"})
    after = ("\nfrom rikin.booktext import BookText\n"
             "print(BookText('locales').tr('✓ the gap is {gap:.0e}', gap=2e-16))\n"
             "print(rikin.i18n.branch_name('front/up/no-flip'))\n")
    env = {k: v for k, v in os.environ.items() if k != "RIKIN_LANG"}
    proc = subprocess.run([sys.executable, "-c", cell + after], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.splitlines()[-2:] == ["✓ la diferencia es 2e-16",
                                             "delante/arriba/sin voltear"], proc.stdout
    english = rikin_site.install_cell_source("http://book.example/", "0.1", None, (), page=PAGE)
    assert "set_language" not in english and "RIKIN_CELL_TEXTS" not in english


def test_an_install_cell_language_is_checked() -> None:
    for bad in ("en", "spanish", ""):
        with pytest.raises(rikin_site.SiteError):
            rikin_site.install_cell_source("http://book.example/", "0.1", language=bad)
