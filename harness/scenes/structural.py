"""Structural changes of a scene: a model's branches and the events that switch between them.

A scene lists its events (``Scene.events``); each kind knows how to simulate the switching with every source
and how the engines are configured for it:

* :class:`StickSlip`, Section 3.5.2, (3.80): a mass on a rough surface sticks while the friction force it
  needs stays within ``mu_H f_N`` and ``ẋ = 0`` (3.80a), and slides with ``f_C = mu_C f_N sgn(ẋ)`` otherwise
  (3.80b). Our simulation (any source: symbolic, Pinocchio, MuJoCo forward dynamics) locates both events with
  ``solve_ivp`` events: breakaway where ``|f_required| = mu_H f_N`` and sticking where ``ẋ = 0``; in the
  sliding branch the model's own friction force is evaluated with the branch's direction. MuJoCo also
  simulates it with its own dry friction (joint ``frictionloss``, the flag switched on by the scene), its
  value switched between ``mu_H f_N`` (at rest) and ``mu_C f_N`` (sliding) before every step, as MuJoCo has
  one coefficient.
* :class:`RollSlip`, Exercise 3.17: a sphere on an inclined plane rolls if ``mu_H ≥ 2/7 tan(alpha)`` and
  slips otherwise. MuJoCo simulates the sphere as a body with a normal, a tangential and a rolling joint in
  contact with a plane (contact and friction switched on, an elliptic friction cone); the rolling constraint
  of the model is *not* imposed: the contact has to produce it. The threshold MuJoCo shows is located by
  bisection on the friction coefficient.
* :class:`LiftOff`, Exercise A.15: the trebuchet's projectile slides on the ground (phase 1, ``trebuchet``)
  until the ground's normal force vanishes, then flies (phase 2, ``trebuchet_free``). The normal force is the
  constraint force ``λ`` of the phase-1 constraint in the phase-2 coordinates,
  ``G^T λ = M₂ (q̈₂ − a₂)`` (``q̈₂`` the phase-1 motion mapped to phase-2 coordinates, ``a₂`` phase 2's free
  acceleration, ``G`` the gradient of the projectile's height), computed from each source's own dynamics.

Tolerances (with :mod:`harness.scenes.trajectories`):
``EVENT_TOL = 1e-8`` s — an event time of the reference against its prediction and against LSODA (events are
located to the integrator's tolerance 1e-12 and root-finding, well below it); engines' forward dynamics locate
their events within ``ENGINE_EVENT_TOL = 1e-5`` s of the reference (their trajectories carry ``ENGINE_TOL``).
MuJoCo's own dry friction and contact are soft constraints solved once per step, stepped by a first-order
method: their error is first order in ``dt`` (:mod:`harness.scenes.trajectories` checks it and derives the ``3 dt``
within which MuJoCo's events must lie: quantization to the step and one step of response). MuJoCo's
rolling threshold is located by bisection to 1e-3 and must lie within ``THRESHOLD_TOL = 1e-2`` (relative) of
the predicted ``2/7 tan(alpha)``: the soft contact lets the sphere creep by a small slip velocity, which the
rolling criterion (slip ≤ 1e-6 of the rolling velocity) tolerates only near the threshold.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from harness.checks import Bound
from harness.engines.mujoco_engine import ContactSphere, DryFriction, MujocoModel, Options
from harness.errors import ModelError
from harness.export.numeric import instantiate
from harness.modeling.system import value_at
from harness.modeling.events import LiftOff, RollSlip, StickSlip
from harness.scenes import simulate as sim

EVENT = Bound("event time", 1e-8, "an event of the reference against its prediction and against LSODA, s: located "
              "to the integrator's tolerance 1e-12 and by root finding")
ENGINE_EVENT = Bound("engine event time", 1e-5, "an event located with an engine's forward dynamics against the "
                     "reference, s: their trajectories carry the engine trajectory tolerance")
THRESHOLD = Bound("rolling threshold", 1e-2, "MuJoCo's rolling threshold (bisection to 1e-3) against 2/7 tan(alpha), "
                  "relative: the soft contact lets the sphere creep")
STEP_EVENT = Bound("MuJoCo step event", 3.0, "an event of MuJoCo's own dry friction against the reference, in time "
                   "steps: a breakaway is seen ½ to 3/2 steps late (the input is held at the step's midpoint), a "
                   "sticking 1 to 2 steps late (MuJoCo's velocity reaches 0 a step after the crossing), the "
                   "trajectory's own error shifts them by ≤ 0.01 dt: δ ≤ 2 dt, and a third step of room",
                   derived=True)
EVENT_TOL, THRESHOLD_TOL, ENGINE_EVENT_TOL = EVENT.value, THRESHOLD.value, ENGINE_EVENT.value
_TINY = 1e-300                                      # a velocity with a sign and no size


@dataclass(frozen=True)
class Event:
    time: float
    before: str
    after: str


@dataclass
class HybridTrajectory(sim.Trajectory):
    events: list = field(default_factory=list)


def _mode_name(mode: int) -> str:
    return {0: "stick", 1: "slide +", -1: "slide -"}[mode]


# ----------------------------------------------------------------------------------------- stick-slip (3.80)
class _StickSlipDynamics:
    """The branches of (3.80) on top of one source's forward dynamics (one coordinate)."""

    def __init__(self, system, scene, event: StickSlip, source: str):
        if len(system.coordinates) != 1:
            raise ModelError(f"{system.name}: stick-slip switching is implemented for one coordinate")
        self.dyn = sim.Dynamics(system, scene, source)
        self.mu_H, self.mu_C, self.f_N = event.values(self.dyn.params)

    def required_force(self, t, q) -> float:
        """The friction force sticking needs: ``M q̈_free`` with the friction at ``ẋ = 0`` (sgn 0 = 0)."""
        zero = np.zeros(1)
        u = self.dyn.scene.u(t, self.dyn.system)
        M = self.dyn.c("M", q, zero, self.dyn.p, u)
        return float(M[0, 0] * self.dyn(t, q, zero)[0])

    def sliding(self, s: int):
        def rhs(t, y):
            qd = y[1:] if y[1] * s > 0 else np.array([s * _TINY])   # the branch's direction at ẋ = 0
            return np.concatenate([y[1:], self.dyn(t, y[:1], qd)])
        return rhs

    def next_mode(self, t, y) -> int:
        force = self.required_force(t, y[:1])
        return 0 if abs(force) <= self.mu_H * self.f_N else int(np.sign(force))


