"""The energy balance of a smooth motion: ``E = T + V`` constant in a conservative scene, otherwise the power
balance ``E(t) − E(0) = ∫ q̇ᵀ f_np dt`` (3.101), along the reference (``INVARIANT``, :mod:`harness.scenes.base`).
A switching motion checks the energy across its events itself (:mod:`.switching`)."""

from __future__ import annotations

import numpy as np

from harness.derivation.compile import compiled
from harness.modeling.scenes import Scene, pruned
from harness.modeling.system import System
from harness.scenes import simulate as sim
from harness.scenes.base import INVARIANT, Phenomenon, SceneRun


def _energy_balance(system: System, scene: Scene) -> tuple[float, float]:
    """Largest ``|E(t) − E(0) − W(t)|`` relative to the energy scale, with ``Ẇ = q̇ᵀ f_np`` integrated
    alongside the motion (DOP853, 1e-12)."""
    s = pruned(system, scene.effects)
    c = compiled(s)
    params = {**system.default_parameters(), **scene.params}
    p = np.array([params[x.name] for x in s.parameters])
    n = len(s.q)

    def rhs(t, y):
        q, qd = y[:n], y[n:2 * n]
        u = scene.u(t, s)
        power = float(qd @ c.generalized_forces(q, qd, p, u))
        return np.concatenate([qd, c.forward_dynamics(q, qd, p, u), [power]])

    y0 = np.concatenate([scene.q0, scene.qd0, [0.0]])
    _, ys, _ = sim.solve_piecewise(rhs, scene, y0, "DOP853", 1e-12, 1e-12, sim.sample_times(scene))
    zeros = np.zeros(len(s.u))
    kinetic = np.array([float(c("T", y[:n], y[n:2 * n], p, zeros)) for y in ys.T])
    energy = kinetic + np.array([float(c("V", y[:n], y[n:2 * n], p, zeros)) for y in ys.T])
    work = ys[2 * n]
    kinetic = np.abs(kinetic)
    scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(kinetic)), float(np.max(np.abs(work))))
    return float(np.max(np.abs(energy - energy[0] - work))) / scale, scale


class EnergyBalance(Phenomenon):
    name = "energy balance (3.101)"

    def applies(self, run: SceneRun) -> bool:
        return not run.motion.switches

    def check(self, run: SceneRun) -> None:
        balance, _ = _energy_balance(run.system, run.scene)
        run.result.add(INVARIANT.check("energy constant" if run.scene.conservative else "power balance (3.101)",
                                       "symbolic", balance))


PLUGIN = EnergyBalance()
