"""Hypothesis profiles, one place for tests and ``harness check``.

* ``ci`` (default): 200 examples per check, derandomized (fixed seed), so a red run can be replayed.
* ``long``: 2000 random examples, run on demand: ``HYPOTHESIS_PROFILE=long``.
"""

from __future__ import annotations

import os
from contextlib import contextmanager

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


@contextmanager
def draws_from_seed_only():
    """Examples that depend on the seed only, not on which of our modules happen to be imported.

    Hypothesis (6.1xx) draws, with a small probability, literal constants mined from the source of the *local*
    modules loaded at draw time. The same seed then gives different examples after a scene run imported
    ``harness.scenes.trajectories``, or after any literal was edited anywhere in ``harness/`` or ``models/``: a
    ``results.json`` would not be reproducible. Inside this context only hypothesis's own constants are used
    (it patches one private hook of the pinned hypothesis version and restores it on exit)."""
    from hypothesis.internal.conjecture import providers

    real = providers._get_local_constants
    empty = type(providers._local_constants)(integers=providers.SortedSet(),
                                              floats=providers.SortedSet(key=providers.float_to_int),
                                              bytes=providers.SortedSet(), strings=providers.SortedSet())
    providers._get_local_constants = lambda: empty
    providers.CONSTANTS_CACHE.cache.clear()
    try:
        yield
    finally:
        providers._get_local_constants = real
        providers.CONSTANTS_CACHE.cache.clear()