def stick_slip(system, scene, event: StickSlip, source: str, method="DOP853", rtol=1e-12, atol=1e-12,
               t_eval=None, catalogue=None) -> HybridTrajectory:
    """Event-located simulation of (3.80) with ``source``'s forward dynamics (``catalogue``: unused, as for
    every switching simulation that stays in its system)."""
    h = _StickSlipDynamics(system, scene, event, source)
    t_eval = sim.sample_times(scene) if t_eval is None else t_eval
    y = np.concatenate([scene.q0, scene.qd0]).astype(float)
    mode = int(np.sign(y[1])) if y[1] != 0 else h.next_mode(0.0, y)
    edges = [*scene.breakpoints, scene.horizon]
    ts, ys, events, t, nfev = [], [], [], 0.0, 0
    start = time.perf_counter()
    while t < scene.horizon:
        end = next(e for e in edges if e > t)
        if mode == 0:
            rhs = lambda t_, y_: np.zeros(2)  # noqa: E731 - stuck: ẋ = 0, ẍ = 0 (3.80a)
            ev = lambda t_, y_: abs(h.required_force(t_, y_[:1])) - h.mu_H * h.f_N  # noqa: E731
            ev.direction = 1.0
        else:
            rhs = h.sliding(mode)
            ev = lambda t_, y_: y_[1]  # noqa: E731 - the mass comes to rest
            ev.direction = -float(mode)
        ev.terminal = True
        inside = t_eval[(t_eval >= t) & (t_eval <= end)]
        # at rest the state does not change, so the step would not see the force rise: sample it finely
        steps = {"max_step": scene.horizon / 500} if mode == 0 else {}
        sol = solve_ivp(rhs, (t, end), y, method=method, rtol=rtol, atol=atol, t_eval=inside, events=ev,
                        dense_output=True, **steps)
        if sol.status < 0:
            raise RuntimeError(f"{scene.name}: integration failed at t={t:g}: {sol.message}")
        nfev += sol.nfev
        keep = sol.t > (ts[-1][-1] if ts and len(ts[-1]) else -1.0)
        ts.append(sol.t[keep])
        ys.append(sol.y[:, keep])
        if sol.status == 1:
            t, y = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
            new = h.next_mode(t, y) if mode != 0 else int(np.sign(h.required_force(t, y[:1])))
            if new == 0:
                y[1] = 0.0
            events.append(Event(t, _mode_name(mode), _mode_name(new)))
            mode = new
        else:
            t, y = end, sol.sol(end)
    y_all = np.concatenate(ys, axis=1)
    dyn = h.dyn
    energy = np.array([dyn.energy(a, b) for a, b in zip(y_all[:1].T, y_all[1:].T)])
    return HybridTrajectory(f"{source} ({method}, rtol={rtol:g}, events)", np.concatenate(ts), y_all[:1].T,
                            y_all[1:].T, time.perf_counter() - start, nfev, energy, events=events)


