"""The catalogue of lecture systems: one module per system, each defining ``SYSTEM``.

A new system is one new module here; the registry, export, conformance tests and reports pick it up.
``HARNESS_MODELS_PATH`` (folders separated by ``os.pathsep``) adds folders searched after this one, so that a
system can live outside the repository (a user's own models, a throwaway system in a test); a module there
cannot shadow a module here.

A module that does not load — it raises, has a syntax error, calls ``sys.exit``, defines an invalid model, a
printed equation (claim) with a symbol the system does not declare, or a system name another module already
uses — is that module's failure, one line naming its file: :func:`failures` lists them, :func:`names` includes
them (so that a run over the catalogue reports them), :func:`get` raises it for that name only; every other
system still loads.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import sys
from functools import cache

from harness.errors import HarnessError, InputError, ModelError
from harness.modeling.system import System

MODELS_PATH_VARIABLE = "HARNESS_MODELS_PATH"
__path__.extend(os.path.abspath(p) for p in os.environ.get(MODELS_PATH_VARIABLE, "").split(os.pathsep) if p)


def _path(info: pkgutil.ModuleInfo) -> str:
    path = os.path.abspath(os.path.join(getattr(info.module_finder, "path", ""), f"{info.name}.py"))
    return os.path.relpath(path) if not os.path.relpath(path).startswith("..") else path


def _load(info: pkgutil.ModuleInfo, path: str):
    """Import ``models.<name>`` and check its claims; a module that does not load is one error naming its file."""
    try:
        module = importlib.import_module(f"{__name__}.{info.name}")
    except HarnessError as exc:
        raise ModelError(f"{path}: {exc}") from None
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - a broken model file is bad input, not a crash
        sys.modules.pop(f"{__name__}.{info.name}", None)
        where = f" (line {exc.lineno})" if isinstance(exc, SyntaxError) else ""
        what = f"calls sys.exit({exc.code!r})" if isinstance(exc, SystemExit) else f"{type(exc).__name__}: {exc}"
        raise ModelError(f"{path} does not load{where}: {what}") from None
    system = getattr(module, "SYSTEM", None)
    if isinstance(system, System):
        from harness.modeling.claims import validate_claims

        try:
            validate_claims(system, getattr(module, "CLAIMS", []))
        except HarnessError as exc:
            raise ModelError(f"{path}: {exc}") from None
    return module


@cache
def _load_all() -> tuple[dict, dict]:
    """``(modules by system name, failures by module name)``, in module order."""
    modules, failures, where = {}, {}, {}
    own, *others = __path__  # the catalogue's own folder first: a user module cannot take a catalogued name
    infos = sorted(pkgutil.iter_modules([own]), key=lambda m: m.name)
    seen = {info.name for info in infos}
    infos += [info for info in sorted(pkgutil.iter_modules(others), key=lambda m: m.name) if info.name not in seen]
    for info in infos:
        if info.name.startswith("_"):
            continue
        path = _path(info)
        try:
            module = _load(info, path)
        except ModelError as exc:
            failures[info.name] = str(exc)
            continue
        system = getattr(module, "SYSTEM", None)
        if not isinstance(system, System):
            continue
        if system.name in modules or system.name in failures:
            failures[info.name] = (f"{path}: system name {system.name!r} is already used by "
                                   f"{where.get(system.name, system.name)}; give SYSTEM a name of its own")
            continue
        modules[system.name], where[system.name] = module, path
    return modules, failures


def _modules() -> dict:
    return _load_all()[0]


def reload() -> None:
    """Forget what was loaded: the next lookup searches ``__path__`` again (a folder added, a module written)."""
    _load_all.cache_clear()


def failures() -> dict[str, str]:
    """Modules that do not load: module name → the one-line reason (naming the file)."""
    return dict(_load_all()[1])


def catalogue() -> dict[str, System]:
    """Every system that loads, by name, in module order."""
    return {name: module.SYSTEM for name, module in _modules().items()}


def names() -> list[str]:
    """Every system of the catalogue and every module that does not load (a run over the catalogue reports
    those as failures)."""
    return [*catalogue(), *(name for name in failures() if name not in catalogue())]


def scenes(name: str) -> list:
    """The scenes of system ``name`` (the module's ``SCENES``)."""
    get(name)
    return list(getattr(_modules()[name], "SCENES", []))


def claims(name: str) -> list:
    """The lecture's printed equations for system ``name`` (the module's ``CLAIMS``)."""
    get(name)
    return list(getattr(_modules()[name], "CLAIMS", []))


def get(name: str) -> System:
    systems = catalogue()
    if name in systems:
        return systems[name]
    broken = failures()
    if name in broken:
        raise ModelError(broken[name])
    known = ", ".join(names())
    raise InputError(f"unknown system {name!r}; known systems: {known}")
