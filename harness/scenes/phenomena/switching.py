"""A motion whose branches switch at events (stick-slip, lift-off): what every such motion checks.

The reference (DOP853, events located by ``solve_ivp``) confirmed by LSODA, trajectories and event times of every
engine's forward dynamics with the same branches, and for a conservative scene the energy across the switching.
Each kind (:mod:`.stick_slip`, :mod:`.lift_off`) gives :meth:`Switching.branches`, its event-located simulation.
"""

from __future__ import annotations

import numpy as np

from harness.scenes import simulate as sim
from harness.scenes.base import (CONFIRMATION, CONFIRMATION_RTOL, ENGINE, ENGINE_EVENT, EVENT, INVARIANT, REFERENCE,
                                 Motion, SceneRun, event_error)


class Switching(Motion):
    switches = True

    def branches(self, system, scene, event, source, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=None,
                 catalogue=None) -> sim.HybridTrajectory:
        raise NotImplementedError

    def simulate(self, system, scene, event, source, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=None,
                 catalogue=None) -> sim.HybridTrajectory:
        return self.branches(system, scene, event, source, method=method, rtol=rtol, atol=atol, t_eval=t_eval,
                             catalogue=catalogue)

    def check(self, run: SceneRun) -> None:
        result = run.result

        def simulate(source, **kw):
            return self.simulate(run.system, run.scene, run.event, source, catalogue=run.catalogue, **kw)

        ref = simulate("symbolic", **{k: v for k, v in sim.REFERENCE.items() if k != "method"})
        result.trajectories["reference"] = ref
        second = simulate("symbolic", method=CONFIRMATION, rtol=CONFIRMATION_RTOL, atol=CONFIRMATION_RTOL)
        result.add(REFERENCE.check(f"reference confirmed ({CONFIRMATION} vs DOP853)", "symbolic",
                                   sim.max_error(second, ref)))
        result.add(EVENT.check(f"events confirmed ({CONFIRMATION} vs DOP853), s", "symbolic", event_error(second, ref)))
        result.notes["events (reference)"] = "; ".join(f"{e.time:.6f} s {e.before} -> {e.after}"
                                                       for e in ref.events) or "none over the horizon"
        for engine in run.engines:
            tr = simulate(engine, rtol=1e-10, atol=1e-10)
            result.trajectories[engine] = tr
            result.add(ENGINE.check("trajectory (DOP853 1e-10, events)", engine, sim.max_error(tr, ref)))
            result.add(ENGINE_EVENT.check("event times, s", engine, event_error(tr, ref)))
        if run.scene.conservative:
            energy = np.asarray(ref.energies())
            scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(np.abs(energy))))
            result.add(INVARIANT.check("energy constant across the events", "symbolic",
                                       float(np.max(np.abs(energy - energy[0]))) / scale))
        else:
            result.notes["power balance"] = "not checked across the switching of the branches"