def predicted_breakaway(system, scene, event: StickSlip) -> float:
    """The first time the applied force reaches ``mu_H f_N`` ((3.80a) with the applied input as the force
    sticking needs), found by root-finding on the input signal alone."""
    params = {**system.default_parameters(), **scene.params}
    mu_H, _, f_N = event.values(params)
    u = lambda t: float(np.max(np.abs(scene.u(t, system))))  # noqa: E731
    grid = np.linspace(0.0, scene.horizon, 20001)
    above = [t for t in grid if u(t) > mu_H * f_N]
    if not above:
        return math.inf
    k = int(np.searchsorted(grid, above[0]))
    return brentq(lambda t: u(t) - mu_H * f_N, grid[k - 1], grid[k], xtol=1e-14)


def frictionloss_bound(system, scene, event: StickSlip, ref: HybridTrajectory) -> float:
    """``C`` of the first-order bound ``error ≤ C dt`` of MuJoCo's frictionloss run against the event-located
    reference ``ref`` (errors relative to each component's scale ``max(1, max|y|)``, as :func:`simulate.max_error`).

    MuJoCo's events are late by ``0 < δ ≤ 2 dt`` (the event falls anywhere within a step, and MuJoCo's velocity
    leaves or reaches 0 at most one step later; :mod:`harness.scenes.trajectories`). At an event the acceleration jumps
    by ``Δẍ = |ẍ_slide(t_e, x_e, 0)|`` (the sliding branch's acceleration at rest): a late event leaves the
    velocity off by ``Δẍ δ`` — after a sticking only while MuJoCo still slides (``≤ δ``), after a breakaway for
    the whole slide ``T`` that follows, which moves the position by ``Δẍ δ T`` (the sliding force depends on time
    only, as in (3.80) with an applied force, so the offset neither grows nor decays). Semi-implicit Euler's own
    position error adds ``dt max|ẋ|``; its velocity error is second order (the input is held at the step's
    midpoint). So ``C = max(2 max Δẍ / s_v, (2 Σ_breakaways Δẍ T + max|ẋ|) / s_x)``, the positions' offsets summed
    over the breakaways as if they never cancelled."""
    h = _StickSlipDynamics(system, scene, event, "symbolic")
    ends = [e.time for e in ref.events[1:]] + [scene.horizon]
    jumps, drift = [0.0], 0.0
    for e, end in zip(ref.events, ends):
        direction = e.after if e.before == "stick" else e.before
        s = 1 if direction == "slide +" else -1
        x = float(np.interp(e.time, ref.t, ref.q[:, 0]))
        jump = abs(float(h.sliding(s)(e.time, np.array([x, 0.0]))[1]))
        jumps.append(jump)
        if e.before == "stick":
            drift += jump * (end - e.time)
    s_x = max(1.0, float(np.max(np.abs(ref.q))))
    s_v = max(1.0, float(np.max(np.abs(ref.qd))))
    return max(2 * max(jumps) / s_v, (2 * drift + float(np.max(np.abs(ref.qd)))) / s_x)


