"""pytest plugin: run the harness's conformance checks on your own models from your own test suite.

Installed with the package (entry point ``pytest11``: nothing to configure; ``-p no:harness`` turns it off).

Fixtures
--------
``harness_conformance``
    ``check(system, engines=None, examples=None)``: every conformance check of ``harness check`` by the given
    engines (default: every engine of :data:`harness.engines.ENGINES`) (M, C·q̇, Christoffel C, g, springs, dampers, q̈, export round trip, self-checks) on
    hypothesis states with random parameters; fails the test with the shrunk counterexample and returns the
    :class:`harness.compare.conformance.Summary` (``summary.worst`` holds the largest error per check and engine).
    ``system`` is a :class:`harness.modeling.system.System` (your own model) or the name of a catalogued one.
``harness_system``
    ``get(name)``: a system of the catalogue (``models/`` and the folders in ``HARNESS_MODELS_PATH``).

Option ``--harness-examples N`` sets the examples (states) per check (default: the active hypothesis profile's),
rounded up to whole parameter draws (:data:`harness.compare.strategies.STATES_PER_DRAW` states each).
Example::

    from my_models import SYSTEM

    def test_my_model_agrees_with_the_engines(harness_conformance):
        harness_conformance(SYSTEM)
"""

from __future__ import annotations

import pytest


def pytest_addoption(parser):
    group = parser.getgroup("harness", "lecture harness conformance checks")
    group.addoption("--harness-examples", type=int, default=None,
                    help="hypothesis examples per conformance check (default: the hypothesis profile's)")


def assert_conformant(system, engines=None, examples: int | None = None):
    """Run every conformance check of ``system``; raise AssertionError with the counterexample on a failure."""
    from harness.compare import conformance
    from harness.settings import draws_from_seed_only

    if isinstance(system, str):
        from harness.catalogue import repository

        system = repository().get(system)
    with draws_from_seed_only():
        summary = conformance.run(system, engines=engines, examples=examples)
    if not summary.passed:
        worst = [f"{c} ({e}): {f.value:.3e} > {f.bound:.1e}" for (c, e), f in sorted(summary.worst.items())
                 if not f.passed]
        raise AssertionError(summary.failure or f"{system.name}: " + "; ".join(worst))
    return summary


@pytest.fixture
def harness_conformance(request):
    """``check(system, engines=None, examples=None)`` → Summary; fails on a disagreement."""
    default = request.config.getoption("--harness-examples")

    def check(system, engines=None, examples: int | None = None):
        return assert_conformant(system, engines, examples if examples is not None else default)

    return check


@pytest.fixture
def harness_system():
    """``get(name)``: a catalogued system (models/ and HARNESS_MODELS_PATH)."""
    from harness.catalogue import repository

    return repository().get
