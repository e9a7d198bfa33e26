"""The catalogue of systems: the model modules of one package (``models``) and the folders on its search path.

A :class:`Catalogue` is an object handed to whatever needs systems (the application layer :mod:`harness.run`,
the hard cases, the benchmarks, the report); library code never imports ``models``. ``models/__init__.py``
creates the catalogue of the repository (with the folders of ``HARNESS_MODELS_PATH``) and delegates its module
functions to it.

Search path: the package's own folder first, then the folders added to its ``__path__`` (a user's own models,
a throwaway system in a test); a module there cannot shadow a module of the package's own folder.

A system's module is named after it (``models/pendulum.py`` defines the system ``pendulum``), as in
robot_descriptions: looking up one system (:meth:`Catalogue.get`, ``harness check pendulum``) loads that module
alone; listing the catalogue loads every module.

A module that does not load — it raises, has a syntax error, calls ``sys.exit``, defines an invalid model, a
printed equation (claim) with a symbol the system does not declare, a scene whose initial state, inputs or
parameter values do not fit the system, or a system not named after its module — is that module's failure,
one line naming its file: :meth:`Catalogue.failures` lists them, :meth:`Catalogue.names` includes them (so that a
run over the catalogue reports them), :meth:`Catalogue.get` raises it for that name only; every other system still
loads.

A catalogue pickles as its description (package name and search path): a worker process (``--jobs``, the
benchmark's process pool or Dask workers) rebuilds it from that and loads the modules itself.

The repository's own catalogue (:func:`repository`) is the one place that locates the ``models`` folder: by its
path next to ``harness/``, never by an ``import models`` in library code.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import pkgutil
import sys
from pathlib import Path
from types import ModuleType

from harness.errors import HarnessError, InputError, ModelError
from harness.io import existing_folder
from harness.modeling.system import System

MODELS_PATH_VARIABLE = "HARNESS_MODELS_PATH"
MODELS_DIR = Path(__file__).resolve().parent.parent / "models"
"""The repository's catalogue folder, a package named ``models`` beside ``harness/``."""


def search_path(environ=None) -> list[str]:
    """The folders ``HARNESS_MODELS_PATH`` names (separated by ``os.pathsep``), absolute."""
    value = (os.environ if environ is None else environ).get(MODELS_PATH_VARIABLE, "")
    return [os.path.abspath(p) for p in value.split(os.pathsep) if p]


def check_search_path(environ=None, creating=None) -> None:
    """Raise :class:`InputError` where ``HARNESS_MODELS_PATH`` names something that is not a folder, or holds a module
    whose name a folder searched before it (``models/`` first) already has: its systems would be missing from every
    listing without a word (the entry points call this; importing ``models`` does not fail on it). ``creating``: a
    folder ``harness new --dir`` is about to create, which may be on the path before it exists."""
    taken = {info.name: _path(info) for info in pkgutil.iter_modules([str(MODELS_DIR)])}
    for folder in search_path(environ):
        if creating is not None and folder == os.path.abspath(creating) and not os.path.exists(folder):
            continue
        existing_folder(folder, MODELS_PATH_VARIABLE)
        for info in sorted(pkgutil.iter_modules([folder]), key=lambda m: m.name):
            if info.name.startswith("_"):
                continue
            if info.name in taken:   # Python imports the module found first: this one would be skipped unsaid
                raise InputError(f"{MODELS_PATH_VARIABLE}: {_path(info)} has the module name of {taken[info.name]}, "
                                 "which is searched first and loaded instead; rename the file (and its SYSTEM)")
            taken[info.name] = _path(info)


def _path(info: pkgutil.ModuleInfo) -> str:
    path = os.path.abspath(os.path.join(getattr(info.module_finder, "path", ""), f"{info.name}.py"))
    return os.path.relpath(path) if not os.path.relpath(path).startswith("..") else path


