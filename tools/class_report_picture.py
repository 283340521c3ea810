#!/usr/bin/env python3
"""The picture of the class report in the instructor's guide (book/instructor/).

Builds a gradebook for an invented class of 40 (seeded scores on the SCARA exercise's
hidden tests, two sections, a late rule, a roster with one student who handed in nothing),
writes the class report with ``rikin-grade``'s own export, and photographs the top of the
page in headless Chromium. Run it from the repository's ``.venv`` after changing the
report:

    .venv/bin/python tools/class_report_picture.py

It needs rikingrade, selenium, chromium and chromedriver (``python3 tools/dev.py test``
installs them).
"""

from __future__ import annotations

import random
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "book" / "instructor" / "class-report.png"
TESTS_OUT = ROOT / "book" / "instructor" / "class-report-tests.png"
FIRST = "Ana Bruno Chen Dara Emil Fatma Goran Hana Ivan Jun Kofi Lena Mia Nadia Omar Pia".split()
LAST = "Silva Rossi Wang Okafor Novak Yilmaz Petrov Sato Kim Mensah Dubois Garcia".split()


def build(folder: Path) -> Path:
    """A gradebook with an invented class, and its views; the report's path."""
    from rikingrade.gradebook import Gradebook
    from rikingrade.hidden import scara
    from rikingrade.report import SubmissionResult, TestResult
    from rikingrade.roster import RosterEntry
    from rikingrade.views import export

    rng = random.Random(27)
    tests = [(t.name, float(t.weight)) for t in scara.TESTS]
    gb = Gradebook.open(folder / "gradebook.sqlite")
    gb.add_assignment("scara", sum(w for _, w in tests), tests)
    gb.set_policy("scara", 1_000_000.0, 10, 50, 0)
    run = gb.start_run("scara", "0", 1, "k", {})
    roster = []
    for i in range(41):
        name = f"{FIRST[i % len(FIRST)]} {LAST[(3 * i) % len(LAST)]}"
        entry = RosterEntry(str(1000 + i), name, section=f"Section {'AB'[i % 2]}", kind="csv")
        roster.append((entry.key, entry.as_dict()))
        if i == 40:  # on the roster, nothing handed in
            continue
        sid = f"s{1000 + i}"
        gb.add_student(sid, name=name, section=entry.section)
        gb.set_roster_key(sid, entry.key)
        skill = rng.betavariate(5, 2)
        points = [
            TestResult(n, w, 1.0 if rng.random() < skill else round(rng.random(), 2), "ok")
            for n, w in tests
        ]
        late = 1_000_000.0 + (86400 * rng.uniform(0.1, 2) if i % 9 == 4 else -3600)
        sub = gb.add_submission(sid, "scara", f"h{i}", f"/class/{sid}.ipynb", late)
        status = "timeout" if i == 7 else "ok"
        res = SubmissionResult(sid, f"/class/{sid}.ipynb", f"h{i}", status, tests=points)
        res.max_score = sum(w for _, w in tests)
        gb.record(run, sub, res, "scara", 1)
    gb.set_roster("scara", "csv", "roster.csv", roster)
    gb.end_run(run, "finished")
    info = export(gb, "scara", "scara", folder, run)
    gb.close()
    return Path(info["report"][0])


def photograph(page: Path, png: Path, width: int = 1000, height: int = 1500) -> None:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = "/usr/bin/chromium"
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"):
        opts.add_argument(flag)
    opts.add_argument(f"--window-size={width},{height}")
    drv = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
    try:
        drv.get(page.as_uri())
        drv.save_screenshot(str(png))
    finally:
        drv.quit()


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        page = build(Path(tmp))
        photograph(page, OUT)
        TESTS_OUT.write_bytes(page.with_name("scara-tests.png").read_bytes())
    print(f"wrote {OUT} and {TESTS_OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
