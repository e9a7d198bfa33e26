"""Lift-off, Exercise A.15: a motion whose branches switch where a contact's normal force vanishes.

The trebuchet's projectile slides on the ground (phase 1, ``trebuchet``) until the ground's normal force vanishes,
then flies (phase 2, ``trebuchet_free``, found in the catalogue handed to the run). The normal force is the
constraint force ``λ`` of the phase-1 constraint in the phase-2 coordinates, ``G^T λ = M₂ (q̈₂ − a₂)`` (``q̈₂`` the
phase-1 motion mapped to phase-2 coordinates, ``a₂`` phase 2's free acceleration, ``G`` the gradient of the
projectile's height), computed from each source's own dynamics. The trajectory is given in phase-2 coordinates; a
constrained tree of phase 1 (:mod:`.closures`) is compared until the lift-off, mapped to them.
"""

from __future__ import annotations

import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from harness.derivation.lambdified import lambdify
from harness.errors import ModelError
from harness.modeling.events import LiftOff
from harness.scenes import simulate as sim
from harness.compare.conformance import ROUND_OFF
from harness.scenes.base import EVENT, SceneRun
from harness.scenes.phenomena.switching import Switching


def phase_two_system(event: LiftOff, catalogue):
    """The phase-2 system a lift-off switches to, from the catalogue handed in."""
    if catalogue is None:
        raise ModelError(f"lift-off to {event.free_system!r}: give the catalogue that holds the phase-2 system")
    return catalogue.get(event.free_system)


class _LiftOffDynamics:
    def __init__(self, system, scene, event: LiftOff, source: str, catalogue=None):
        self.one = sim.Dynamics(system, scene, source)
        self.free_system = phase_two_system(event, catalogue)
        self.two = sim.Dynamics(self.free_system, scene, source)
        q1, qd1 = [c.symbol for c in system.coordinates], [c.rate for c in system.coordinates]
        q2 = [c.symbol for c in self.free_system.coordinates]
        params = [p.symbol for p in system.parameters]
        to_free = sp.Matrix(event.to_free)
        J = to_free.jacobian(q1)
        J_dot = sp.Matrix(J.shape[0], J.shape[1], lambda i, j: sum(sp.diff(J[i, j], a) * b for a, b in zip(q1, qd1)))
        height_gradient = sp.Matrix([event.height]).jacobian(q2)
        p2 = [p.symbol for p in self.free_system.parameters]
        self._map = lambdify([q1, qd1, params], [to_free, J, J_dot], "numpy")
        self._G = lambdify([q2, p2], height_gradient, "numpy")

    def to_free(self, y):
        n = len(self.one.system.coordinates)
        q2, J, J_dot = (np.asarray(a, dtype=float) for a in self._map(y[:n], y[n:], self.one.p))
        return q2.ravel(), J, J_dot

    def normal_force(self, t, y) -> float:
        """``λ`` from ``G^T λ = M₂ (q̈₂ − a₂)`` (least squares), with this source's dynamics in both phases."""
        n = len(self.one.system.coordinates)
        q2, J, J_dot = self.to_free(y)
        qd2 = J @ y[n:]
        qdd2 = J @ self.one(t, y[:n], y[n:]) + J_dot @ y[n:]
        M2 = self.two.mass_matrix(t, q2, qd2)
        a2 = self.two(t, q2, qd2)
        G = np.asarray(self._G(q2, self.two.p), dtype=float).ravel()
        return float(G @ (M2 @ (qdd2 - a2)) / (G @ G))


def lift_off(system, scene, event: LiftOff, source: str, method="DOP853", rtol=1e-12, atol=1e-12,
             t_eval=None, catalogue=None) -> sim.HybridTrajectory:
    """Phase 1 until ``λ = 0`` (a ``solve_ivp`` event), then phase 2 (``event.free_system`` from ``catalogue``);
    the trajectory in phase-2 coordinates."""
    h = _LiftOffDynamics(system, scene, event, source, catalogue)
    t_eval = sim.sample_times(scene) if t_eval is None else t_eval
    n1, n2 = len(system.coordinates), len(h.free_system.coordinates)
    start = time.perf_counter()

    def phase1(t, y):
        return np.concatenate([y[n1:], h.one(t, y[:n1], y[n1:])])

    def phase2(t, y):
        return np.concatenate([y[n2:], h.two(t, y[:n2], y[n2:])])

    ev = lambda t, y: h.normal_force(t, y)  # noqa: E731
    ev.terminal, ev.direction = True, -1.0
    y0 = np.concatenate([scene.q0, scene.qd0]).astype(float)
    if h.normal_force(0.0, y0) <= 0:
        raise ModelError(f"{system.name}: the ground does not push at t = 0 (normal force ≤ 0): no phase 1")
    one = solve_ivp(phase1, (0.0, scene.horizon), y0, method=method, rtol=rtol, atol=atol, t_eval=t_eval,
                    events=ev)
    if one.status < 0:
        raise RuntimeError(f"{scene.name}: phase 1 failed: {one.message}")
    mapped = [h.to_free(y) for y in one.y.T]
    q = [m[0] for m in mapped]
    qd = [m[1] @ y[n1:] for m, y in zip(mapped, one.y.T)]
    ts, events, nfev = list(one.t), [], one.nfev
    if one.status == 1:
        t1, y1 = float(one.t_events[0][0]), one.y_events[0][0]
        events.append(sim.Event(t1, "phase 1 (on the ground)", "phase 2 (lift-off)"))
        q2, J, _ = h.to_free(y1)
        y2 = np.concatenate([q2, J @ y1[n1:]])
        rest = t_eval[t_eval > t1]
        two = solve_ivp(phase2, (t1, scene.horizon), y2, method=method, rtol=rtol, atol=atol, t_eval=rest)
        if two.status < 0:
            raise RuntimeError(f"{scene.name}: phase 2 failed: {two.message}")
        ts += list(two.t)
        q += list(two.y[:n2].T)
        qd += list(two.y[n2:].T)
        nfev += two.nfev
    q, qd = np.array(q), np.array(qd)
    tr = sim.HybridTrajectory(f"{source} ({method}, rtol={rtol:g}, lift-off)", np.array(ts), q, qd,
                              time.perf_counter() - start, nfev, energy_of=h.two.energy, events=events)
    tr.notes["coordinates"] = [c.name for c in h.free_system.coordinates]
    if events:
        tr.notes["lift-off state"] = one.y_events[0][0]   # phase 1's (q, q̇) where the normal force vanished
    return tr


