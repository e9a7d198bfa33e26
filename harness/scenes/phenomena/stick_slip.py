"""Stick-slip, Section 3.5.2, (3.80): a motion whose branches switch between sticking and sliding.

A mass on a rough surface sticks while the friction force it needs stays within ``mu_H f_N`` and ``ẋ = 0``
(3.80a), and slides with ``f_C = mu_C f_N sgn(ẋ)`` otherwise (3.80b). Our simulation (any source: symbolic,
Pinocchio, MuJoCo forward dynamics) integrates the sliding branch, the model's own friction force evaluated with the
branch's direction, and locates sticking where ``ẋ = 0`` with a ``solve_ivp`` event; stuck, the state is held and
nothing is integrated: the breakaway, where ``|f_required| = mu_H f_N``, is the first root of that guard in time
(:meth:`_StickSlipDynamics.breakaway`: a bound over the segment, else a scan and ``brentq``). Every breakaway is
checked against its prediction from the force sticking needs at the held position (:func:`sticking_phases`).
MuJoCo also simulates it with its own dry friction (joint ``frictionloss``, the flag switched on by the scene), its
value switched between ``mu_H f_N`` (at rest) and ``mu_C f_N`` (sliding) before every step, as MuJoCo has one
coefficient: a soft constraint solved once per step and stepped by a first-order method, its error first order in
``dt`` but not smooth in it (events fall on steps); its first-order constant is checked against ``C`` derived from
the events' acceleration jumps (:func:`frictionloss_bound`), its events within ``3 dt`` (:data:`STEP_EVENT`).
Event tolerances shared with every switching motion: :mod:`harness.scenes.base`.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from harness.checks import Bound
from harness.engines import simulating
from harness.engines.base import evaluated_loads, load_functions
from harness.engines.mujoco_engine import DryFriction, MujocoModel, Options
from harness.errors import ModelError
from harness.export.numeric import instantiate
from harness.modeling.events import StickSlip
from harness.modeling.system import BodyTorque, PointForce
from harness.scenes import simulate as sim
from harness.scenes.base import EVENT, MUJOCO_SOFT, MUJOCO_SOFT_TOL, SceneRun, event_error
from harness.scenes.phenomena.switching import Switching

STEP_EVENT = Bound("MuJoCo step event", 3.0, "an event of MuJoCo's own dry friction against the reference, in time "
                   "steps: a breakaway is seen ½ to 3/2 steps late (the input is held at the step's midpoint), a "
                   "sticking or a reversal at most 1 step late (seen at the step where the velocity reaches 0 or "
                   "changes its sign): δ ≤ 3/2 dt, and 3/2 steps of room for the trajectory's own first-order "
                   "error, which shifts a velocity zero (measured from dt to dt/8 on stick_slip, friction "
                   "oscillators with a linear, a hardening and a damped spring, one forced, one under a constant "
                   "load, and a pendulum with bearing friction: breakaways 0.27 steps early to 1.44 late, stickings "
                   "and reversals 0.18 early to 1.85 late)",
                   derived=True)
FRICTIONLOSS = Bound("frictionloss first-order constant", 1.0, "error / dt of MuJoCo's dry friction at dt and dt/2 "
                     "against C, derived from the events' acceleration jumps and the step's quantization "
                     "(stick_slip.frictionloss_bound)", derived=True)
_TINY = 1e-300                                      # a velocity with a sign and no size


def _mode_name(mode: int) -> str:
    return {0: "stick", 1: "slide +", -1: "slide -"}[mode]


class _StickSlipDynamics:
    """The branches of (3.80) on top of one source's forward dynamics (one coordinate)."""

    def __init__(self, system, scene, event: StickSlip, source: str):
        if len(system.coordinates) != 1:
            raise ModelError(f"{system.name}: stick-slip switching is implemented for one coordinate")
        self.dyn = sim.Dynamics(system, scene, source)
        self.mu_H, self.mu_C, self.f_N = event.values(self.dyn.params)
        self.affine = affine_in_inputs(self.dyn.system)

    def required_force(self, t, q) -> float:
        """The friction force sticking needs: ``M q̈_free`` with the friction at ``ẋ = 0`` (sgn 0 = 0)."""
        return self.required_force_at(q, self.dyn.scene.u(t, self.dyn.system))

    def required_force_at(self, q, u) -> float:
        """:meth:`required_force` at the inputs ``u``."""
        zero = np.zeros(1)
        self.dyn.evaluations += 1
        return float(self.dyn.c("M", q, zero, self.dyn.p, u)[0, 0] * self.dyn.at(u, q, zero)[0])

    def breakaway(self, t0: float, end: float, q) -> tuple[float | None, int]:
        """The first time in ``(t0, end]`` the force sticking needs at the held position ``q`` rises through
        ``mu_H f_N`` (3.80a), or None; with the forward-dynamics calls it took. At rest the state does not change,
        so the guard is a function of time through the inputs alone. Where the model's generalized forces are
        affine in the inputs (:func:`affine_in_inputs`), the force is ``a + b u(t)``, ``a`` and ``b`` from
        ``1 + len(u)`` calls: then a bound over the segment, ``|a| + Σ |b_i| sup |u_i|`` within ``mu_H f_N``
        (:func:`harness.scenes.effects.affine_bound`, the inference's), proves that it sticks to ``end``, and
        otherwise the guard is scanned on steps of ``horizon / 500`` (the resolution the event-located stick branch
        had) and its first upward crossing refined by ``brentq``; elsewhere each point of the scan is a call. A force
        already beyond ``mu_H f_N`` at ``t0`` (exactly, one call: an input's jump at a breakpoint) breaks away at
        ``t0``."""
        from harness.scenes.effects import affine_bound

        dyn, limit = self.dyn, self.mu_H * self.f_N
        scene, system = dyn.scene, dyn.system
        if abs(self.required_force(t0, q)) > limit:  # already beyond (an input's jump at a breakpoint): slides now
            return t0, 1
        calls = 1
        if self.affine:
            n = len(system.inputs)
            a = self.required_force_at(q, np.zeros(n))
            b = np.array([self.required_force_at(q, np.eye(n)[i]) - a for i in range(n)])
            calls += 1 + n
            bound = affine_bound(a, b, [i.name for i in system.inputs], scene)
            if bound is not None and bound <= limit:  # sticks while |f| ≤ mu_H f_N (3.80a)
                return None, calls

            def guard(t):
                return abs(a + float(b @ scene.u(t, system))) - limit
        else:
            def guard(t):
                nonlocal calls
                calls += 1
                return abs(self.required_force(t, q)) - limit
        step = scene.horizon / 500
        times = np.append(np.arange(t0, end, step), end)
        before = guard(times[0])
        for lo, hi in zip(times[:-1], times[1:]):
            after = guard(hi)
            if before <= 0 < after:
                return brentq(guard, lo, hi, xtol=4 * np.finfo(float).eps, rtol=4 * np.finfo(float).eps), calls
            before = after
        return None, calls

    def sliding(self, s: int):
        def rhs(t, y):
            qd = y[1:] if y[1] * s > 0 else np.array([s * _TINY])   # the branch's direction at ẋ = 0
            return np.concatenate([y[1:], self.dyn(t, y[:1], qd)])
        return rhs

    def next_mode(self, t, y) -> int:
        force = self.required_force(t, y[:1])
        return 0 if abs(force) <= self.mu_H * self.f_N else int(np.sign(force))


