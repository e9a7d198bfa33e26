"""Test configuration: hypothesis runs the fixed-seed ``ci`` profile unless HYPOTHESIS_PROFILE says otherwise,
and the derivation cache lives in a per-session folder so tests never depend on a developer's cache."""

import pytest

from harness.settings import load_hypothesis_profile

load_hypothesis_profile()


@pytest.fixture(scope="session", autouse=True)
def _isolated_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv("HARNESS_CACHE_DIR", str(tmp_path_factory.mktemp("derivations")))
    yield
    mp.undo()
