"""What every phenomenon of a scene shares: the run's context and record, the tolerances and their reasons.

A scene is checked by :func:`harness.scenes.trajectories.run_scene`, a loop over the plug-ins of
:mod:`harness.scenes.phenomena` (one module each: the smooth motion, stick-slip, lift-off, rolling contact, closed
chains, the energy balance, pruning). Each reads and adds to one :class:`SceneRun`. The tolerances (one place):

* **reference**: our symbolic model, DOP853 at ``rtol = 1e-12``, ``atol = 1e-14`` (its global error, against
  DOP853 at 2.3e-14: 6e-11 at most over the catalogue), confirmed by LSODA at ``rtol = atol = 1e-13``
  (``CONFIRMATION_RTOL``; Adams/BDF multistep: another family than Runge-Kutta; scipy's ``odeint``, its stepping
  in Fortran, for scenes without events; its global error 4.4e-10 at most, series_rlc's lc_ring, where at
  ``1e-12`` it was 2.9e-9; Radau agrees as well but costs 10-30x more): they must agree to
  ``REFERENCE_TOL = 1e-8`` of the state's scale (global error of both, grown over the horizon; scenes are
  chosen non-chaotic over it). The difference is the sum of the two global errors: ≤ 0.05 ``REFERENCE_TOL``.
* **engines**: Pinocchio's and MuJoCo's forward dynamics integrated by DOP853 at ``rtol = atol = 1e-10``
  must stay within ``ENGINE_TOL = 1e-6`` of the reference: the per-step tolerance 1e-10 grows over a few
  hundred steps and a few periods by at most ~1e4 for the (non-chaotic) scenes.
* **MuJoCo's own RK4** (``mj_step``, where the map is the identity and no external load is applied): its
  global error is ``C dt⁴``. A coarse run (``RK4_START`` steps on the grid of :func:`simulate.grid_steps`)
  measures ``C``; the pair ``dt``, ``dt/2`` is taken where the predicted error at ``dt/2`` is ``RK4_TARGET = 1e-8``
  (ENGINE_TOL / 100, and ≥ 100 x the reference's own error, so the ratio is not read off round-off). Checked:
  the error at ``dt/2`` within ``ENGINE_TOL``, and the observed order ``p̂ = log2(error(dt) / error(dt/2))`` at
  least 3: recorded as its deficit ``4 − p̂ ≤ 1`` (a lower bound on the order as an upper bound, so that the
  margin shows: 0 in the asymptotic regime; errors below 1e-10 have no order). MuJoCo holds ``ctrl`` over a
  step, at the step's midpoint (:func:`simulate.held_inputs`): with an input that varies within steps the error
  is ``O(dt²)`` (the midpoint rule), reported, not bounded, with the deficit ``2 − p̂ ≤ 1``.
* **invariants**: a conservative scene keeps ``E = T + V`` within ``INVARIANT_TOL = 1e-8`` of its scale;
  otherwise the power balance ``E(t) − E(0) = ∫ q̇ᵀ f_np dt`` (3.101) holds to the same tolerance.
* **pruning**: the scene run with every effect of the system present but idle (multiplied by a parameter
  set to 0, :func:`harness.modeling.scenes.idle`) gives the same trajectory (``ENGINE_TOL``); the time ratio
  idle/pruned of our symbolic simulation is reported for every scene.
* **structural changes** (stick-slip, rolling or slipping; :mod:`harness.scenes.phenomena.stick_slip`,
  ``rolling`` and ``lift_off`` state theirs): event times against their prediction and between sources. MuJoCo's own contact and its
  equality constraints for closed chains and couplings (:mod:`harness.scenes.phenomena.closures`) are soft constraints
  (``solref = 2 dt``) stepped by implicitfast, a first-order method: the error is ``K dt + K₂ dt² + O(dt³)``
  (``K`` reported; over the catalogue 0.4 to 48 per second, the error halving with ``dt`` to 1%). Runs at ``dt``
  and ``dt/2`` are extrapolated to ``dt → 0`` (Richardson, ``2 y(dt/2) − y(dt)``), which must be within
  ``MUJOCO_SOFT_TOL = 1e-3`` of the reference: ``dt`` (on the grid of :func:`simulate.grid_steps`, so input
  jumps fall on steps) is halved, reusing the finer runs, until the extrapolated error is within
  ``SOFT_MARGIN = 0.1`` of it and the order below within its slack (at most ``SOFT_REFINEMENTS = 6`` times);
  from three runs on, the extrapolation is Romberg's, ``(8 y(dt/4) − 6 y(dt/2) + y(dt)) / 3``, which cancels the
  ``K₂ dt²`` term too. Where ``K`` is large that term dominates Richardson's residual: a user's four-bar linkage
  swinging under gravity (``K`` ≈ 1500 per second) had Richardson's residual at 1.4e-2 after three halvings and
  at 1.0e-3 after six, Romberg's at 9.7e-5. The first-order model the extrapolation rests on is checked on the
  last pair: ``|log2(error(dt) / error(dt/2)) − 1| ≤ 0.2``. MuJoCo's dry friction (frictionloss) switches at events
  that fall on steps: its error is first order but not smooth in ``dt`` (no extrapolation); its first-order constant
  ``error / dt`` at ``dt`` and ``dt/2`` must stay within ``C`` derived from the events' acceleration jumps
  (:func:`harness.scenes.phenomena.stick_slip.frictionloss_bound`), and its event times within ``3 dt``: an event
  falls anywhere within a step and MuJoCo's velocity leaves 0 (breakaway: the input is held at the step's midpoint,
  so ``½ < δ/dt ≤ 3/2``) or is seen at rest where it reaches 0 or changes its sign (sticking, reversal:
  ``0 < δ/dt ≤ 1``), ``δ ≤ 3/2 dt``; the trajectory's own first-order error shifts a velocity zero by
  ``error / |ẍ|``, for which the rest of the ``3 dt`` leaves room (measured from ``dt`` to ``dt/8`` on stick_slip,
  five friction oscillators and a pendulum with bearing friction: breakaways 0.27 steps early to 1.44 late,
  stickings and reversals 0.18 early to 1.85 late).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from harness.checks import Bound, Check
from harness.modeling.scenes import Scene
from harness.modeling.system import System
from harness.scenes import simulate as sim

REFERENCE = Bound("reference confirmation", 1e-8, "our model by DOP853 (rtol 1e-12, atol 1e-14) against LSODA at "
                  "1e-13, another integrator family: the sum of both global errors, at most 0.05 of it over the "
                  "catalogue")
CONFIRMATION = "LSODA"
CONFIRMATION_RTOL = 1e-13  # LSODA's global error over the catalogue: 4.4e-10 at most (2.9e-9 at 1e-12)
ENGINE = Bound("engine trajectory", 1e-6, "an engine's forward dynamics integrated by DOP853 at 1e-10 against the "
               "reference: the per-step tolerance grown over a few hundred steps and periods by at most 1e4")
INVARIANT = Bound("energy balance", 1e-8, "E(t) − E(0) = ∫ q̇ᵀ f_np dt (3.101) along the reference, relative to the "
                  "energy scale: the reference integrator's global error")
MUJOCO_SOFT = Bound("MuJoCo soft constraint", 1e-3, "MuJoCo's soft constraints (contact, equalities) extrapolated to "
                    "dt → 0 from dt and dt/2 (first order), against the reference; dt is refined until within 0.1 "
                    "of this")
SOFT_ORDER = Bound("first order", 0.2, "|observed order − 1| of MuJoCo's implicitfast runs with soft constraints at "
                   "dt, dt/2: the first-order error model the extrapolation rests on", derived=True)
EVENT = Bound("event time", 1e-8, "an event of the reference against its prediction and against LSODA, s: located "
              "to the integrator's tolerance 1e-12 and by root finding")
ENGINE_EVENT = Bound("engine event time", 1e-5, "an event located with an engine's forward dynamics against the "
                     "reference, s: their trajectories carry the engine trajectory tolerance")
REFERENCE_TOL, ENGINE_TOL, INVARIANT_TOL, MUJOCO_SOFT_TOL = (REFERENCE.value, ENGINE.value, INVARIANT.value,
                                                             MUJOCO_SOFT.value)
EVENT_TOL, ENGINE_EVENT_TOL = EVENT.value, ENGINE_EVENT.value


@dataclass
class SceneResult:
    system: str
    scene: str
    checks: list[Check] = field(default_factory=list)
    notes: dict = field(default_factory=dict)
    trajectories: dict = field(default_factory=dict)

    def add(self, check: Check) -> None:
        self.checks.append(check)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)


@dataclass
class SceneRun:
    """One scene being checked: what every plug-in reads (the system, the scene, the engines that apply, the
    catalogue a lift-off's phase 2 comes from, the motion that simulates it and the event that motion switches
    at) and the result they add to."""

    system: System
    scene: Scene
    engines: tuple
    result: SceneResult
    motion: object = None            # the plug-in that simulates the scene (harness.scenes.phenomena.motion_of)
    event: object = None             # the scene's event the motion switches at (None: a smooth motion)
    catalogue: object = None
    mujoco_dt: float | None = None

    @property
    def reference(self) -> sim.Trajectory:
        return self.result.trajectories["reference"]

    def events(self, kind: type) -> list:
        """The scene's events of ``kind`` (a class of :mod:`harness.modeling.events`)."""
        return [e for e in self.scene.events if type(e) is kind]


