"""The conformance suite: every registered system against every engine on hypothesis states with random
parameters (200 examples per check in the ``ci`` profile). A new system needs no new test code.

The engines of a system are checked in one run, as ``harness check`` does (``conformance_run`` in
``tests/conftest.py``): the same states for every engine (the seed derives from the check), each state drawn and
evaluated symbolically once. Where that run failed, the engine's test runs it again alone, so that each engine
is judged on its own."""

import pytest

import models
from harness.compare import conformance
from harness.engines import ENGINES
from harness.settings import EXAMPLES_CI

SYSTEMS = list(models.catalogue())


@pytest.mark.parametrize("engine", list(ENGINES))
@pytest.mark.parametrize("system", [pytest.param(s, marks=pytest.mark.xdist_group(f"conformance-{s}"))
                                    for s in SYSTEMS])
def test_engine_agrees_with_derivation(system, engine, conformance_run):
    reason = ENGINES[engine].applies(models.get(system))
    if reason:
        pytest.skip(f"{engine} does not apply to {system}: {reason}")
    summary = conformance_run(system)
    if summary.failure is not None:  # another engine may have stopped the shared run: this engine alone
        summary = conformance.run(models.get(system), engines=(engine,))
    assert summary.failure is None, summary.failure
    mine = {key: check for key, check in summary.worst.items() if key[1] in (engine, "symbolic")}
    assert all(check.passed for check in mine.values()), [c.record() for c in mine.values() if not c.passed]
    assert summary.examples >= EXAMPLES_CI
    assert any(source == engine for _, source in mine)
    checked = {check for check, _ in mine}
    assert {"M", "Cqd", "g", "qdd", "f_damper", "C (Christoffel)", "Mdot - 2C skew", "M positive definite"} <= checked


@pytest.mark.xdist_group("grouping-guard")
def test_tests_of_one_group_share_a_worker(request):
    """The engines of a system share one conformance run only if ``--dist loadgroup`` keeps their group on one
    worker (xdist marks the group in the node id). pytest 9.2.0 with pytest-xdist 3.8.0 dropped the groups without
    a word (pytest-xdist #1386): every system was checked twice over, once per worker. Outside xdist: nothing to
    check."""
    if getattr(request.config.option, "loadgroup", False):  # set on xdist's workers under --dist loadgroup
        assert request.node.nodeid.endswith("@grouping-guard"), request.node.nodeid
