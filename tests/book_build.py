"""Run ``jupyter-book build`` for the tests, once more if a notebook's kernel lost the race
for its TCP port.

jupyter_client picks a kernel's ports by binding and releasing them, and the kernel binds
them a moment later; a kernel another process (an nbval or grader test on the other xdist
worker) starts in between may take one first. The kernel then dies with ZMQError "Address
already in use" before it replies to kernel_info, and the build fails although no page is
wrong (jupyter_client and ipykernel issues; papermill #511). That failure, and only that
one, is retried: any other failure, or the same one twice, fails the test.
"""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Any

#: What the build log holds when a kernel lost its port, and nothing else went wrong.
PORT_RACE = ("Address already in use", "Kernel died before replying to kernel_info")


def lost_port_race(log: str) -> bool:
    """True when the build failed because a kernel could not bind its port."""
    return all(marker in log for marker in PORT_RACE)


def run_build(cmd: list[Any], *, cwd: Path, env: dict[str, str],
              timeout: float = 1800) -> subprocess.CompletedProcess[str]:
    """``jupyter-book build`` (``cmd``) with its output in ``stdout``; rerun once after a
    kernel's port race (module docstring), saying so in the log."""
    def once() -> subprocess.CompletedProcess[str]:
        return subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=timeout)

    proc = once()
    if proc.returncode != 0 and lost_port_race(proc.stdout):
        first = proc.stdout
        proc = once()
        proc.stdout = (f"[a kernel lost its port to another process; the build was rerun. "
                       f"First run's log ends:]\n{first[-3000:]}\n[rerun:]\n{proc.stdout}")
    return proc
