"""Each exercise notebook states the grading contract, and it is what the grader does
(issue 11, class 9): the tests and their points, the calling convention and input types,
the libraries, the time limit per call, and how the seed is chosen."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import nbformat
import numpy as np
import pytest
from rikingrade.hidden import EXERCISES
from rikingrade.hidden._common import TIMEOUT

ROOT = Path(__file__).resolve().parent.parent


def _graded_section(folder: str, name: str) -> str:
    nb = nbformat.read(str(ROOT / folder / f"{name}.ipynb"), as_version=4)
    cells = [c.source for c in nb.cells if c.source.startswith("## How your notebook is graded")]
    assert len(cells) == 1
    return cells[0]


@pytest.mark.parametrize("folder", ["exercises", "solutions"])
@pytest.mark.parametrize("name", EXERCISES)
def test_the_notebook_states_what_the_grader_does(name, folder):
    text = _graded_section(folder, name)
    m = importlib.import_module(f"rikingrade.hidden.{name}")
    rows = re.findall(r"^\| `(\w+)` \| ([\d.]+) \| (.+) \|$", text, re.M)
    assert [(t.name, t.weight, t.description) for t in m.TESTS] == [
        (n, float(w), d) for n, w, d in rows]
    # the calls: positional, float64 arrays, as the statement says
    for t in m.TESTS:
        for c in t.make_calls(np.random.default_rng(0)):
            assert c.positional == tuple(c.kwargs)
            assert all(isinstance(v, float) or v.dtype == np.float64 for v in c.kwargs.values())
    assert "positionally, in the order of the signatures" in text
    assert "numpy arrays of float64" in text
    assert f"**{TIMEOUT:g} s**" in text
    assert "**scipy is not**" in text
    assert "seed your instructor sets for the" in text and "new seed each" not in text
    assert "$10^{-6}$" in text and "exactly at 0 is reachable" in text