class Catalogue:
    """The systems of the model modules of ``package`` (a package module or its name), loaded on first use.

    ``package.__path__`` is read at each (re)load: a folder added to it is searched after :meth:`reload`."""

    def __init__(self, package: ModuleType | str = "models"):
        self.package = package if isinstance(package, str) else package.__name__
        self._loaded: tuple[dict, dict] | None = None
        self._tried: dict[str, ModuleType | ModelError | None] = {}  # module name -> its system's module, or why not

    # ------------------------------------------------------------------------------------------ description
    @property
    def path(self) -> list[str]:
        """The search path: the package's own folder first, then the added folders."""
        return list(importlib.import_module(self.package).__path__)

    def description(self) -> tuple[str, tuple[str, ...]]:
        """What a worker process rebuilds this catalogue from: ``(package, search path)``."""
        return self.package, tuple(self.path)

    def __reduce__(self):
        return rebuild, self.description()

    def __repr__(self) -> str:
        return f"Catalogue({self.package!r})"

    # ------------------------------------------------------------------------------------------ loading
    def _load(self, info: pkgutil.ModuleInfo) -> ModuleType | None:
        """Import ``<package>.<name>`` and check its system's name, claims and scenes: the module of a system, None for
        a module that defines none (a helper); a module that does not load raises one error naming its file."""
        if info.name in self._tried:
            if isinstance(self._tried[info.name], ModelError):
                raise self._tried[info.name]
            return self._tried[info.name]
        try:
            module = self._tried[info.name] = self._import(info, _path(info))
        except ModelError as exc:
            self._tried[info.name] = exc
            raise
        return module

    def _import(self, info: pkgutil.ModuleInfo, path: str) -> ModuleType | None:
        name = f"{self.package}.{info.name}"
        try:
            module = importlib.import_module(name)
        except HarnessError as exc:
            raise ModelError(f"{path}: {exc}") from None
        except (Exception, SystemExit) as exc:  # noqa: BLE001 - a broken model file is bad input, not a crash
            sys.modules.pop(name, None)
            where = f" (line {exc.lineno})" if isinstance(exc, SyntaxError) else ""
            what = f"calls sys.exit({exc.code!r})" if isinstance(exc, SystemExit) else f"{type(exc).__name__}: {exc}"
            raise ModelError(f"{path} does not load{where}: {what}") from None
        system = getattr(module, "SYSTEM", None)
        if not isinstance(system, System):
            return None
        if system.name != info.name:  # a lookup by name loads the module of that name alone
            raise ModelError(f"{path}: its SYSTEM is named {system.name!r}; a system's module is named after it: "
                             f"rename the file to {system.name}.py or the system to {info.name!r}")
        from harness.modeling.claims import validate_claims
        from harness.modeling.scenes import validate_scenes

        try:
            validate_claims(system, getattr(module, "CLAIMS", []))
            validate_scenes(system, getattr(module, "SCENES", []))
        except HarnessError as exc:
            raise ModelError(f"{path}: {exc}") from None
        return module

    def _infos(self) -> list[pkgutil.ModuleInfo]:
        """The model modules on the search path, in catalogue order: the package's own folder first (a user module
        cannot take a catalogued name), then the added folders; each sorted by name."""
        own, *others = self.path
        infos = sorted(pkgutil.iter_modules([own]), key=lambda m: m.name)
        seen = {info.name for info in infos}
        infos += [info for info in sorted(pkgutil.iter_modules(others), key=lambda m: m.name) if info.name not in seen]
        return [info for info in infos if not info.name.startswith("_")]

    def _load_all(self) -> tuple[dict, dict]:
        """``(modules by system name, failures by module name)``, in module order."""
        if self._loaded is not None:
            return self._loaded
        modules, failures = {}, {}
        for info in self._infos():
            try:
                module = self._load(info)
            except ModelError as exc:
                failures[info.name] = str(exc)
                continue
            if module is not None:
                modules[info.name] = module
        self._loaded = modules, failures
        return self._loaded

    def _module(self, name: str) -> ModuleType:
        """The module of system ``name``, loading that module alone (its file is named after the system); a module
        that does not load raises its failure, an unknown name an InputError naming every system."""
        if self._loaded is None:
            info = next((info for info in self._infos() if info.name == name), None)
            module = None if info is None else self._load(info)
            if module is not None:
                return module
        modules, failures = self._load_all()
        if name in modules:
            return modules[name]
        if name in failures:
            raise ModelError(failures[name])
        raise InputError(f"unknown system {name!r}; known systems: {', '.join(self.names())}")

    def reload(self) -> None:
        """Forget what was loaded: the next lookup searches the path again (a folder added, a module written)."""
        self._loaded = None
        self._tried.clear()

    # ------------------------------------------------------------------------------------------ lookups
    def systems(self) -> dict[str, System]:
        """Every system that loads, by name, in module order."""
        return {name: module.SYSTEM for name, module in self._load_all()[0].items()}

    def failures(self) -> dict[str, str]:
        """Modules that do not load: module name → the one-line reason (naming the file)."""
        return dict(self._load_all()[1])

    def names(self) -> list[str]:
        """Every system of the catalogue and every module that does not load (a run over the catalogue reports
        those as failures)."""
        systems = self.systems()
        return [*systems, *(name for name in self.failures() if name not in systems)]

    def order(self) -> dict[str, int]:
        """Position of each system's (and failing module's) name in module order (records are sorted by it; other
        names after); no module is loaded for it."""
        return {info.name: k for k, info in enumerate(self._infos())}

    def get(self, name: str) -> System:
        """The system ``name``; a module that does not load raises its failure, an unknown name an InputError."""
        return self._module(name).SYSTEM

    def require(self, names) -> None:
        """Unknown or broken names given by a user fail before any work (one line)."""
        for name in names or ():
            self.get(name)

    def scenes(self, name: str) -> list:
        """The scenes of system ``name`` (the module's ``SCENES``)."""
        return list(getattr(self._module(name), "SCENES", []))

    def claims(self, name: str) -> list:
        """The lecture's printed equations for system ``name`` (the module's ``CLAIMS``)."""
        return list(getattr(self._module(name), "CLAIMS", []))

    def from_lecture(self, name: str) -> bool:
        """Whether system ``name`` is the lecture's: its module is in the package's own folder, not in an added
        one (one's own model, a paper's system, names its source in ``System.lecture``)."""
        return Path(self._module(name).__file__).resolve().parent == Path(self.path[0]).resolve()

    def lecture_claims(self) -> set[str]:
        """The systems of the lecture's catalogue (:meth:`from_lecture`) that list printed equations: the systems
        whose claims decide which numbered equations have none."""
        return {name for name, module in self._load_all()[0].items()
                if self.from_lecture(name) and getattr(module, "CLAIMS", None)}

    def module(self, name: str) -> ModuleType:
        """The model module of system ``name`` (for what a model states beyond SYSTEM, CLAIMS, SCENES: e.g. the
        lightweight robot's URDF file)."""
        return self._module(name)

    def added_folder(self, name: str) -> str | None:
        """The folder added to the search path (``HARNESS_MODELS_PATH``) that holds system ``name``'s module; None for
        a module of the package's own folder."""
        folder = os.path.dirname(os.path.realpath(self.module(name).__file__))
        return None if folder == os.path.realpath(self.path[0]) else folder

    def __contains__(self, name) -> bool:
        try:
            self._module(name)
        except HarnessError:
            return False
        return True


