"""Test configuration: hypothesis runs the fixed-seed ``ci`` profile unless HYPOTHESIS_PROFILE says otherwise,
and the derivation cache lives in a per-run folder, seeded with a copy of the project's, so tests never write to a
developer's cache.

The tests that compile to machine code (numba: ``native=True``, :mod:`harness.scenes.native`) share the xdist group
``machine-code``: numba compiles a system's functions once per process (generated code, no cache on disk), and its
first compilation in a process costs ~9 s more; in one worker each is paid once."""

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
    """One cache folder per test run, shared by the xdist workers (entries are written atomically), seeded with a
    copy of the project's cache (:func:`_seed`): the tests do not derive again what the main job derived, and no
    test writes to the project's cache."""
    from harness.derivation.cache import cache_dir

    root = tmp_path_factory.getbasetemp()
    shared = root.parent if root.name.startswith("popen-gw") else root
    project = cache_dir()  # before it is moved: the project's folder, or the one HARNESS_CACHE_DIR names
    _seed(project, shared / "derivations")
    _seed(project.parent / "equations", shared / "equations")  # the report's page equations (harness.report)
    _seed(project.parent / "results", shared / "results")  # the main job's conformance summaries (remembered)
    _seed(project.parent / "states", shared / "states")  # the systems' drawn states (harness.compare.strategies)
    _seed(project.parent / "counterexamples", shared / "counterexamples")  # printed equations' (compare.claims)
    _seed(project.parent / "compiled", shared / "compiled")  # generated code (harness.derivation.lambdified)
    _seed(project.parent / "exports", shared / "exports")  # each numeric tree's MJCF (harness.export.mjcf)
    _seed(project.parent / "trajectories", shared / "trajectories")  # scene references (harness.scenes.simulate)
    _seed(project.parent / "decisions", shared / "decisions")  # printed equations' symbolic decisions (errata)
    mp = pytest.MonkeyPatch()
    mp.setenv("HARNESS_CACHE_DIR", str(shared / "derivations"))
    yield
    mp.undo()


def _seed(source, target) -> None:
    """Copy the entries of ``source`` to ``target`` (each by a rename, so that a worker reading an entry the other
    is copying sees all of it or none). An entry is keyed by a hash of what it is computed from (the model and the
    code that derives it) and checked when read (checksum, a parser that runs no code), as in every run of the
    harness; tests of the cache itself use folders of their own."""
    import os
    import shutil

    if not source.is_dir():
        return
    target.mkdir(parents=True, exist_ok=True)
    for entry in source.glob("*.json"):
        if not (target / entry.name).exists():
            part = target / f".{entry.name}.{os.getpid()}"
            shutil.copyfile(entry, part)
            os.replace(part, target / entry.name)


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
    session (per xdist worker) and shared by the tests that read it; read back where the main job computed it with
    the same code, models, packages and settings (:mod:`harness.compare.remembered`)."""
    import models
    from harness.compare import remembered

    runs: dict = {}

    def run(name: str):
        if name not in runs:
            runs[name] = remembered.run(models.CATALOGUE, models.get(name))
        return runs[name]

    return run
