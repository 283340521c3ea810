"""Running student code: a sandboxed zygote (bubblewrap) that forks one child per submission.

``child.py`` and ``launcher.py`` are standalone scripts (never imported by the grader);
``zygote.py`` is the grader's side; ``config.py`` says what a sandbox may see and use.
"""

from .config import INSTALL_HINT, Limits, SandboxConfig, SandboxUnavailable
from .zygote import Child, ChildDied, ChildTimeout, ProtocolError, Sandbox, prepare_workdir

__all__ = [
    "INSTALL_HINT",
    "Limits",
    "SandboxConfig",
    "SandboxUnavailable",
    "Child",
    "ChildDied",
    "ChildTimeout",
    "ProtocolError",
    "Sandbox",
    "prepare_workdir",
]
