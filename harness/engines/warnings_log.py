"""Engine warnings are findings, never console noise: each is captured with the system, where it was raised and
the parameter values, and explained — or it fails the system.

MuJoCo warns through two channels: ``MjSpec.compile()`` and ``MjSpec.to_xml()`` raise Python ``UserWarning``s,
everything else calls its user-warning handler (installed here, once). :func:`capture` collects both within a
block; :func:`drain` hands the collected warnings of a run to its record, grouped by message.

An explanation is checked, not asserted. The one MuJoCo warning the catalogue produces is "Inertia matrix is too
close to singular … Time = 0" while compiling: ``mj_setConst`` evaluates the mass matrix at the model's reference
configuration ``qpos0`` (every joint at 0), which for some systems is a configuration the lecture's coordinates
exclude (the tower crane's rope length ``s_5 = 0``: the point load sits on the axes of both rope angles). It is
explained when Pinocchio's own ``crba`` of the same exported tree is singular at ``qpos0`` too; the constants
MuJoCo computes there (``dof_invweight0``) only scale its constraint regularization.
"""

from __future__ import annotations

import re
import warnings
from contextlib import contextmanager
from dataclasses import dataclass

import mujoco
import numpy as np

SINGULAR_AT_QPOS0 = re.compile(r"Inertia matrix is too close to singular.*Time = 0\.0+\.?$")
SINGULAR_RATIO = 1e-12
"""M at qpos0 counts as singular when its smallest eigenvalue is below this fraction of its largest."""

_texts: list[str] = []
_active = [0]   # captures under way


def _handler(text: str) -> None:
    _texts.append(text)
    if not _active[0]:
        del _texts[:-256]  # outside a capture, MuJoCo's warning counters (mujoco_engine.check_warnings) decide


mujoco.set_mju_user_warning(_handler)


@dataclass(frozen=True)
class EngineWarning:
    engine: str
    system: str
    where: str
    message: str
    explained: bool
    reason: str
    state: dict


_log: list[EngineWarning] = []


def texts_since(start: int) -> list[str]:
    """MuJoCo's handler texts after position ``start`` (removed from the buffer)."""
    out = _texts[start:]
    del _texts[start:]
    return out


def mark() -> int:
    return len(_texts)


@contextmanager
def capture(engine: str, where: str, tree, state: dict | None = None):
    """Collect every warning raised within the block (Python warnings and MuJoCo's handler) for ``tree``;
    ``state`` is the configuration they refer to (by default MuJoCo's qpos0: every tree joint at 0)."""
    start = mark()
    _active[0] += 1
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            yield
    finally:
        _active[0] -= 1
    record(engine, where, tree, [str(w.message) for w in caught] + texts_since(start), state)


def record(engine: str, where: str, tree, texts, state: dict | None = None) -> None:
    """Log the warnings ``texts`` that ``engine`` raised at ``where`` for ``tree``, each explained (:func:`explain`):
    what :func:`capture` does with the warnings of its block, and what a kept export replays (the warnings its
    writing raised, :func:`harness.export.mjcf.exported_mjcf`)."""
    state = state if state is not None else {"qpos0": {j.name: 0.0 for j in tree.joints}}
    for text in texts:
        explained, reason = explain(engine, text, tree)
        _log.append(EngineWarning(engine, tree.system, where, text.strip(), explained, reason, state))


def logged() -> int:
    """How many warnings are logged: :func:`messages_since` reads those logged after."""
    return len(_log)


def messages_since(start: int) -> list[str]:
    """The messages of the warnings logged after position ``start`` (:func:`logged`), in order."""
    return [w.message for w in _log[start:]]


_EXPLAINED: dict = {}


def explain(engine: str, text: str, tree) -> tuple[bool, str]:
    """Whether the warning is explained, and why (or why not); once per engine, message and tree (building the
    exported MJCF and loading it raise the same warning three times for one tree)."""
    key = (engine, text.strip(), id(tree))
    kept = _EXPLAINED.get(key)
    if kept is not None and kept[0] is tree:  # the tree is kept alive with the answer: its id is not reused
        return kept[1]
    answer = _explain(engine, text, tree)
    if len(_EXPLAINED) >= 1024:
        _EXPLAINED.clear()
    _EXPLAINED[key] = (tree, answer)
    return answer


def _explain(engine: str, text: str, tree) -> tuple[bool, str]:
    if engine == "mujoco" and SINGULAR_AT_QPOS0.search(text.strip()):
        from harness.engines.pinocchio_engine import PinocchioModel
        import pinocchio as pin

        pm = PinocchioModel(tree)
        M = pin.crba(pm.model, pm.data, np.zeros(pm.model.nq))
        M = np.triu(M) + np.triu(M, 1).T
        eig = np.linalg.eigvalsh(M)
        ratio = float(eig[0] / eig[-1]) if eig[-1] > 0 else 0.0
        if ratio < SINGULAR_RATIO:
            return True, (f"MuJoCo's compiler evaluates M at qpos0 (every joint at 0), where Pinocchio's crba of "
                          f"the same tree is singular too (smallest/largest eigenvalue {ratio:.1e}): a configuration "
                          f"outside the coordinates' ranges the checks draw; the constants computed there "
                          f"(dof_invweight0) only scale constraint regularization")
        return False, f"Pinocchio's M at qpos0 is regular (smallest/largest eigenvalue {ratio:.1e})"
    return False, "no explanation is known for this warning"


@contextmanager
def discarded():
    """The warnings captured within the block are dropped, not reported: a phase whose warnings belong to no
    record (``harness export --check`` compares texts) leaves none behind for the next job of its process."""
    start = len(_log)
    try:
        yield
    finally:
        del _log[start:]


def drain(system: str | None = None) -> list[dict]:
    """The captured warnings (of ``system``, or all), grouped by engine, place and message, removed from the log:
    ``{"engine", "where", "message", "count", "explained", "reason", "state"}`` (``state``: the configuration of
    the first one)."""
    taken = [w for w in _log if system is None or w.system == system]
    _log[:] = [w for w in _log if not (system is None or w.system == system)]
    groups: dict[tuple, dict] = {}
    for w in taken:
        key = (w.engine, w.where, re.sub(r"\d+", "#", w.message), w.explained)
        entry = groups.setdefault(key, {"engine": w.engine, "where": w.where, "message": w.message, "count": 0,
                                        "explained": w.explained, "reason": w.reason, "state": w.state})
        entry["count"] += 1
    return list(groups.values())


def compile_spec(spec, tree, where: str):
    """``spec.compile()`` with its warnings captured for ``tree`` (a scene's engine configuration)."""
    with capture("mujoco", where, tree):
        return spec.compile()
