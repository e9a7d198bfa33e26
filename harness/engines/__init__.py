"""Engine adapters: our compiled symbolic model, Pinocchio (from the URDF), MuJoCo (from the MJCF).
Each returns an :class:`~harness.engines.base.Evaluation` in lecture coordinates."""

from __future__ import annotations

from harness.engines import mujoco_engine, pinocchio_engine, symbolic
from harness.engines.base import Evaluation, State
from harness.errors import InputError

ENGINES = ("symbolic", "pinocchio", "mujoco")


def evaluate(engine: str, state: State) -> Evaluation:
    if engine == "symbolic":
        return symbolic.evaluate(state)
    if engine == "pinocchio":
        return pinocchio_engine.evaluate(state)
    if engine == "mujoco":
        return mujoco_engine.evaluate(state)
    raise InputError(f"unknown engine {engine!r}; choose one of {', '.join(ENGINES)}")
