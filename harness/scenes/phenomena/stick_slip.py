"""Stick-slip, Section 3.5.2, (3.80): a motion whose branches switch between sticking and sliding.

A mass on a rough surface sticks while the friction force it needs stays within ``mu_H f_N`` and ``ẋ = 0``
(3.80a), and slides with ``f_C = mu_C f_N sgn(ẋ)`` otherwise (3.80b). Our simulation (any source: symbolic,
Pinocchio, MuJoCo forward dynamics) integrates the sliding branch, the model's own friction force evaluated with the
branch's direction, and locates sticking where ``ẋ = 0`` with a ``solve_ivp`` event; stuck, the state is held and
nothing is integrated: the breakaway, where ``|f_required| = mu_H f_N``, is the first root of that guard in time
(:meth:`_StickSlipDynamics.breakaway`: a bound over the segment, else a scan and ``brentq``). The breakaway is
checked against its prediction from the input alone.
MuJoCo also simulates it with its own dry friction (joint ``frictionloss``, the flag switched on by the scene), its
value switched between ``mu_H f_N`` (at rest) and ``mu_C f_N`` (sliding) before every step, as MuJoCo has one
coefficient: a soft constraint solved once per step and stepped by a first-order method, its error first order in
``dt`` but not smooth in it (events fall on steps); its first-order constant is checked against ``C`` derived from
the events' acceleration jumps (:func:`frictionloss_bound`), its events within ``3 dt`` (:data:`STEP_EVENT`).
Event tolerances shared with every switching motion: :mod:`harness.scenes.base`.
"""

from __future__ import annotations

import math
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from harness.checks import Bound
from harness.engines import simulating
from harness.engines.mujoco_engine import DryFriction, MujocoModel, Options
from harness.errors import ModelError
from harness.export.numeric import instantiate
from harness.modeling.events import StickSlip
from harness.scenes import simulate as sim
from harness.scenes.base import EVENT, MUJOCO_SOFT, MUJOCO_SOFT_TOL, SceneRun, event_error
from harness.scenes.phenomena.switching import Switching

STEP_EVENT = Bound("MuJoCo step event", 3.0, "an event of MuJoCo's own dry friction against the reference, in time "
                   "steps: a breakaway is seen ½ to 3/2 steps late (the input is held at the step's midpoint), a "
                   "sticking 1 to 2 steps late (MuJoCo's velocity reaches 0 a step after the crossing), the "
                   "trajectory's own error shifts them by ≤ 0.01 dt: δ ≤ 2 dt, and a third step of room",
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


def frictionloss_bound(system, scene, event: StickSlip, ref: sim.HybridTrajectory) -> float:
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


def mujoco_stick_slip(system, scene, event: StickSlip, dt: float) -> sim.HybridTrajectory:
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
            events.append(sim.Event(mm.time, "slide" if moving[0] else "stick", "slide" if now_moving else "stick"))
            moving[0] = now_moving
        mm.set_frictionloss(joint, (mu_C if moving[0] else mu_H) * f_N)
        mm.set_inputs(sim.held_inputs(scene, mm.actuators, k, dt))

    start = time.perf_counter()
    out = np.array(mm.rollout(steps, every, lambda k: (mm.time, *mm.joint_state(joint)), before=switch))
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
        """The checks of every switching motion, then (3.80)'s breakaway where |f_e| = mu_H f_N (none predicted: none
        found), and MuJoCo's own dry friction: its first-order constant against ``C`` of the events' jumps, or,
        without an event (``C = 0``: only round-off is left), its error within MuJoCo's soft-constraint tolerance."""
        super().check(run)
        system, scene, event, result, ref = run.system, run.scene, run.event, run.result, run.reference
        predicted = predicted_breakaway(system, scene, event)
        found = ref.events[0].time if ref.events else math.inf
        result.add(EVENT.check("breakaway where |f_e| = mu_H f_N (3.80), s", "symbolic",
                               0.0 if found == predicted == math.inf else abs(found - predicted),
                               detail="none predicted, none found" if found == predicted == math.inf else ""))
        if simulating(run.engines, "dry friction"):
            dt = scene.horizon / sim.grid_steps(scene, 4000)
            if ref.events:
                bound = frictionloss_bound(system, scene, event, ref)
                coarse, fine = (mujoco_stick_slip(system, scene, event, h) for h in (dt, dt / 2))
                constant = max(sim.max_error(coarse, ref) / dt, sim.max_error(fine, ref) / (dt / 2))
                result.add(FRICTIONLOSS.check("MuJoCo frictionloss first-order constant error / dt at dt, dt/2, 1/s",
                                              "mujoco", constant, scale=bound, detail=f"C = {bound:.3g} 1/s"))
                result.notes["MuJoCo frictionloss: dt where C dt = MUJOCO_SOFT_TOL"] = MUJOCO_SOFT_TOL / bound
            else:  # no switching: the events' jumps give C = 0, MuJoCo must hold the reference to its soft tolerance
                fine = mujoco_stick_slip(system, scene, event, dt / 2)
                result.add(MUJOCO_SOFT.check("MuJoCo frictionloss without a switch: error", "mujoco",
                                             sim.max_error(fine, ref), detail=f"dt={dt / 2:g}"))
            result.trajectories["mujoco frictionloss"] = fine
            result.add(STEP_EVENT.check("MuJoCo frictionloss event times, s", "mujoco",
                                        event_error(fine, ref, kinds=False), scale=dt / 2, detail=f"dt={dt / 2:g}"))


PLUGIN = StickSlipMotion()