_AFFINE: dict = {}


def affine_in_inputs(system) -> bool:
    """Whether the generalized forces ``f_np`` of ``system`` are affine in its inputs (every second derivative in
    them 0, on the derived expressions): then so is the force sticking needs, ``M q̈`` at ``q̇ = 0``."""
    from harness.derivation.derive import derive

    key = system.fingerprint()
    if key not in _AFFINE:
        u = [i.symbol for i in system.inputs]
        f = derive(system).f_np
        _AFFINE[key] = all(sp.diff(e, x, y) == 0 for e in f for x in u for y in u)
    return _AFFINE[key]


def stick_slip(system, scene, event: StickSlip, source: str, method="DOP853", rtol=1e-12, atol=1e-12,
               t_eval=None, catalogue=None) -> sim.HybridTrajectory:
    """Event-located simulation of (3.80) with ``source``'s forward dynamics (``catalogue``: unused, as for
    every switching simulation that stays in its system)."""
    t_eval = sim.sample_times(scene) if t_eval is None else t_eval
    y = np.concatenate([scene.q0, scene.qd0]).astype(float)
    if event.held:  # proved to stick from rest throughout (3.80a): ẋ = 0, ẍ = 0, no breakaway to look for and no
        if y[1] != 0:  # model of the source to make (its energy, E of our model, only where it is read)
            raise ModelError(f"{scene.name}: a held friction needs the scene to start at rest (ẋ(0) = {y[1]:g})")
        start = time.perf_counter()
        q = np.full((len(t_eval), 1), y[0])
        return sim.HybridTrajectory(f"{source} (held: sticks throughout)", t_eval.copy(), q, np.zeros_like(q),
                                    time.perf_counter() - start, 0,
                                    energy_of=lambda a, b: sim.Dynamics(system, scene, "symbolic").energy(a, b))
    h = _StickSlipDynamics(system, scene, event, source)
    mode = int(np.sign(y[1])) if y[1] != 0 else h.next_mode(0.0, y)
    edges = [*scene.breakpoints, scene.horizon]
    ts, ys, events, t, nfev = [], [], [], 0.0, 0
    start = time.perf_counter()
    while t < scene.horizon:
        end = next(e for e in edges if e > t)
        if mode == 0:  # stuck: ẋ = 0, ẍ = 0 (3.80a), nothing to integrate; the state held until the breakaway
            t_break, calls = h.breakaway(t, end, y[:1])
            nfev += calls
            stop = end if t_break is None else t_break
            inside = t_eval[(t_eval >= t) & (t_eval <= stop) & (t_eval > _last(ts))]
            ts.append(inside)
            ys.append(np.repeat(y[:, None], len(inside), axis=1))
            if t_break is None:
                t = end
                continue
            t, new = t_break, int(np.sign(h.required_force(t_break, y[:1])))
            events.append(sim.Event(t, _mode_name(mode), _mode_name(new)))
            mode = new
            continue
        rhs = h.sliding(mode)
        ev = lambda t_, y_: y_[1]  # noqa: E731 - the mass comes to rest
        ev.direction = -float(mode)
        ev.terminal = True
        inside = t_eval[(t_eval >= t) & (t_eval <= end)]
        sol = solve_ivp(rhs, (t, end), y, method=method, rtol=rtol, atol=atol, t_eval=inside, events=ev,
                        dense_output=True)
        if sol.status < 0:
            raise RuntimeError(f"{scene.name}: integration failed at t={t:g}: {sol.message}")
        nfev += sol.nfev
        keep = sol.t > _last(ts)
        ts.append(sol.t[keep])
        ys.append(sol.y[:, keep])
        if sol.status == 1:
            t, y = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
            new = h.next_mode(t, y)
            if new == 0:
                y[1] = 0.0
            events.append(sim.Event(t, _mode_name(mode), _mode_name(new)))
            mode = new
        else:
            t, y = end, sol.sol(end)
    y_all = np.concatenate(ys, axis=1)
    dyn = h.dyn
    return sim.HybridTrajectory(f"{source} ({method}, rtol={rtol:g}, events)", np.concatenate(ts), y_all[:1].T,
                                y_all[1:].T, time.perf_counter() - start, nfev, energy_of=dyn.energy, events=events)