# --------------------------------------------------------------------------- MuJoCo's soft constraints
SOFT_MARGIN = 0.1          # the extrapolated error is refined until within this fraction of MUJOCO_SOFT_TOL
SOFT_REFINEMENTS = 6       # halvings of dt at most: 64 × the first run's steps
ORDER_SLACK_SOFT = SOFT_ORDER.value
ROUND_OFF = 1e-9           # an error this small has no order to measure (soft errors of the catalogue: ≥ 1e-5)


def extrapolated(*runs: sim.Trajectory) -> sim.Trajectory:
    """The extrapolation of a first-order method's runs at ``dt``, ``dt/2`` (, ``dt/4``) to ``dt → 0`` at their
    common sample times: Richardson's ``2 y(dt/2) − y(dt)`` of two runs (the ``K dt`` term of the error cancels,
    ``O(dt²)`` remains), Romberg's ``(8 y(dt/4) − 6 y(dt/2) + y(dt)) / 3`` of three (``O(dt³)`` remains)."""
    weights = {2: (-1.0, 2.0), 3: (1 / 3, -2.0, 8 / 3)}[len(runs)]
    t = runs[0].t
    for r in runs[1:]:
        t = np.intersect1d(np.round(t, 9), np.round(r.t, 9))
    at = [np.isin(np.round(r.t, 9), t) for r in runs]
    q = sum(w * r.q[k] for w, r, k in zip(weights, runs, at))
    qd = sum(w * r.qd[k] for w, r, k in zip(weights, runs, at))
    return sim.Trajectory(f"{runs[-1].source}, extrapolated dt -> 0", runs[-1].t[at[-1]], q, qd,
                          sum(r.seconds for r in runs), sum(r.evaluations for r in runs))


