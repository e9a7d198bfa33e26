"""The energy balance of a smooth motion: ``E = T + V`` constant in a conservative scene, along the reference itself
(the trajectory every source is compared with); otherwise the power balance ``E(t) − E(0) = ∫ q̇ᵀ f_np dt`` (3.101),
the work integrated alongside the motion (``INVARIANT``, :mod:`harness.scenes.base`). A switching motion checks the
energy across its events itself (:mod:`.switching`).

Before, a conservative scene was integrated a second time for this check (with a work integral that is 0 there):
2.5 CPU s of the main job (measured per scene with ``_energy_balance``), for a check of another trajectory than the
one compared; along the reference its values went from 5.3e-15–1.2e-10 to 1.8e-15–1.7e-11 (its atol is 1e-14, the
second run's 1e-12), bound 1e-8."""

from __future__ import annotations

import numpy as np

from harness.engines import SYMBOLIC
from harness.modeling.scenes import Scene
from harness.modeling.system import System
from harness.scenes import simulate as sim
from harness.scenes.base import INVARIANT, Phenomenon, SceneRun


def _energy_balance(system: System, scene: Scene, reference: sim.Trajectory) -> tuple[float, float]:
    """Largest ``|E(t) − E(0) − W(t)|`` relative to the energy scale. A conservative scene (no damper, input, load,
    friction or contact: ``f_np ≡ 0``, ``W ≡ 0``) is checked along ``reference`` itself, the trajectory every source is
    compared with (DOP853 at rtol 1e-12, atol 1e-14); otherwise ``Ẇ = q̇ᵀ f_np`` is integrated alongside the motion
    (DOP853, 1e-12; kept for the next run, :func:`~harness.scenes.simulate.kept_solution`)."""
    dyn = sim.Dynamics(system, scene, SYMBOLIC)   # the pruned system, compiled, its parameter values
    s, c, p = dyn.system, dyn.c, dyn.p
    n = len(s.q)
    if scene.conservative:
        qs, qds, work = reference.q, reference.qd, np.zeros(len(reference.t))
    else:
        def rhs(t, y):
            q, qd = y[:n], y[n:2 * n]
            u = dyn.inputs(t)   # held over each piece (Dynamics.hold)
            power = float(qd @ c.generalized_forces(q, qd, p, u))
            return np.concatenate([qd, c.forward_dynamics(q, qd, p, u), [power]])

        def solve() -> dict:
            y0 = np.concatenate([scene.q0, scene.qd0, [0.0]])
            return {"y": sim.solve_piecewise(rhs, scene, y0, "DOP853", 1e-12, 1e-12, sim.sample_times(scene),
                                             on_piece=dyn.hold)[1]}

        ys = sim.kept_solution(system, scene, "power balance (3.101), DOP853, rtol=1e-12, atol=1e-12",
                               sim.sample_times(scene), solve)["y"]
        qs, qds, work = ys[:n].T, ys[n:2 * n].T, ys[2 * n]
    zeros = np.zeros(len(s.u))
    kinetic = np.array([float(c("T", q, qd, p, zeros)) for q, qd in zip(qs, qds)])
    energy = kinetic + np.array([float(c("V", q, qd, p, zeros)) for q, qd in zip(qs, qds)])
    kinetic = np.abs(kinetic)
    scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(kinetic)), float(np.max(np.abs(work))))
    return float(np.max(np.abs(energy - energy[0] - work))) / scale, scale


class EnergyBalance(Phenomenon):
    name = "energy balance (3.101)"

    def applies(self, run: SceneRun) -> bool:
        return not run.motion.switches

    def check(self, run: SceneRun) -> None:
        balance, _ = _energy_balance(run.system, run.scene, run.reference)
        run.result.add(INVARIANT.check("energy constant" if run.scene.conservative else "power balance (3.101)",
                                       "symbolic", balance))


PLUGIN = EnergyBalance()
