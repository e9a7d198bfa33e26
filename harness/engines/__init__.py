"""Engine adapters and their registry.

:data:`ENGINES` maps an engine's name to its adapter class (a :class:`~harness.engines.base.TreeEngine`):
Pinocchio (from the URDF), MuJoCo (from the MJCF), Drake (from the URDF). An adapter is imported when it is first
looked up, so that naming the engines (``harness list``, the CLI's choices) loads none of them. Our compiled
symbolic model is the other source of numbers, already in lecture coordinates (:data:`SYMBOLIC`,
:mod:`harness.engines.symbolic`). :func:`evaluate` gives an :class:`~harness.engines.base.Evaluation` in lecture
coordinates from any source."""

from __future__ import annotations

from collections.abc import Mapping
from importlib import import_module

from harness.errors import InputError

SYMBOLIC = "symbolic"


class _Registry(Mapping):
    """Engine name → adapter class, each imported on first use."""

    def __init__(self, where: dict[str, str]):
        self._where = where
        self._loaded: dict = {}

    def __getitem__(self, name: str):
        if name not in self._loaded:
            module, cls = self._where[name].split(":")
            self._loaded[name] = getattr(import_module(module), cls)
        return self._loaded[name]

    def __iter__(self):
        return iter(self._where)

    def __len__(self) -> int:
        return len(self._where)


ENGINES = _Registry({"pinocchio": "harness.engines.pinocchio_engine:PinocchioModel",
                     "mujoco": "harness.engines.mujoco_engine:MujocoModel",
                     "drake": "harness.engines.drake_engine:DrakeModel"})
SOURCES = (SYMBOLIC, *ENGINES)


def engine(name: str):
    """The adapter class of engine ``name`` (an :class:`~harness.errors.InputError` naming the choices)."""
    if name not in ENGINES:
        raise InputError(f"unknown engine {name!r}; choose one of {', '.join(SOURCES)}")
    return ENGINES[name]


def evaluate(source: str, state):
    """The quantities at ``state`` (a :class:`~harness.engines.base.State`) in lecture coordinates
    (an :class:`~harness.engines.base.Evaluation`) from ``source``: our symbolic model or an engine."""
    if source == SYMBOLIC:
        from harness.engines import symbolic

        return symbolic.evaluate(state)
    return engine(source)(state.tree).evaluate(state)


def simulating(engines, phenomenon: str) -> tuple[str, ...]:
    """The engines of ``engines`` (names) that simulate ``phenomenon`` themselves
    (:attr:`~harness.engines.base.TreeEngine.natively`), in the given order."""
    return tuple(name for name in engines if engine(name).simulates(phenomenon))
