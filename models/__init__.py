"""The catalogue of lecture systems: one module per system, each defining ``SYSTEM``.

A new system is one new module here; the registry, export, conformance tests and reports pick it up.
``HARNESS_MODELS_PATH`` (folders separated by ``os.pathsep``) adds folders searched after this one, so that a
system can live outside the repository (a user's own models, a throwaway system in a test); a module there
cannot shadow a module here.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
from functools import cache

from harness.errors import HarnessError, InputError, ModelError
from harness.model import System

MODELS_PATH_VARIABLE = "HARNESS_MODELS_PATH"
__path__.extend(os.path.abspath(p) for p in os.environ.get(MODELS_PATH_VARIABLE, "").split(os.pathsep) if p)


def _load(info: pkgutil.ModuleInfo):
    """Import ``models.<name>``; a module that does not load is one error naming its file."""
    path = os.path.abspath(os.path.join(getattr(info.module_finder, "path", ""), f"{info.name}.py"))
    path = os.path.relpath(path) if not os.path.relpath(path).startswith("..") else path
    try:
        return importlib.import_module(f"{__name__}.{info.name}")
    except HarnessError as exc:
        raise ModelError(f"{path}: {exc}") from None
    except Exception as exc:  # noqa: BLE001 - a broken model file is bad input, not a crash
        where = f" (line {exc.lineno})" if isinstance(exc, SyntaxError) else ""
        raise ModelError(f"{path} does not load{where}: {type(exc).__name__}: {exc}") from None


@cache
def _modules() -> dict:
    modules = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = _load(info)
        system = getattr(module, "SYSTEM", None)
        if isinstance(system, System):
            modules[system.name] = module
    return modules


def catalogue() -> dict[str, System]:
    """Every registered system by name, in module order."""
    return {name: module.SYSTEM for name, module in _modules().items()}


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
    if name not in systems:
        raise InputError(f"unknown system {name!r}; known systems: {', '.join(systems)}")
    return systems[name]