def _last(ts: list) -> float:
    """The last sample time kept so far (-1 before the first)."""
    return max((float(x[-1]) for x in ts if len(x)), default=-1.0)


def needed_force(system, scene):
    """``f(q, u)``: the force sticking needs at ``q`` and the inputs ``u``, ``f_np − g`` at ``q̇ = 0`` (the balance
    (5.93) with ``q̈ = 0``, the sliding friction 0 at ``q̇ = 0``) from the derived terms: the applied input ``f_e``
    in the lecture's (3.80a), whatever else acts at rest (a spring, a slope) in another system."""
    dyn = sim.Dynamics(system, scene, "symbolic")
    zero = np.zeros(1)

    def force(q, u) -> float:
        _, _, g, f_np = dyn.c.terms(np.asarray(q, dtype=float), zero, dyn.p, u)
        return float(f_np[0] - g[0])
    return force


def predicted_breakaway(system, scene, event: StickSlip, start: float = 0.0, q=None, force=None) -> float:
    """The first time after ``start`` the force sticking needs at the held position ``q`` (the scene's start by
    default; :func:`needed_force`) reaches ``mu_H f_N`` (3.80a), found on a grid of ``horizon / 20000`` and refined
    by root-finding, apart from the simulation's own guard (:meth:`_StickSlipDynamics.breakaway`); inf: none."""
    params = {**system.default_parameters(), **scene.params}
    mu_H, _, f_N = event.values(params)
    force = needed_force(system, scene) if force is None else force
    q = scene.q0 if q is None else q
    excess = lambda t: abs(force(q, scene.u(t, system))) - mu_H * f_N  # noqa: E731
    grid = np.linspace(0.0, scene.horizon, 20001)
    grid = np.concatenate([[start], grid[grid > start]])
    above = next((k for k, t in enumerate(grid) if excess(t) > 0), None)
    if above is None:
        return math.inf
    return float(grid[0]) if above == 0 else brentq(excess, grid[above - 1], grid[above], xtol=1e-14)


