"""Hypothesis profiles, one place for tests and ``harness check``.

* ``ci`` (default): 200 examples per check, derandomized (fixed seed), so a red run can be replayed.
* ``long``: 2000 random examples, run on demand: ``HYPOTHESIS_PROFILE=long``.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

EXAMPLES_CI = 200

settings.register_profile("ci", max_examples=EXAMPLES_CI, derandomize=True, deadline=None, print_blob=True,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
settings.register_profile("long", max_examples=2000, derandomize=False, deadline=None, print_blob=True,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def load_hypothesis_profile() -> str:
    name = os.environ.get("HYPOTHESIS_PROFILE", "ci")
    settings.load_profile(name)
    return name