def _package(name: str, folder: str | Path | None = None) -> ModuleType:
    """The package ``name``: already imported, else from ``folder`` (its ``__init__.py``, located by path) when
    given, else imported by name."""
    if name in sys.modules:
        return sys.modules[name]
    init = Path(folder) / "__init__.py" if folder is not None else None
    if init is None or not init.is_file():
        return importlib.import_module(name)
    spec = importlib.util.spec_from_file_location(name, init, submodule_search_locations=[str(Path(folder))])
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


def repository() -> Catalogue:
    """The catalogue of the repository: the package ``models`` in :data:`MODELS_DIR` (located by path) with the
    folders of ``HARNESS_MODELS_PATH`` on its search path. The entry points (the command line, the pytest
    plugin) create it; the library is handed it."""
    module = _package("models", MODELS_DIR)
    catalogue = getattr(module, "CATALOGUE", None)
    return catalogue if isinstance(catalogue, Catalogue) else Catalogue(module)


def rebuild(package: str, path: tuple[str, ...] = ()) -> Catalogue:
    """The catalogue of ``package`` with the folders of ``path`` on its search path (in a worker process: the
    package is loaded from its own folder ``path[0]``, the same the parent process used, and the folders it lacks
    are added). Loading again is cheap: the modules stay imported."""
    module = _package(package, path[0] if path else None)
    module.__path__.extend(p for p in path if p not in module.__path__)
    return Catalogue(package)