def soft_convergence(result: SceneResult, what: str, run, ref, dt: float) -> tuple[sim.Trajectory, float]:
    """MuJoCo's soft constraints (implicitfast, a first-order method) against the reference (see the module
    docstring): runs at ``dt`` and ``dt/2``, their extrapolation to ``dt → 0`` against the reference; it holds if
    the error is first order: the observed order of the last pair, ``log2(error(dt) / error(dt/2))``, must be within
    ``ORDER_SLACK_SOFT`` of 1. ``dt`` is halved (reusing the finer runs) until the extrapolation is within
    ``SOFT_MARGIN · MUJOCO_SOFT_TOL`` and the order within its slack, at most ``SOFT_REFINEMENTS`` times; the
    extrapolation is Richardson's of the last two runs, Romberg's of the last three once there are three
    (:func:`extrapolated`). The first-order constant ``K = error / dt`` is reported with them."""
    runs = [run(dt)]
    errors = [sim.max_error(runs[0], ref)]
    for level in range(SOFT_REFINEMENTS + 1):
        runs.append(run(dt / 2))
        errors.append(sim.max_error(runs[-1], ref))
        limit = sim.max_error(extrapolated(*runs[-3:]), ref)
        gap = order_gap(*errors[-2:], 1.0, two_sided=True)
        if limit <= SOFT_MARGIN * MUJOCO_SOFT_TOL and gap <= ORDER_SLACK_SOFT or level == SOFT_REFINEMENTS:
            break
        dt /= 2
    detail = f"from dt={dt:g}, dt/2" if len(runs) == 2 else f"Romberg from dt={2 * dt:g}, dt/2, dt/4"
    result.add(MUJOCO_SOFT.check(f"{what}, extrapolated dt -> 0", "mujoco", limit, detail=detail))
    result.add(SOFT_ORDER.check(f"{what}, first order |log2(error(dt) / error(dt/2)) - 1|", "mujoco", gap))
    e2 = errors[-1]
    result.notes[f"{what} error at dt={dt / 2:g}"] = e2
    result.notes[f"{what} first-order constant K = error / dt, 1/s"] = e2 / (dt / 2)
    return runs[-1], dt / 2


