"""The conformance suite: every registered system against every engine on hypothesis states with random
parameters (200 examples per check in the ``ci`` profile). A new system needs no new test code."""

import pytest

import models
from harness.compare import conformance
from harness.engines import ENGINES
from harness.settings import EXAMPLES_CI

SYSTEMS = list(models.catalogue())


@pytest.mark.parametrize("engine", list(ENGINES))
@pytest.mark.parametrize("system", SYSTEMS)
def test_engine_agrees_with_derivation(system, engine):
    reason = ENGINES[engine].applies(models.get(system))
    if reason:
        pytest.skip(f"{engine} does not apply to {system}: {reason}")
    summary = conformance.run(models.get(system), engines=(engine,))
    assert summary.failure is None, summary.failure
    assert summary.passed
    assert summary.examples >= EXAMPLES_CI
    checked = {check for check, _ in summary.worst}
    assert {"M", "Cqd", "g", "qdd", "f_damper", "C (Christoffel)", "Mdot - 2C skew", "M positive definite"} <= checked
