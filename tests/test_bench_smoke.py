"""The IK benchmark script runs end to end (small sizes) and prints its figures."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_bench_ik_quick_runs_and_prints_poses_per_second(tmp_path):
    out_json = tmp_path / "bench.json"
    proc = subprocess.run(
        [
            sys.executable,
            str(ROOT / "benchmarks" / "bench_ik.py"),
            "--quick",
            "--json",
            str(out_json),
        ],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "poses/s" in proc.stdout
    assert "peak RSS" in proc.stdout
    data = json.loads(out_json.read_text())
    batch = [r for r in data["results"] if r["method"].startswith("rikin ik_batch")]
    assert batch and all(r["poses_per_s"] > 0 for r in batch)
    # FK of random q is always reachable: the Aula 10 arm then has 8 solutions per pose
    assert all(r["solutions_per_pose"] == 8.0 for r in batch)
    assert data["memory"]["peak_rss_mib"] > 0
    single = {r["arm"]: r for r in data["single_pose"]}
    assert set(single) == {"Aula 10 6R", "Epson C4"}
    assert all(r["rikin_poses_per_s"] > 0 for r in single.values())
    assert single["Aula 10 6R"]["rikin_solutions_per_pose"] == 8.0
    assert "one pose at a time" in proc.stdout