def sticking_phases(system, scene, event: StickSlip, ref: sim.HybridTrajectory) -> list[tuple[float, float, float]]:
    """``(start, found, predicted)`` for each phase ``ref`` sticks in: from the start where it starts at rest with a
    force within ``mu_H f_N``, and from each sticking; ``found`` the breakaway ``ref`` found (inf: none),
    ``predicted`` :func:`predicted_breakaway` at the held position (a sample inside the phase, where the state is
    held; a phase between two samples is not predicted)."""
    params = {**system.default_parameters(), **scene.params}
    mu_H, _, f_N = event.values(params)
    force, starts = needed_force(system, scene), [e.time for e in ref.events if e.after == "stick"]
    if scene.qd0[0] == 0 and abs(force(scene.q0, scene.u(0.0, system))) <= mu_H * f_N:
        starts.insert(0, 0.0)
    phases = []
    for start in starts:
        found = next((e.time for e in ref.events if e.time > start and e.before == "stick"), math.inf)
        inside = (ref.t >= start) & (ref.t < found)
        if inside.any():
            held = ref.q[np.argmax(inside)]
            phases.append((start, found, predicted_breakaway(system, scene, event, start, held, force)))
    return phases


UNBOUNDED = ("not checked: its bound (stick_slip.frictionloss_bound) is derived for a sliding force of time alone or "
             "of a linear spring and damper (ẍ = a(t) − k x − c ẋ with constant k, c ≥ 0), whose offsets never grow; "
             "along this reference ∂ẍ/∂x or ∂ẍ/∂ẋ is not such a constant")