def order_gap(e1: float, e2: float, order: float, two_sided: bool = False, floor: float = ROUND_OFF) -> float:
    """How far the observed order ``log2(e1 / e2)`` of a pair ``dt``, ``dt/2`` falls short of ``order`` (or misses
    it either way, ``two_sided``): a lower bound on the order recorded as an upper bound on its deficit, so that
    the margin is measured (0 at the asymptotic order). Errors at round-off have no order: 0."""
    if max(e1, e2) <= floor:
        return 0.0
    if e2 <= 0:
        return 0.0 if not two_sided else np.inf
    gap = order - np.log2(e1 / e2)
    return float(abs(gap) if two_sided else max(0.0, gap))


def event_error(a, b, kinds: bool = True) -> float:
    """Largest difference of corresponding event times (inf when the sequences differ)."""
    if len(a.events) != len(b.events) or (kinds and [e.after for e in a.events] != [e.after for e in b.events]):
        return np.inf
    return max((abs(x.time - y.time) for x, y in zip(a.events, b.events)), default=0.0)


# --------------------------------------------------------------------------- the plug-in interface
class Phenomenon:
    """One thing a scene can call for (a plug-in of :mod:`harness.scenes.phenomena`).

    ``event`` is the class of :mod:`harness.modeling.events` that calls for it (None: it is asked of every scene);
    :meth:`applies` says whether it has anything to check in a run, :meth:`check` simulates what it needs and adds
    checks, notes and trajectories to ``run.result``. ``mujoco_run(system, scene, event, dt)``, where given, is
    MuJoCo's own simulation of the phenomenon (a soft constraint stepped at ``dt``: dry friction, contact)."""

    name = ""
    event: type | None = None
    mujoco_run = None

    def applies(self, run: SceneRun) -> bool:
        return True

    def check(self, run: SceneRun) -> None:
        raise NotImplementedError


class Motion(Phenomenon):
    """How the scene moves: exactly one motion per scene simulates it with any source and checks the sources
    against the reference; it runs first (the other plug-ins read its reference)."""

    switches = False        # whether its branches switch at events (a hybrid motion)
    mujoco_note = None      # why MuJoCo has no simulation of its own of this motion, where it has none

    def simulate(self, system: System, scene: Scene, event, source: str, method: str = "DOP853",
                 rtol: float = 1e-12, atol: float = 1e-12, t_eval=None, catalogue=None) -> sim.Trajectory:
        raise NotImplementedError

    def tree_view(self, run: SceneRun):
        """How a constrained tree's run compares with this motion's reference: ``(horizon, mapping)``, the time
        the tree's constraints hold until (None: the whole scene) and the map of its trajectory to the reference's
        coordinates; None where the tree is not simulated with this motion."""
        return None, (lambda tr: tr)
