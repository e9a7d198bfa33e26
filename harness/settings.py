"""Hypothesis settings, one place for tests, ``harness check`` and ``harness claims``.

Profiles:

* ``ci`` (default): 200 examples per check, derandomized (fixed seed), so a red run can be replayed.
* ``long``: 2000 random examples, run on demand: ``HYPOTHESIS_PROFILE=long``.

:func:`property_test` builds every property test of the oracles (conformance, claims) with the same overrides;
:func:`apply_seed` makes every check of a run draw from one seed (``--seed``).
"""

from __future__ import annotations

import os
from contextlib import contextmanager

from hypothesis import HealthCheck, settings

EXAMPLES_CI = 200

OVERRIDES = {"suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large], "deadline": None}
"""What every property test of the oracles overrides in the active profile: a check may be slow (an engine
evaluation, a compiled model) and draw large states; it has no deadline. The profiles set the same."""

settings.register_profile("ci", max_examples=EXAMPLES_CI, derandomize=True, print_blob=True, **OVERRIDES)
settings.register_profile("long", max_examples=2000, derandomize=False, print_blob=True, **OVERRIDES)


def load_hypothesis_profile() -> str:
    name = os.environ.get("HYPOTHESIS_PROFILE", "ci")
    settings.load_profile(name)
    return name


def apply_seed(seed: int | None) -> None:
    """Load the hypothesis profile; with ``seed``, every check draws from ``Random(seed)`` (no example
    database, so that saved failures cannot change the run). Without, the process's own forced seed (None, or
    hypothesis's pytest option ``--hypothesis-seed``) again: a process that runs several jobs (a kept worker, a Dask
    worker, the test suite) drew every later job's states from an earlier job's ``--seed``."""
    import hypothesis.core

    if not _OWN_FORCED_SEED:
        _OWN_FORCED_SEED.append(hypothesis.core.global_force_seed)
    name = load_hypothesis_profile()
    if seed is not None:
        settings.register_profile("seeded", parent=settings.get_profile(name), derandomize=False, database=None)
        settings.load_profile("seeded")
    hypothesis.core.global_force_seed = seed if seed is not None else _OWN_FORCED_SEED[0]


_OWN_FORCED_SEED: list = []
"""The process's forced seed before :func:`apply_seed` first set one."""


@contextmanager
def seeded(seed: int | None):
    """:func:`apply_seed` for the block, and the process's own seed and profile after it: a job's ``--seed`` does
    not reach what the process does next (found when a ``--seed`` check left its seed to the next test of its worker,
    whose key of a kept summary then was not the one ``harness check`` had written)."""
    apply_seed(seed)
    try:
        yield
    finally:
        apply_seed(None)


def property_test(strategy, check, examples: int | None = None, shrink: bool = True, seed: int | None = None):
    """``check(example)`` as a hypothesis test over ``strategy`` with :data:`OVERRIDES` (``examples``: the
    number of examples instead of the profile's). Calling the result runs it; a failing check is shrunk (unless
    ``shrink`` is false: a yes/no question needs no minimal example) and its exception raised. The examples are
    drawn from ``seed`` when given, else (a derandomized profile) from a seed derived from ``check``'s source."""
    from hypothesis import Phase, given
    from hypothesis import seed as seeded

    overrides = dict(OVERRIDES)
    if examples is not None:
        overrides["max_examples"] = examples
    # no explain phase: after shrinking it runs the check again on variations of the minimal example only to
    # comment on which parts of it matter; the harness reports the minimal example itself (and its own reduction)
    overrides["phases"] = [Phase.explicit, Phase.reuse, Phase.generate] + ([Phase.shrink] if shrink else [])
    test = settings(**overrides)(given(strategy)(check))
    return test if seed is None else seeded(seed)(test)


@contextmanager
def draws_from_seed_only():
    """Examples that depend on the seed only, not on which of our modules happen to be imported.

    Hypothesis (6.1xx) draws, with a small probability, literal constants mined from the source of the *local*
    modules loaded at draw time. The same seed then gives different examples after a scene run imported
    ``harness.scenes.trajectories``, or after any literal was edited anywhere in ``harness/`` or ``models/``: a
    ``results.json`` would not be reproducible. Inside this context only hypothesis's own constants are used
    (it patches one private hook of the pinned hypothesis version and restores it on exit)."""
    from hypothesis.internal.conjecture import providers

    global _SEED_ONLY
    real = providers._get_local_constants
    empty = type(providers._local_constants)(integers=providers.SortedSet(),
                                              floats=providers.SortedSet(key=providers.float_to_int),
                                              bytes=providers.SortedSet(), strings=providers.SortedSet())
    providers._get_local_constants = lambda: empty
    providers.CONSTANTS_CACHE.cache.clear()
    _SEED_ONLY += 1
    try:
        yield
    finally:
        _SEED_ONLY -= 1
        providers._get_local_constants = real
        providers.CONSTANTS_CACHE.cache.clear()


_SEED_ONLY = 0


def seed_only() -> bool:
    """Whether the examples drawn now depend on the seed only (inside :func:`draws_from_seed_only`)."""
    return _SEED_ONLY > 0


def fixed_examples() -> tuple | None:
    """What, besides the test itself, decides the examples hypothesis draws now: ``(forced seed, max_examples,
    derandomize, phases)``; None when the settings do not fix them (a random seed per run, an example database,
    or constants mined from our modules' source: outside :func:`draws_from_seed_only`). The key of anything kept
    from one run for the next (the claims' replayed states, the remembered conformance summaries)."""
    import hypothesis.core
    from hypothesis import settings

    current, force = settings.default, hypothesis.core.global_force_seed
    if not seed_only() or not (current.derandomize or force is not None) or current.database is not None:
        return None
    return force, current.max_examples, current.derandomize, tuple(current.phases)