def frictionloss_bound(system, scene, event: StickSlip, ref: sim.HybridTrajectory) -> float | None:
    """``C`` of the first-order bound ``error ≤ C dt`` of MuJoCo's frictionloss run against the event-located
    reference ``ref`` (errors relative to each component's scale ``max(1, max|y|)``, as :func:`simulate.max_error`).

    MuJoCo's events are late by ``0 < δ ≤ 2 dt`` (the event falls anywhere within a step, and MuJoCo's velocity
    leaves or reaches 0 at most one step later; :mod:`harness.scenes.trajectories`). At an event the acceleration jumps
    by ``Δẍ = |ẍ_slide(t_e, x_e, 0)|`` (the sliding branch's acceleration at rest): a late event leaves the
    velocity off by ``Δẍ δ`` — after a sticking only while MuJoCo still slides (``≤ δ``), after a breakaway or a
    reversal for the whole slide ``T`` that follows, which moves the position by at most ``Δẍ δ T``: the sliding
    branch is ``ẍ = a(t) − k x − c ẋ`` with constant ``k ≥ 0``, ``c ≥ 0`` (:func:`sliding_linearization`: a force of
    time alone, as in (3.80) with an applied force, ``k = c = 0``, or a linear spring and damper), whose offsets
    never grow (their energy ``δẋ²/2 + k δx²/2`` does not), so ``|δẋ| ≤ Δẍ δ`` and ``|δx| ≤ Δẍ δ T``.
    Semi-implicit Euler's own position error adds ``dt max|ẋ|``; its velocity error is second order where
    ``k = 0`` (the input is held at the step's midpoint), and with ``k > 0`` its invariant ellipse is tilted,
    ``δẋ = dt k |x − x_eq| / 2 = dt |ẍ| / 2`` (its position error ``dt ω A / 2`` within ``dt max|ẋ|``). So
    ``C = max((2 max Δẍ + [k > 0] max|ẍ| / 2) / s_v, (2 Σ Δẍ T + max|ẋ|) / s_x)``, the positions' offsets summed
    over the breakaways and reversals as if they never cancelled. Another sliding branch (a stiffness that changes
    or is negative, a pendulum's gravity) has no bound: None (:data:`UNBOUNDED`)."""
    h = _StickSlipDynamics(system, scene, event, "symbolic")
    k, c = sliding_linearization(h, ref)
    if k < 0 or c < 0:
        return None
    ends = [e.time for e in ref.events[1:]] + [scene.horizon]
    jumps, drift = [0.0], 0.0
    for e, end in zip(ref.events, ends):
        direction = e.after if e.before == "stick" else e.before
        s = 1 if direction == "slide +" else -1
        x = float(np.interp(e.time, ref.t, ref.q[:, 0]))
        jump = abs(float(h.sliding(s)(e.time, np.array([x, 0.0]))[1]))
        jumps.append(jump)
        if e.after != "stick":  # a slide follows: a breakaway, or a reversal through rest
            drift += jump * (end - e.time)
    tilt = 0.0
    if k > 0:  # the largest sliding acceleration, each sample on its own branch
        tilt = max(abs(float(h.sliding(int(np.sign(v)))(t, np.array([x, v]))[1]))
                   for t, x, v in zip(ref.t, ref.q[:, 0], ref.qd[:, 0]) if v != 0) / 2
    s_x = max(1.0, float(np.max(np.abs(ref.q))))
    s_v = max(1.0, float(np.max(np.abs(ref.qd))))
    return max((2 * max(jumps) + tilt) / s_v, (2 * drift + float(np.max(np.abs(ref.qd)))) / s_x)


def sliding_linearization(h: _StickSlipDynamics, ref: sim.HybridTrajectory) -> tuple[float, float]:
    """``(k, c)`` of the sliding branches ``ẍ = a(t) − k x − c ẋ`` along ``ref`` (central differences at its
    samples that slide, each on its own branch); ``(-1, -1)`` where they are not the same constants at every sample
    (to ``1e-6`` of the largest, relative, and ``1e-9`` absolute)."""
    ks, cs = [], []
    for t, x, v in zip(ref.t, ref.q[:, 0], ref.qd[:, 0]):
        if v == 0:
            continue
        rhs, dx, dv = h.sliding(int(np.sign(v))), 1e-6 * max(1.0, abs(x)), 1e-6 * abs(v)
        ks.append(-(rhs(t, np.array([x + dx, v]))[1] - rhs(t, np.array([x - dx, v]))[1]) / (2 * dx))
        cs.append(-(rhs(t, np.array([x, v + dv]))[1] - rhs(t, np.array([x, v - dv]))[1]) / (2 * dv))
    out = []
    for values in (ks, cs):
        values = np.array(values or [0.0])
        size = float(np.max(np.abs(values)))
        out.append(float(np.median(values)) if np.ptp(values) <= max(1e-9, 1e-6 * size) else -1.0)
    return out[0], out[1]


