"""Pruning: the scene simulated with only the effects it calls for against the same scene with every effect of
the system present but idle (multiplied by a parameter set to 0, :func:`harness.modeling.scenes.idle`): the same
trajectory (``ENGINE``, :mod:`harness.scenes.base`), and the time ratio idle/pruned of our symbolic simulation."""

from __future__ import annotations

from harness.modeling.scenes import with_idle_effects
from harness.scenes import simulate as sim
from harness.scenes.base import ENGINE, Phenomenon, SceneRun

PRUNING_REPEATS = 3


class Pruning(Phenomenon):
    name = "pruning"

    def check(self, run: SceneRun) -> None:
        """Idle-but-present against pruned: the same trajectory, and the time ratio (the fastest of
        ``PRUNING_REPEATS`` runs each, as a single timing on a shared machine is noise). A scene that calls for
        every effect of its system has nothing to prune: its ratio is 1 by construction."""
        system, scene, result = run.system, run.scene, run.result
        idle_system, idle_scene = with_idle_effects(system, scene)
        key = "pruning time ratio (idle / pruned), symbolic"
        if idle_scene is scene:
            result.timings[key] = 1.0
            result.notes["pruning"] = "nothing to prune: the scene calls for every effect of the system"
            return

        def symbolic(s, sc):
            return run.motion.simulate(s, sc, run.event, "symbolic", rtol=1e-10, atol=1e-10, catalogue=run.catalogue)

        lean = [symbolic(system, scene) for _ in range(PRUNING_REPEATS)]
        full = [symbolic(idle_system, idle_scene) for _ in range(PRUNING_REPEATS)]
        result.add(ENGINE.check("pruned = all effects present but idle", "symbolic", sim.max_error(full[0], lean[0])))
        result.timings[key] = min(t.seconds for t in full) / max(min(t.seconds for t in lean), 1e-12)
        result.notes["pruning: effects left out"] = ", ".join(sorted(set(idle_scene.effects) - set(scene.effects)))


PLUGIN = Pruning()
