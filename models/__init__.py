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
def catalogue() -> dict[str, System]:
    """Every registered system by name, in module order."""
    systems = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        system = getattr(module, "SYSTEM", None)
        if isinstance(system, System):
            systems[system.name] = system
    return systems


def get(name: str) -> System:
    systems = catalogue()
    if name not in systems:
        raise InputError(f"unknown system {name!r}; known systems: {', '.join(systems)}")
    return systems[name]
