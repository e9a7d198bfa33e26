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


@pytest.fixture
def user_models(tmp_path, monkeypatch):
    """A temporary folder on the catalogue's search path, as HARNESS_MODELS_PATH would put it; the modules
    loaded from it are forgotten afterwards."""
    import sys

    import models

    folder = tmp_path / "user_models"
    folder.mkdir()
    monkeypatch.setattr(models, "__path__", [*models.__path__, str(folder)])
    models.reload()
    yield folder
    models.reload()
    for name, module in list(sys.modules.items()):
        if name.startswith("models.") and str(getattr(module, "__file__", "") or "").startswith(str(folder)):
            sys.modules.pop(name)


@pytest.fixture(scope="session")
def conformance_run():
    """``conformance_run(name)``: the conformance summary of catalogued system ``name`` against every engine that
    applies (:func:`harness.compare.conformance.run`, what ``harness check`` computes), run once per test
    session (per xdist worker) and shared by the tests that read it."""
    import models
    from harness.compare import conformance

    runs: dict = {}

    def run(name: str):
        if name not in runs:
            runs[name] = conformance.run(models.get(name))
        return runs[name]

    return run
