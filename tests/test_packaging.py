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