class _Rest:
    """Sticking and sliding of MuJoCo's run, read before each step, as (3.80) reads them: at rest where MuJoCo's dry
    friction held the joint over the last step (:meth:`MujocoModel.friction_holds`: its force within the limit) or
    the velocity changed its sign (the mass passed through rest within the step, as a mass whose spring pulls it
    back with a force between ``mu_C f_N`` and ``mu_H f_N``: with ``mu_C f_N`` it would creep on), ``mu_H f_N`` for
    the next step, where MuJoCo's friction either holds it (sticking) or does not (a reversal: the mass slides on the
    other way). An event is recorded when seen: a sticking or a reversal at the step the mass was seen at rest, a
    breakaway at the step it moves again; the mode after the first step is the initial one, as the reference takes
    its mode at ``t = 0`` without an event."""

    def __init__(self, moving: bool):
        self.moving, self.velocity, self.passing = moving, 0.0, None

    def step(self, k: int, t: float, velocity: float, holds: bool, events: list) -> None:
        if k == 0:   # no step yet
            return
        moving = not holds
        if self.passing is not None:  # seen at rest after a slide, under mu_H f_N over the last step: held or not
            events.append(sim.Event(self.passing, "slide", "slide" if moving else "stick"))
            self.passing = None
        elif self.moving and (not moving or velocity * self.velocity < 0):
            self.passing, moving = t, False   # at rest: the next step decides
        elif moving and not self.moving and k > 1:
            events.append(sim.Event(t, "stick", "slide"))
        self.moving, self.velocity = moving, velocity


def other_loads(system, event: StickSlip):
    """The external loads of ``system`` (:func:`~harness.engines.base.load_functions`) but its sliding friction, the
    force element(s) in whose expression ``mu_C`` appears (none where the scene leaves it out as idle), which
    MuJoCo's own run replaces by ``frictionloss``."""
    def friction(f) -> bool:
        vector = f.force if isinstance(f, PointForce) else f.torque if isinstance(f, BodyTorque) else ()
        return any(s.name == event.mu_C for s in sp.Matrix(vector).free_symbols)
    return load_functions(dataclasses.replace(system, forces=tuple(f for f in system.forces if not friction(f))))