def constraint_force(system, scene):
    """``λ(t, y)``: Pinocchio's own normal force at a phase-1 state ``y = (q, q̇)``, the multiplier of the ground's row
    in its KKT forward dynamics (``M a + b = τ + Jᵀλ``, ``J a + γ = 0``; ``pin.forwardDynamics`` of
    :class:`~harness.scenes.phenomena.closures.PinocchioConstrained`, no stabilization at a state on the
    constraint): apart from the phase-2 projection the lift-off is located with
    (:meth:`_LiftOffDynamics.normal_force`). None where phase 1 has more than its ground as a constraint row."""
    from harness.scenes.phenomena.closures import PinocchioConstrained

    pc = PinocchioConstrained(system, scene)
    if len(pc.couplings) + len(pc.dyn.system.closures) != 1:
        return None
    n = len(system.coordinates)

    def at(t: float, y) -> float:
        q, qd, u = np.asarray(y[:n], dtype=float), np.asarray(y[n:], dtype=float), pc.dyn.inputs(t)
        theta, J, _ = pc.dyn.c.map_at(q, qd, pc.dyn.p, u)
        inputs = dict(zip(pc.dyn.input_names, u))
        pc.constraints.forward_dynamics(theta, J @ qd, inputs, pc.dyn.loads(q, qd, u), 0.0)
        return float(np.ravel(pc.pm.data.lambda_c)[0])
    return at


def in_free_coordinates(system, scene, event: LiftOff, tr: sim.Trajectory, catalogue=None) -> sim.Trajectory:
    """A phase-1 trajectory expressed in phase-2 coordinates (to compare it with a lift-off reference)."""
    h = _LiftOffDynamics(system, scene, event, "symbolic", catalogue)
    mapped = [h.to_free(np.concatenate([a, b])) for a, b in zip(tr.q, tr.qd)]
    q = np.array([m[0] for m in mapped])
    qd = np.array([m[1] @ b for m, b in zip(mapped, tr.qd)])
    out = sim.Trajectory(tr.source, tr.t, q, qd, tr.seconds, tr.evaluations, tr.energies())
    out.notes.update(tr.notes)
    return out


class LiftOffMotion(Switching):
    name = "lift-off (Exercise A.15)"
    event = LiftOff
    mujoco_note = ("MuJoCo has no lift-off of its own here (its phase 1, a point held on the ground by an equality, "
                   "is checked by harness check)")

    def branches(self, system, scene, event, source, **kw) -> sim.HybridTrajectory:
        return lift_off(system, scene, event, source, **kw)

    def check(self, run: SceneRun) -> None:
        """What every switching motion checks (:class:`Switching`), and the normal force the lift-off is located
        with against Pinocchio's own (:func:`constraint_force`): equal at the start, and vanishing at the
        reference's lift-off, as a time ``|λ / λ̇|`` there (the first-order offset of Pinocchio's zero from it)."""
        super().check(run)
        if "pinocchio" not in run.engines:
            return
        system, scene, result, ref = run.system, run.scene, run.result, run.reference
        force = constraint_force(system, scene)
        if force is None:
            result.notes["lift-off against Pinocchio's constraint force"] = (
                "not checked: phase 1 has more constraint rows than its ground")
            return
        h = _LiftOffDynamics(system, scene, run.event, "symbolic", run.catalogue)
        y0 = np.concatenate([scene.q0, scene.qd0]).astype(float)
        ours, pinocchio = h.normal_force(0.0, y0), force(0.0, y0)
        result.add(ROUND_OFF.check("normal force at the start: the lift-off's (phase-2 projection) against "
                                   "Pinocchio's constraint force (KKT multiplier)", "pinocchio",
                                   abs(ours - pinocchio) / abs(pinocchio), detail=f"{ours:.6g} N, {pinocchio:.6g} N"))
        if ref.events:
            t1, y1 = ref.events[0].time, ref.notes["lift-off state"]
            n = len(system.coordinates)
            rate = np.concatenate([y1[n:], h.one(t1, y1[:n], y1[n:])])    # the phase-1 motion's ẏ there
            step = 1e-7
            slope = (force(t1, y1 + step * rate) - force(t1, y1 - step * rate)) / (2 * step)
            at_lift_off = force(t1, y1)
            result.add(EVENT.check("lift-offs where Pinocchio's constraint force (KKT multiplier) vanishes, s",
                                   "pinocchio", abs(at_lift_off / slope),
                                   detail=f"λ = {at_lift_off:.3g} N at the reference's lift-off, λ̇ = {slope:.4g} N/s"))

    def tree_view(self, run: SceneRun):
        """Phase 1's constrained tree holds until the lift-off; compared in phase-2 coordinates."""
        return (run.reference.events[0].time,
                lambda tr: in_free_coordinates(run.system, run.scene, run.event, tr, run.catalogue))


PLUGIN = LiftOffMotion()
