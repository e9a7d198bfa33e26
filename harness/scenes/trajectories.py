"""A scene checked by every plug-in that applies, and its record for results.json.

:func:`run_scene` is the loop: the scene's motion first (:func:`harness.scenes.phenomena.motion_of`), then every
plug-in of :data:`harness.scenes.phenomena.CHECKS` that applies, each adding to one
:class:`harness.scenes.base.SceneRun`. Tolerances and their reasons: :mod:`harness.scenes.base` and the plug-ins.
"""

from __future__ import annotations

import numpy as np

from harness.engines import ENGINES
from harness.modeling.scenes import Scene
from harness.modeling.system import System
from harness.scenes.base import SceneResult, SceneRun
from harness.scenes.phenomena import CHECKS, motion_of


def run_scene(system: System, scene: Scene, engines=("pinocchio", "mujoco"), mujoco_dt: float | None = None,
              catalogue=None) -> SceneResult:
    """Simulate ``scene`` with every source and check it; ``catalogue`` resolves the systems an event switches
    to (a lift-off's phase 2)."""
    result = SceneResult(system.name, scene.name)
    for engine in engines:
        if ENGINES[engine].applies(system):
            result.notes[engine] = ENGINES[engine].applies(system)
    motion, event = motion_of(scene)
    run = SceneRun(system, scene, tuple(e for e in engines if not ENGINES[e].applies(system)), result, motion, event,
                   catalogue, mujoco_dt)
    for phenomenon in (motion, *CHECKS):
        if phenomenon.applies(run):
            phenomenon.check(run)
    return result


# --------------------------------------------------------------------------- records for results.json
def _digits(values, significant: int = 7):
    """Nested lists of floats with ``significant`` digits (plots need no more; the file shrinks ~2.5x)."""
    return np.vectorize(lambda v: float(f"{v:.{significant}g}"), otypes=[float])(np.asarray(values, float)).tolist()


def series(system: System, scene: Scene, result: SceneResult) -> dict:
    """The trajectories of every source at the reference's sample times (for plots): q, q̇, energy, and the
    error over time (state difference relative to the state's scale, as :func:`simulate.max_error`)."""
    ref = result.trajectories["reference"]
    scale = np.maximum(1.0, np.max(np.abs(np.hstack([ref.q, ref.qd])), axis=0))   # as simulate.max_error
    coordinates = ref.notes.get("coordinates") or [c.name for c in system.coordinates]
    out = {"system": system.name, "scene": scene.name, "coordinates": coordinates,
           "t": _digits(ref.t), "sources": {}, "error": {}}
    key = np.round(ref.t, 9)
    for name, tr in result.trajectories.items():
        keep = np.isin(np.round(tr.t, 9), key)
        out["sources"][name] = {"t": _digits(tr.t[keep]), "q": _digits(tr.q[keep]), "qd": _digits(tr.qd[keep]),
                                "energy": None if tr.energies() is None else _digits(np.asarray(tr.energies())[keep])}
        if name != "reference":
            at = np.isin(key, np.round(tr.t[keep], 9))
            diff = np.hstack([tr.q[keep], tr.qd[keep]]) - np.hstack([ref.q[at], ref.qd[at]])
            out["error"][name] = _digits(np.max(np.abs(diff) / scale, axis=1))
    return out


def scene_record(system: System, scene: Scene, catalogue=None) -> tuple[dict, dict]:
    """One scene's checks as a results.json record, and its series (written to ``series`` by the caller)."""
    record = {"scene": scene.name, "description": scene.description, "effects": sorted(scene.effects),
              "horizon": scene.horizon, "series": f"trajectories/{system.name}.{scene.name}.json"}
    try:
        result = run_scene(system, scene, catalogue=catalogue)
    except Exception as exc:  # noqa: BLE001 - one scene raising never loses the others
        record.update(passed=False, checks=[], notes={}, failure=f"{type(exc).__name__}: {exc}", series=None)
        return record, {}
    record.update(passed=result.passed, failure=None,
                  checks=[c.record() for c in result.checks],
                  notes={k: (float(v) if isinstance(v, (float, np.floating)) else str(v))
                         for k, v in result.notes.items()})
    return record, series(system, scene, result)
