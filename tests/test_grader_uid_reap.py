"""The uid sandbox leaves no process behind, zombies included, when init reaps nobody.

In a container whose PID 1 is not an init (Docker without ``--init``, this CI machine), a
process orphaned when its zygote is SIGKILLed would be adopted by PID 1 and, once killed,
stay a zombie of the sandbox uid until that init gets round to it (here: now and then): it
counts for that uid's process limit and keeps the uid from being leased. The rikin-grade
command is the subreaper of what it starts and collects such zombies itself.

The scenario runs in a subprocess of its own (the subreaper flag is per process) as root,
as the uid sandbox needs; where it cannot run, the test fails, saying why.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import pytest

SCENARIO = textwrap.dedent(
    """
    import json, os, signal, subprocess, sys, time
    from rikingrade.sandbox import uidmode

    uidmode.adopt_orphans()  # as the rikin-grade command does at its start
    lease = uidmode.UidLease.acquire()
    uid = lease.uid
    # an interpreter the sandbox uid may run (the venv's may sit in a private folder)
    for exe in (sys.executable, os.path.realpath(sys.executable), "/usr/bin/python3"):
        try:
            ok = subprocess.run([exe, "-S", "-c", "pass"], user=uid, group=uid,
                                extra_groups=[], cwd="/", capture_output=True)
        except OSError:
            continue
        if ok.returncode == 0:
            break
    else:
        sys.exit("no Python interpreter the sandbox uid can run")
    # A stand-in for a zygote as the sandbox uid: one child that sleeps (killed later by
    # reap), one that has exited and is not waited for (a zombie), then the zygote dies.
    zygote = (
        "import os, time\\n"
        "if os.fork() == 0:\\n"
        "    time.sleep(600)\\n"
        "    os._exit(0)\\n"
        "if os.fork() == 0:\\n"
        "    os._exit(0)\\n"
        "time.sleep(0.3)\\n"
        "print('ready', flush=True)\\n"
        "time.sleep(600)\\n"
    )
    p = subprocess.Popen(
        [exe, "-S", "-c", zygote], user=uid, group=uid, extra_groups=[],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, cwd="/",
    )
    assert p.stdout.readline().strip() == b"ready"
    before = uidmode.processes_of(uid)
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    # the orphans go to the nearest subreaper: the grader, not an init that may never reap
    def parent(pid):
        with open(f"/proc/{pid}/stat") as f:
            return int(f.read().rsplit(")", 1)[1].split()[1])
    parents = {parent(pid) for pid in uidmode.processes_of(uid)}
    t0 = time.monotonic()
    left = uidmode.reap(uid)
    print(json.dumps({
        "uid": uid, "before": len(before), "adopted": parents == {os.getpid()}, "left": left,
        "listed": uidmode.processes_of(uid), "seconds": time.monotonic() - t0,
    }))
    lease.release()
    """
)


def test_orphans_of_a_dead_zygote_are_reaped_not_left_zombies():
    if os.geteuid() != 0:
        pytest.fail("the uid sandbox needs root (CI runs as root)", pytrace=False)
    r = subprocess.run(
        [sys.executable, "-c", SCENARIO], capture_output=True, text=True, timeout=120
    )
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["before"] == 3, out  # the zygote, its sleeper and its zombie: the check could fail
    assert out["adopted"], out
    assert out["left"] == [] and out["listed"] == [], (out, r.stderr)
