"""The catalogue of lecture systems: one module per system, each defining ``SYSTEM``.

A new system is one new module here; the registry, export, conformance tests and reports pick it up.
"""

from __future__ import annotations

import importlib
import pkgutil
from functools import cache

from harness.errors import InputError
from harness.model import System


@cache
def _modules() -> dict:
    modules = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
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
