"""Shared pytest setup: headless matplotlib and deterministic Hypothesis runs."""

from __future__ import annotations

import os

# Must happen before anything imports matplotlib.pyplot.
os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import HealthCheck, settings  # noqa: E402

# Property tests are derandomized (same examples on every run and machine), have no
# per-example deadline (CI machines are slow and shared) and try 200 examples each.
settings.register_profile(
    "ci",
    derandomize=True,
    deadline=None,
    max_examples=200,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
    print_blob=True,
)
# A quicker local profile is available with HYPOTHESIS_PROFILE=dev; "ci" is the default.
settings.register_profile("dev", parent=settings.get_profile("ci"), max_examples=50)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