def mujoco_stick_slip(system, scene, event: StickSlip, dt: float) -> HybridTrajectory:
    """MuJoCo's own dry friction: joint ``frictionloss`` (flag on, stiff impedance), ``mu_H f_N`` at rest and
    ``mu_C f_N`` sliding, implicitfast integration at ``dt``."""
    dyn = sim.Dynamics(system, scene, "symbolic")
    mu_H, mu_C, f_N = event.values(dyn.params)
    tree = instantiate(dyn.system, dyn.params)
    mm = MujocoModel(tree, transforms=[
        Options(timestep=dt, integrator="implicitfast", enable=("frictionloss", "constraint"), noslip_iterations=10),
        DryFriction(event.coordinate, mu_H * f_N, (2 * dt, 1.0))], where="MjSpec.compile (dry friction scene)")
    joint = mm.address(event.coordinate)
    mm.set_joint(joint, scene.q0[0], scene.qd0[0])
    steps = int(round(scene.horizon / dt))
    every = max(1, steps // 200)
    events, moving = [], [abs(scene.qd0[0]) > 0]

    def switch(k):  # MuJoCo has one dry friction coefficient: mu_H f_N at rest, mu_C f_N sliding
        now_moving = abs(mm.joint_state(joint)[1]) > 1e-10
        if now_moving != moving[0]:
            events.append(Event(mm.time, "slide" if moving[0] else "stick", "slide" if now_moving else "stick"))
            moving[0] = now_moving
        mm.set_frictionloss(joint, (mu_C if moving[0] else mu_H) * f_N)
        mm.set_inputs(sim.held_inputs(scene, mm.actuators, k, dt))

    start = time.perf_counter()
    out = np.array(mm.rollout(steps, every, lambda k: (mm.time, *mm.joint_state(joint)), before=switch))
    energy = np.array([dyn.energy(np.array([a]), np.array([b])) for a, b in out[:, 1:]])
    return HybridTrajectory(f"mujoco (frictionloss, implicitfast, dt={dt:g})", out[:, 0], out[:, 1:2], out[:, 2:3],
                            time.perf_counter() - start, steps, energy, events=events)


# ----------------------------------------------------------------------------------------- rolling or slipping
def _rolling_model(system, scene, event: RollSlip, mu: float, dt: float):
    dyn = sim.Dynamics(system, scene, "symbolic")
    params = dyn.params
    rpy = tuple(value_at(a, params) for a in event.plane_rpy)
    tree = instantiate(dyn.system, params)
    mm = MujocoModel(tree, transforms=[
        Options(timestep=dt, integrator="implicitfast", enable=("contact", "constraint"), elliptic=True),
        ContactSphere(event.link, params[event.radius], rpy, mu, (2 * dt, 1.0))],
        where="MjSpec.compile (contact scene)")
    return mm, dyn


def mujoco_rolling(system, scene, event: RollSlip, dt: float, mu: float | None = None) -> HybridTrajectory:
    """The sphere on the plane in MuJoCo's contact; ``q`` is the rolling angle; the slip velocity
    ``ẋ − R ω`` is in ``notes['slip']`` over time."""
    mu = event.mu if mu is None else mu
    mm, dyn = _rolling_model(system, scene, event, mu, dt)
    slide, roll = mm.address(event.slide_joint), mm.address(event.roll_joint)
    R = dyn.params[event.radius]
    mm.set_joint(roll, scene.q0[0], scene.qd0[0])
    mm.set_joint(slide, R * scene.q0[0], R * scene.qd0[0])
    steps = int(round(scene.horizon / dt))
    every = max(1, steps // 200)

    def sample(k):
        (x, v), (_, slide_v) = mm.joint_state(roll), mm.joint_state(slide)
        return mm.time, x, v, slide_v - R * v

    start = time.perf_counter()
    out = np.array(mm.rollout(steps, every, sample))
    energy = np.array([dyn.energy(np.array([a]), np.array([b])) for a, b in out[:, 1:3]])
    tr = HybridTrajectory(f"mujoco (contact, mu={mu:.4g}, implicitfast, dt={dt:g})", out[:, 0], out[:, 1:2],
                          out[:, 2:3], time.perf_counter() - start, steps, energy)
    tr.notes["slip"] = out[:, 3]
    return tr


ROLLING_SLIP = 1e-6  # slip velocity at the end / the motion's velocity scale below which the sphere rolls
ROLLING = Bound("rolling criterion", ROLLING_SLIP, "the slip velocity at the end of a rolling scene relative to the "
                "motion's velocity scale (rolls())")
SLIPPING = Bound("slipping criterion", 1.0, "the rolling criterion 1e-6 relative to the measured slip of a slipping "
                 "scene: slipping makes the slip grow linearly in time")


def rolls(tr: HybridTrajectory, scale: float) -> bool:
    """Rolling: at the end of the scene the slip velocity is below 1e-6 of the motion's velocity scale (slipping
    makes it grow linearly in time; the first steps, while MuJoCo's soft contact builds up its force from zero
    penetration, may show a transient slip of ~1e-4 that rolling then removes)."""
    return abs(float(tr.notes["slip"][-1])) <= ROLLING_SLIP * scale


def mujoco_threshold(system, scene, event: RollSlip, dt: float, rel: float = 1e-3) -> float:
    """The smallest friction coefficient at which MuJoCo's sphere rolls, by bisection (to ``rel``)."""
    params = {**system.default_parameters(), **scene.params}
    predicted = event.predicted(params)
    lo, hi = 0.5 * predicted, 2.0 * predicted
    scale = float(np.max(np.abs(mujoco_rolling(system, scene, event, dt, hi).qd))) * params[event.radius]
    while hi - lo > rel * predicted:
        mid = 0.5 * (lo + hi)
        if rolls(mujoco_rolling(system, scene, event, dt, mid), scale):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


# ----------------------------------------------------------------------------------------- lift-off (A.15)
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
        self._map = sp.lambdify([q1, qd1, params], [to_free, J, J_dot], "numpy")
        self._G = sp.lambdify([q2, p2], height_gradient, "numpy")

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
             t_eval=None, catalogue=None) -> HybridTrajectory:
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
        events.append(Event(t1, "phase 1 (on the ground)", "phase 2 (lift-off)"))
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
    energy = np.array([h.two.energy(a, b) for a, b in zip(q, qd)])
    tr = HybridTrajectory(f"{source} ({method}, rtol={rtol:g}, lift-off)", np.array(ts), q, qd,
                          time.perf_counter() - start, nfev, energy, events=events)
    tr.notes["coordinates"] = [c.name for c in h.free_system.coordinates]
    return tr


def in_free_coordinates(system, scene, event: LiftOff, tr: sim.Trajectory, catalogue=None) -> sim.Trajectory:
    """A phase-1 trajectory expressed in phase-2 coordinates (to compare it with a lift-off reference)."""
    h = _LiftOffDynamics(system, scene, event, "symbolic", catalogue)
    mapped = [h.to_free(np.concatenate([a, b])) for a, b in zip(tr.q, tr.qd)]
    q = np.array([m[0] for m in mapped])
    qd = np.array([m[1] @ b for m, b in zip(mapped, tr.qd)])
    out = sim.Trajectory(tr.source, tr.t, q, qd, tr.seconds, tr.evaluations, tr.energy)
    out.notes.update(tr.notes)
    return out
