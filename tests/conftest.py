"""Test configuration: hypothesis runs the fixed-seed ``ci`` profile unless HYPOTHESIS_PROFILE says otherwise,
and the derivation cache lives in a per-run folder so tests never depend on a developer's cache."""

import pytest

from harness.settings import load_hypothesis_profile

load_hypothesis_profile()


@pytest.fixture(scope="session", autouse=True)
def _seed_only_examples():
    """The ``ci`` examples depend on the seed only, not on which modules an xdist worker imported first
    (see :func:`harness.settings.draws_from_seed_only`), so a red run replays."""
    from harness.settings import draws_from_seed_only

    with draws_from_seed_only():
        yield


@pytest.fixture(scope="session", autouse=True)
def _isolated_cache(tmp_path_factory):
    # one folder per test run, shared by the xdist workers (entries are written atomically)
    root = tmp_path_factory.getbasetemp()
    shared = root.parent if root.name.startswith("popen-gw") else root
    mp = pytest.MonkeyPatch()
    mp.setenv("HARNESS_CACHE_DIR", str(shared / "derivations"))
    yield
    mp.undo()