def mujoco_stick_slip(system, scene, event: StickSlip, dt: float) -> sim.HybridTrajectory:
    """MuJoCo's own dry friction: joint ``frictionloss`` (flag on, stiff impedance), ``mu_H f_N`` at rest and
    ``mu_C f_N`` sliding, implicitfast integration at ``dt``; the model's other external loads (:func:`other_loads`)
    applied at each step's kinematics."""
    dyn = sim.Dynamics(system, scene, "symbolic")
    mu_H, mu_C, f_N = event.values(dyn.params)
    loads = other_loads(dyn.system, event)
    tree = instantiate(dyn.system, dyn.params)
    mm = MujocoModel(tree, transforms=[
        Options(timestep=dt, integrator="implicitfast", enable=("frictionloss", "constraint"), noslip_iterations=10),
        DryFriction(event.coordinate, mu_H * f_N, (2 * dt, 1.0))], where="MjSpec.compile (dry friction scene)")
    joint = mm.address(event.coordinate)
    mm.set_joint(joint, scene.q0[0], scene.qd0[0])
    steps = int(round(scene.horizon / dt))
    every = max(1, steps // 200)
    events, rest = [], _Rest(abs(scene.qd0[0]) > 0)

    def switch(k):  # MuJoCo has one dry friction coefficient: mu_H f_N at rest, mu_C f_N sliding
        rest.step(k, mm.time, mm.joint_state(joint)[1], mm.friction_holds(joint), events)
        mm.set_frictionloss(joint, (mu_C if rest.moving else mu_H) * f_N)
        mm.set_inputs(sim.held_inputs(scene, mm.actuators, k, dt))

    def between(k):  # the other loads at the step's kinematics, the inputs held over the step
        x, v = mm.joint_state(joint)
        u = np.array(list(sim.held_inputs(scene, dyn.input_names, k, dt).values()))
        mm.apply_loads(evaluated_loads(loads, np.array([x]), np.array([v]), dyn.p, u))

    start = time.perf_counter()
    out = np.array(mm.rollout(steps, every, lambda k: (mm.time, *mm.joint_state(joint)), before=switch,
                              between=between if loads.entries else None))
    return sim.HybridTrajectory(f"mujoco (frictionloss, implicitfast, dt={dt:g})", out[:, 0], out[:, 1:2], out[:, 2:3],
                                time.perf_counter() - start, steps, energy_of=dyn.energy, events=events)


class StickSlipMotion(Switching):
    name = "stick-slip (3.80)"
    event = StickSlip

    def branches(self, system, scene, event, source, **kw) -> sim.HybridTrajectory:
        return stick_slip(system, scene, event, source, **kw)

    @staticmethod
    def mujoco_run(system, scene, event, dt):
        return mujoco_stick_slip(system, scene, event, dt)

    def tree_view(self, run: SceneRun):
        return None     # a stick-slip system is one coordinate: no constrained tree

    def check(self, run: SceneRun) -> None:
        """The checks of every switching motion, then (3.80a)'s breakaway of each sticking phase where the force
        sticking needs reaches mu_H f_N (none predicted: none found; :func:`sticking_phases`), and MuJoCo's own dry
        friction: its first-order constant against ``C`` of the events' jumps and the sliding (a note where
        :func:`frictionloss_bound` has none), or, held throughout (``C = 0``: only round-off is left), its error
        within MuJoCo's soft-constraint tolerance."""
        super().check(run)
        system, scene, event, result, ref = run.system, run.scene, run.event, run.result, run.reference
        phases = sticking_phases(system, scene, event, ref)
        errors = [0.0 if found == predicted == math.inf else abs(found - predicted) for _, found, predicted in phases]
        predicted = sum(p < math.inf for *_, p in phases)
        result.add(EVENT.check("breakaways where |f| = mu_H f_N (3.80a), s", "symbolic", max(errors, default=0.0),
                               detail=f"{len(phases)} sticking phases, {predicted} breakaways predicted from the "
                                      "force sticking needs at the held position"))
        if simulating(run.engines, "dry friction"):
            dt = scene.horizon / sim.grid_steps(scene, 4000)
            if ref.events or np.any(ref.qd):  # C from the events' jumps and the sliding
                bound = frictionloss_bound(system, scene, event, ref)
                if bound is None:
                    fine = mujoco_stick_slip(system, scene, event, dt / 2)
                    result.notes["MuJoCo frictionloss first-order constant"] = UNBOUNDED
                else:
                    coarse, fine = (mujoco_stick_slip(system, scene, event, h) for h in (dt, dt / 2))
                    constant = max(sim.max_error(coarse, ref) / dt, sim.max_error(fine, ref) / (dt / 2))
                    result.add(FRICTIONLOSS.check("MuJoCo frictionloss first-order constant error / dt at dt, dt/2, "
                                                  "1/s", "mujoco", constant, scale=bound,
                                                  detail=f"C = {bound:.3g} 1/s"))
                    result.notes["MuJoCo frictionloss: dt where C dt = MUJOCO_SOFT_TOL"] = MUJOCO_SOFT_TOL / bound
            else:  # held throughout: no jump, no slide, C = 0: MuJoCo must hold the reference to its soft tolerance
                fine = mujoco_stick_slip(system, scene, event, dt / 2)
                result.add(MUJOCO_SOFT.check("MuJoCo frictionloss without a switch: error", "mujoco",
                                             sim.max_error(fine, ref), detail=f"dt={dt / 2:g}"))
            result.trajectories["mujoco frictionloss"] = fine
            result.add(STEP_EVENT.check("MuJoCo frictionloss event times, s", "mujoco",
                                        event_error(fine, ref, kinds=False), scale=dt / 2, detail=f"dt={dt / 2:g}"))


PLUGIN = StickSlipMotion()
