"""The conformance suite: every registered system against every engine on hypothesis states with random
parameters (200 examples per check in the ``ci`` profile). A new system needs no new test code.

The engines of a system are checked in one run, as ``harness check`` does (``conformance_run`` in
``tests/conftest.py``): the same states for every engine (the seed derives from the check), each state drawn and
evaluated symbolically once. Where that run failed, the engine's test runs it again alone, so that each engine
is judged on its own."""

import pytest

import models
from harness.compare import conformance
from harness.compare.strategies import STATES_PER_DRAW
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


def test_a_remembered_summary_is_the_one_computed(tmp_path, monkeypatch):
    """The test suite reads the summary the main job computed (:mod:`harness.compare.remembered`): read back, it is
    the computed one check for check; a damaged entry is computed again; another numeric environment (BLAS
    kernels) or other settings is another key."""
    from hypothesis import settings

    from harness.compare import remembered
    from harness.settings import load_hypothesis_profile

    monkeypatch.setenv("HARNESS_CACHE_DIR", str(tmp_path / "derivations"))
    system = models.get("pendulum")
    computed = remembered.run(models.CATALOGUE, system, read=False)
    entry = remembered.key(models.CATALOGUE, "pendulum", None)
    stored = remembered.folder() / f"{entry}.json"
    assert stored.is_file()
    read = remembered.run(models.CATALOGUE, system)
    assert read is not computed
    assert (read.system, read.examples, read.parameter_draws, read.failure, read.not_applicable) == \
        (computed.system, computed.examples, computed.parameter_draws, computed.failure, computed.not_applicable)
    assert 1 < computed.parameter_draws <= computed.examples // STATES_PER_DRAW
    assert {k: c.record() for k, c in read.worst.items()} == {k: c.record() for k, c in computed.worst.items()}

    stored.write_text(stored.read_text().replace('"examples": 200', '"examples": 2000'))
    assert remembered._load(stored) is None  # the checksum no longer matches: computed again

    monkeypatch.setenv("OPENBLAS_CORETYPE", "Prescott")
    assert remembered.key(models.CATALOGUE, "pendulum", None) != entry
    monkeypatch.delenv("OPENBLAS_CORETYPE")
    assert remembered.key(models.CATALOGUE, "pendulum", 10) != entry
    settings.register_profile("random draws", settings.get_profile("ci"), derandomize=False, database=None)
    settings.load_profile("random draws")
    try:
        assert remembered.key(models.CATALOGUE, "pendulum", None) is None  # examples not fixed: nothing kept
    finally:
        load_hypothesis_profile()


def test_the_main_job_stores_what_the_tests_read(tmp_path):
    """``harness check`` (a worker process of its own, started from the command line) stores a summary under the
    key the test suite looks for: a key that depended on the process (the working directory on ``sys.path`` found
    the project's metadata twice) made the tests compute everything again without a word."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    from harness.compare import remembered

    harness_cli = Path(sys.executable).with_name("harness")
    env = {**os.environ, "HARNESS_CACHE_DIR": str(tmp_path / "derivations")}
    subprocess.run([str(harness_cli), "check", "pendulum", "--jobs", "2", "--no-scenes", "--out", str(tmp_path / "out")],
                   check=True, capture_output=True, env=env, cwd=tmp_path)
    entry = remembered.key(models.CATALOGUE, "pendulum", None)
    assert (tmp_path / "results" / f"{entry}.json").is_file(), sorted(p.name for p in (tmp_path / "results").iterdir())
