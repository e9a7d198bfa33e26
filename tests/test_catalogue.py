"""The catalogue is an object handed to the library: it pickles as its description (a worker process rebuilds
it, with the folders added to its search path), and no library module imports ``models``."""

from __future__ import annotations

import ast
import multiprocessing
import pickle
from pathlib import Path

import models
from harness.catalogue import MODELS_DIR, Catalogue, repository

HARNESS = Path(__file__).resolve().parent.parent / "harness"


def _names(catalogue: Catalogue) -> list[str]:
    return catalogue.names()


def test_a_catalogue_pickles_as_its_description():
    again = pickle.loads(pickle.dumps(models.CATALOGUE))
    assert isinstance(again, Catalogue) and again is not models.CATALOGUE
    assert again.description() == models.CATALOGUE.description()
    assert again.names() == models.names() and again.get("pendulum") is models.get("pendulum")


def test_a_worker_process_rebuilds_the_catalogue_with_its_search_path(user_models):
    (user_models / "user_pendulum.py").write_text(
        "import dataclasses\nfrom models.pendulum import SYSTEM as _S\n"
        "SYSTEM = dataclasses.replace(_S, name='user_pendulum')\n")
    models.reload()
    assert "user_pendulum" in models.names()
    with multiprocessing.get_context("spawn").Pool(1) as pool:   # a fresh interpreter: only the description
        (names,) = pool.map(_names, [models.CATALOGUE])
    assert names == models.names()


def test_the_repository_catalogue_is_the_models_folder_located_by_path():
    assert repository() is models.CATALOGUE
    assert Path(repository().path[0]).resolve() == MODELS_DIR


def test_library_code_never_imports_models():
    """Not even the entry points: they create the catalogue with :func:`harness.catalogue.repository`."""
    offenders = []
    for path in sorted(HARNESS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
            if any(n == "models" or n.startswith("models.") for n in names):
                offenders.append(f"{path.relative_to(HARNESS.parent)}:{node.lineno}")
    assert not offenders, offenders


def test_the_lecture_systems_with_printed_equations_are_those_of_the_models_folder(user_models):
    """Which numbered equations of the lecture have no claim is decided by the systems of ``models/`` that list
    printed equations (the errata sheet's last section), not by a user's own models beside them."""
    (user_models / "user_pendulum.py").write_text(
        "import dataclasses\nfrom models.pendulum import SYSTEM as _S, CLAIMS\n"
        "SYSTEM = dataclasses.replace(_S, name='user_pendulum')\n")
    models.reload()
    lecture = models.CATALOGUE.lecture_claims()
    assert "user_pendulum" in models.names() and "user_pendulum" not in lecture
    assert lecture == {name for name in models.names() if name != "user_pendulum" and models.CATALOGUE.claims(name)}
    assert "pendulum" in lecture and "lightweight_robot" not in lecture   # the robot lists no printed equation


def test_looking_up_one_system_loads_its_module_alone(user_models):
    """A system's module is named after it, so ``harness check NAME`` imports that module and no other; listing
    the catalogue imports every module; a module whose system has another name is that module's failure."""
    (user_models / "user_one.py").write_text(
        "import dataclasses\nfrom models.pendulum import SYSTEM as _S\n"
        "SYSTEM = dataclasses.replace(_S, name='user_one')\n")
    (user_models / "user_two.py").write_text(
        "from pathlib import Path\n(Path(__file__).parent / 'user_two loaded').touch()\n"
        "import dataclasses\nfrom models.pendulum import SYSTEM as _S\n"
        "SYSTEM = dataclasses.replace(_S, name='user_three')\n")
    catalogue = Catalogue(models)
    assert catalogue.get("user_one").name == "user_one" and "user_one" in catalogue
    assert catalogue.scenes("user_one") == [] and not catalogue.from_lecture("user_one")
    assert not (user_models / "user_two loaded").exists()
    assert catalogue.order()["user_two"] > catalogue.order()["user_one"] > catalogue.order()["pendulum"]
    assert not (user_models / "user_two loaded").exists()
    assert "user_two" in catalogue.names() and (user_models / "user_two loaded").exists()
    assert "user_three" not in catalogue and "user_two" not in catalogue.systems()
    assert catalogue.failures()["user_two"].endswith(
        "user_two.py: its SYSTEM is named 'user_three'; a system's module is named after it: "
        "rename the file to user_three.py or the system to 'user_two'")
