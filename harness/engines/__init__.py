"""Engine adapters and their registry.

:data:`ENGINES` maps an engine's name to its adapter class (a :class:`~harness.engines.base.TreeEngine`):
Pinocchio (from the URDF), MuJoCo (from the MJCF), Drake (from the URDF). An adapter is imported when it is first
looked up, so that naming the engines (``harness list``, the CLI's choices) loads none of them. Our compiled
symbolic model is the other source of numbers, already in lecture coordinates (:data:`SYMBOLIC`,
:mod:`harness.engines.symbolic`). :func:`evaluate` gives an :class:`~harness.engines.base.Evaluation` in lecture
coordinates from any source."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Mapping
from contextlib import contextmanager
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


_KEPT: list = []   # (models, how many) of the innermost :func:`models_kept` block (nested blocks share one)


@contextmanager
def models_kept(kept: int = 4096):
    """Within the block, :func:`model` builds each engine's model of a numeric tree once and hands it out again,
    the ``kept`` most recently used (then the least recently used is dropped; a model with its ``MjData``
    holds megabytes): :func:`~harness.export.numeric.instantiate` gives one tree per system and parameter values,
    and the states share parameter values: a conformance run checks two states per parameter draw
    (:data:`~harness.compare.strategies.STATES_PER_DRAW`) and hypothesis repeats draws (49 to 91 distinct of 100,
    mostly in a row), the claims' states repeat them too. Every evaluation
    sets the whole state (MuJoCo: ``mj_forward`` alone, no step, so no warm start carried from one evaluation to
    the next), so a kept model gives the numbers a new one gives. The models are dropped at the end of the
    outermost block. One block at a time per process (the CLI's and the cluster's workers run one system at a
    time)."""
    _KEPT.append(_KEPT[-1] if _KEPT else (OrderedDict(), kept))
    try:
        yield
    finally:
        _KEPT.pop()


def model(name: str, tree):
    """Engine ``name``'s model of ``tree`` from our exported text: kept within :func:`models_kept`, built for the
    call alone outside it."""
    if not _KEPT:
        return ENGINES[name](tree)
    kept, size = _KEPT[-1]
    key = (name, id(tree))
    hit = kept.get(key)
    if hit is None or hit[0] is not tree:  # the tree is kept alive with its model: its id is not reused
        hit = kept[key] = (tree, ENGINES[name](tree))
        while len(kept) > size:
            kept.popitem(last=False)
    kept.move_to_end(key)
    return hit[1]


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


def steps_itself(name: str) -> bool:
    """Whether the source ``name`` steps a scene with its own integrators (MuJoCo's ``mj_step``) rather than being
    integrated by ours around its forward dynamics (the symbolic model, Pinocchio)."""
    return name in ENGINES and bool(simulating((name,), "stepping"))
