"""Trajectory checks of a scene, with their tolerances and reasons (one place).

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
* **structural changes** (stick-slip, rolling or slipping; :mod:`harness.scenes.structural` states their
  tolerances): event times against their prediction and between sources. MuJoCo's own contact and its
  equality constraints for closed chains and couplings (:mod:`harness.scenes.constraints`) are soft constraints
  (``solref = 2 dt``) stepped by implicitfast, a first-order method: the error is ``K dt + O(dt²)`` (``K``
  reported; over the catalogue 0.4 to 48 per second, the error halving with ``dt`` to 1%). Runs at ``dt`` and
  ``dt/2`` are extrapolated to ``dt → 0`` (Richardson, ``2 y(dt/2) − y(dt)``), which must be within
  ``MUJOCO_SOFT_TOL = 1e-3`` of the reference: ``dt`` (on the grid of :func:`simulate.grid_steps`, so input
  jumps fall on steps) is halved, reusing the finer run, until the extrapolated error is within
  ``SOFT_MARGIN = 0.1`` of it (at most three times). The first-order model the extrapolation rests on is checked
  on the last pair: ``|log2(error(dt) / error(dt/2)) − 1| ≤ 0.2``. MuJoCo's dry friction (frictionloss) switches
  at events that fall on steps: its error is first order but not smooth in ``dt`` (no extrapolation); its
  first-order constant ``error / dt`` at ``dt`` and ``dt/2`` must stay within ``C`` derived from the events'
  acceleration jumps (:func:`structural.frictionloss_bound`), and its event times within ``3 dt``: an event
  falls anywhere within a step and MuJoCo's velocity leaves (breakaway: the input is held at the step's
  midpoint, so ``½ < δ/dt ≤ 3/2``) or reaches 0 (sticking: ``1 < δ/dt ≤ 2``) at most a step later,
  ``δ ≤ 2 dt``; the trajectory's own error shifts a velocity zero by ``error / |ẍ|`` (measured ≤ 0.01 dt), for
  which the third ``dt`` leaves ample room.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from harness.checks import Bound, Check
from harness.derivation.compile import compiled
from harness.engines import ENGINES, simulating
from harness.modeling.system import System
from harness.modeling.scenes import Scene, pruned, with_idle_effects
from harness.scenes import constraints
from harness.scenes import structural
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
RK4_ORDER = Bound("RK4 order", 1.0, "order deficit p − log2(error(dt)/error(dt/2)) of MuJoCo's RK4 (p = 4, or 2 with a "
                  "midpoint-held input): at most 1, i.e. the observed order is at least p − 1 before the asymptotic "
                  "regime", derived=True)
FRICTIONLOSS = Bound("frictionloss first-order constant", 1.0, "error / dt of MuJoCo's dry friction at dt and dt/2 "
                     "against C, derived from the events' acceleration jumps and the step's quantization "
                     "(structural.frictionloss_bound)", derived=True)
REFERENCE_TOL, ENGINE_TOL, INVARIANT_TOL, MUJOCO_SOFT_TOL = (REFERENCE.value, ENGINE.value, INVARIANT.value,
                                                             MUJOCO_SOFT.value)


@dataclass
class SceneResult:
    system: str
    scene: str
    checks: list[Check] = field(default_factory=list)
    notes: dict = field(default_factory=dict)
    trajectories: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)   # clock values (the pruning time ratio): timings.json

    def add(self, check: Check) -> None:
        self.checks.append(check)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)


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
    energy = np.array([float(c("T", y[:n], y[n:2 * n], p, zeros)) + float(c("V", y[:n], y[n:2 * n], p, zeros))
                       for y in ys.T])
    work = ys[2 * n]
    kinetic = [abs(float(c("T", y[:n], y[n:2 * n], p, zeros))) for y in ys.T]
    scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(kinetic)), float(np.max(np.abs(work))))
    return float(np.max(np.abs(energy - energy[0] - work))) / scale, scale


HYBRID = {structural.StickSlip: structural.stick_slip, structural.LiftOff: structural.lift_off}


def hybrid_event(scene: Scene):
    """The scene's event whose switching the simulation itself carries out (stick-slip, lift-off), if any."""
    return next((e for e in scene.events if type(e) in HYBRID), None)


def symbolic_run(system: System, scene: Scene, rtol: float = 1e-10, catalogue=None) -> sim.Trajectory:
    """Our symbolic simulation of ``scene`` (DOP853, ``atol = rtol``; events located when it has any; a lift-off
    finds its phase-2 system in ``catalogue``)."""
    event = hybrid_event(scene)
    if event is not None:
        return HYBRID[type(event)](system, scene, event, "symbolic", rtol=rtol, atol=rtol, catalogue=catalogue)
    return sim.integrate(system, scene, "symbolic", rtol=rtol, atol=rtol)


PRUNING_REPEATS = 3


def _pruning(system: System, scene: Scene, result: "SceneResult", catalogue=None) -> None:
    """Idle-but-present against pruned: the same trajectory, and the time ratio (the fastest of
    ``PRUNING_REPEATS`` runs each, as a single timing on a shared machine is noise). A scene that calls for
    every effect of its system has nothing to prune: its ratio is 1 by construction."""
    idle_system, idle_scene = with_idle_effects(system, scene)
    key = "pruning time ratio (idle / pruned), symbolic"
    if idle_scene is scene:
        result.timings[key] = 1.0
        result.notes["pruning"] = "nothing to prune: the scene calls for every effect of the system"
        return
    lean = [symbolic_run(system, scene, catalogue=catalogue) for _ in range(PRUNING_REPEATS)]
    full = [symbolic_run(idle_system, idle_scene, catalogue=catalogue) for _ in range(PRUNING_REPEATS)]
    result.add(ENGINE.check("pruned = all effects present but idle", "symbolic", sim.max_error(full[0], lean[0])))
    result.timings[key] = min(t.seconds for t in full) / max(min(t.seconds for t in lean), 1e-12)
    result.notes["pruning: effects left out"] = ", ".join(sorted(set(idle_scene.effects) - set(scene.effects)))


SOFT_MARGIN = 0.1          # the extrapolated error is refined until within this fraction of MUJOCO_SOFT_TOL
SOFT_REFINEMENTS = 3       # halvings of dt at most
ORDER_SLACK_SOFT = SOFT_ORDER.value
ROUND_OFF = 1e-9           # an error this small has no order to measure (soft errors of the catalogue: ≥ 1e-5)


def extrapolated(coarse: sim.Trajectory, fine: sim.Trajectory) -> sim.Trajectory:
    """Richardson's extrapolation of a first-order method to ``dt → 0``: ``2 y(dt/2) − y(dt)`` at the common
    sample times (the ``K dt`` term of the error cancels, ``O(dt²)`` remains)."""
    t = np.intersect1d(np.round(coarse.t, 9), np.round(fine.t, 9))
    ic, jf = np.isin(np.round(coarse.t, 9), t), np.isin(np.round(fine.t, 9), t)
    return sim.Trajectory(f"{fine.source}, extrapolated dt -> 0", fine.t[jf], 2 * fine.q[jf] - coarse.q[ic],
                          2 * fine.qd[jf] - coarse.qd[ic], coarse.seconds + fine.seconds,
                          coarse.evaluations + fine.evaluations)


def _soft_convergence(result: "SceneResult", what: str, run, ref, dt: float) -> tuple[sim.Trajectory, float]:
    """MuJoCo's soft constraints (implicitfast, a first-order method) against the reference (see the module
    docstring): runs at ``dt`` and ``dt/2``, their Richardson extrapolation to ``dt → 0`` against the reference,
    ``dt`` halved (reusing the finer run) until that is within ``SOFT_MARGIN · MUJOCO_SOFT_TOL`` (at most
    ``SOFT_REFINEMENTS`` times). The extrapolation holds if the error is first order: the observed order of the last
    pair, ``log2(error(dt) / error(dt/2))``, must be within ``ORDER_SLACK_SOFT`` of 1; the first-order constant
    ``K = error / dt`` is reported with it."""
    coarse = run(dt)
    e1 = sim.max_error(coarse, ref)
    for level in range(SOFT_REFINEMENTS + 1):
        fine = run(dt / 2)
        e2 = sim.max_error(fine, ref)
        limit = sim.max_error(extrapolated(coarse, fine), ref)
        if limit <= SOFT_MARGIN * MUJOCO_SOFT_TOL or level == SOFT_REFINEMENTS:
            break
        coarse, e1, dt = fine, e2, dt / 2
    result.add(MUJOCO_SOFT.check(f"{what}, extrapolated dt -> 0", "mujoco", limit, detail=f"from dt={dt:g}, dt/2"))
    result.add(SOFT_ORDER.check(f"{what}, first order |log2(error(dt) / error(dt/2)) - 1|", "mujoco",
                                _order_gap(e1, e2, 1.0, two_sided=True)))
    result.notes[f"{what} error at dt={dt / 2:g}"] = e2
    result.notes[f"{what} first-order constant K = error / dt, 1/s"] = e2 / (dt / 2)
    return fine, dt / 2


def _hybrid(system: System, scene: Scene, event, engines, result: "SceneResult", catalogue=None) -> None:
    """A scene whose branches switch at events: reference (DOP853) confirmed by LSODA, trajectories and event
    times of the engines' forward dynamics, the energy across the switch for a conservative scene."""
    def run(source, **kw):
        return HYBRID[type(event)](system, scene, event, source, catalogue=catalogue, **kw)

    ref = run("symbolic", **{k: v for k, v in sim.REFERENCE.items() if k != "method"})
    result.trajectories["reference"] = ref
    second = run("symbolic", method=CONFIRMATION, rtol=CONFIRMATION_RTOL, atol=CONFIRMATION_RTOL)
    result.add(REFERENCE.check(f"reference confirmed ({CONFIRMATION} vs DOP853)", "symbolic", sim.max_error(second, ref)))
    result.add(structural.EVENT.check(f"events confirmed ({CONFIRMATION} vs DOP853), s", "symbolic",
                                      _event_error(second, ref)))
    result.notes["events (reference)"] = "; ".join(f"{e.time:.6f} s {e.before} -> {e.after}" for e in ref.events)
    for engine in engines:
        tr = run(engine, rtol=1e-10, atol=1e-10)
        result.trajectories[engine] = tr
        result.add(ENGINE.check("trajectory (DOP853 1e-10, events)", engine, sim.max_error(tr, ref)))
        result.add(structural.ENGINE_EVENT.check("event times, s", engine, _event_error(tr, ref)))
    if scene.conservative:
        energy = np.asarray(ref.energy)
        scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(np.abs(energy))))
        result.add(INVARIANT.check("energy constant across the events", "symbolic",
                                   float(np.max(np.abs(energy - energy[0]))) / scale))
    else:
        result.notes["power balance"] = "not checked across the switching of the branches"
    if isinstance(event, structural.StickSlip):
        _stick_slip(system, scene, event, engines, result)


def _stick_slip(system: System, scene: Scene, event, engines, result: "SceneResult") -> None:
    """(3.80): the breakaway where |f_e| = mu_H f_N, and MuJoCo's own dry friction."""
    ref = result.trajectories["reference"]
    predicted = structural.predicted_breakaway(system, scene, event)
    result.add(structural.EVENT.check("breakaway where |f_e| = mu_H f_N (3.80), s", "symbolic",
                                      abs(ref.events[0].time - predicted)))
    if simulating(engines, "dry friction"):
        dt = scene.horizon / sim.grid_steps(scene, 4000)
        bound = structural.frictionloss_bound(system, scene, event, ref)
        coarse, fine = (structural.mujoco_stick_slip(system, scene, event, h) for h in (dt, dt / 2))
        constant = max(sim.max_error(coarse, ref) / dt, sim.max_error(fine, ref) / (dt / 2))
        result.add(FRICTIONLOSS.check("MuJoCo frictionloss first-order constant error / dt at dt, dt/2, 1/s",
                                      "mujoco", constant, scale=bound, detail=f"C = {bound:.3g} 1/s"))
        result.notes["MuJoCo frictionloss: dt where C dt = MUJOCO_SOFT_TOL"] = MUJOCO_SOFT_TOL / bound
        result.trajectories["mujoco frictionloss"] = fine
        result.add(structural.STEP_EVENT.check("MuJoCo frictionloss event times, s", "mujoco",
                                               _event_error(fine, ref, kinds=False), scale=dt / 2,
                                               detail=f"dt={dt / 2:g}"))


def _constrained(system: System, scene: Scene, engines, result: "SceneResult", horizon=None,
                 mapping=lambda tr: tr) -> None:
    """The tree with the map's constraints imposed by the engines themselves (:mod:`harness.scenes.constraints`);
    up to ``horizon`` (a lift-off ends the constraint), compared in the reference's coordinates (``mapping``)."""
    ref = result.trajectories["reference"]
    if horizon is not None:
        result.notes["constrained tree simulated until"] = f"{horizon:.6f} s (the event that ends the constraint)"
    if simulating(engines, "kkt constraints"):
        tr = mapping(constraints.pinocchio_constrained(system, scene, horizon=horizon))
        result.trajectories["pinocchio constrained"] = tr
        result.add(ENGINE.check("constrained tree (pin.forwardDynamics KKT, DOP853 1e-10)", "pinocchio",
                                sim.max_error(tr, ref)))
        result.add(constraints.DRIFT.check("constraint drift max |c_k| / sum_j |J_kj| max(1, |theta_j|)",
                                           "pinocchio", tr.notes["drift"]))
    if simulating(engines, "soft constraints"):
        dt = scene.horizon / sim.grid_steps(scene, 4000)

        def run(h):
            return mapping(constraints.mujoco_constrained(system, scene, h, horizon=horizon))

        fine, _ = _soft_convergence(result, "MuJoCo equality constraints", run, ref, dt)
        result.trajectories["mujoco constrained"] = fine


def _event_error(a, b, kinds: bool = True) -> float:
    """Largest difference of corresponding event times (inf when the sequences differ)."""
    if len(a.events) != len(b.events) or (kinds and [e.after for e in a.events] != [e.after for e in b.events]):
        return np.inf
    return max((abs(x.time - y.time) for x, y in zip(a.events, b.events)), default=0.0)


def _roll_slip(system: System, scene: Scene, event, result: "SceneResult") -> None:
    """MuJoCo's sphere in contact: rolls or slips as the predicted threshold says; its threshold located."""
    params = {**system.default_parameters(), **scene.params}
    predicted = event.predicted(params)
    dt = scene.horizon / sim.grid_steps(scene, 1000)
    ref = result.trajectories["reference"]
    mujoco_contact = structural.mujoco_rolling(system, scene, event, dt / 4)
    scale = float(np.max(np.abs(ref.qd))) * params[event.radius]
    expect_roll = event.mu >= predicted
    slip = abs(float(mujoco_contact.notes["slip"][-1])) / scale
    result.notes["MuJoCo contact: slip velocity at the end / rolling velocity scale"] = slip
    at = f"at mu = {event.mu / predicted:.2f} x 2/7 tan(alpha)"
    if expect_roll:   # the measured slip against the rolling criterion (rolls(): slip <= ROLLING_SLIP)
        result.add(structural.ROLLING.check(f"MuJoCo contact rolls {at}: slip / velocity scale", "mujoco", slip))
    else:             # a lower bound on the slip, recorded as the criterion's share of it
        result.add(structural.SLIPPING.check(f"MuJoCo contact slips {at}: 1e-6 / (slip / velocity scale)", "mujoco",
                                             structural.ROLLING_SLIP / slip if slip > 0 else np.inf))
    if expect_roll:
        fine, _ = _soft_convergence(result, "MuJoCo contact", lambda h: structural.mujoco_rolling(
            system, scene, event, h), ref, dt)
        result.trajectories["mujoco contact"] = fine
    threshold = structural.mujoco_threshold(system, scene, event, dt)
    result.notes["rolling threshold mu: MuJoCo (bisection) / predicted 2/7 tan(alpha)"] = threshold / predicted
    result.add(structural.THRESHOLD.check("MuJoCo's rolling threshold vs 2/7 tan(alpha), relative", "mujoco",
                                          abs(threshold / predicted - 1)))


def run_scene(system: System, scene: Scene, engines=("pinocchio", "mujoco"), mujoco_dt: float | None = None,
              catalogue=None) -> SceneResult:
    """Simulate ``scene`` with every source and check it; ``catalogue`` resolves the systems an event switches
    to (a lift-off's phase 2)."""
    result = SceneResult(system.name, scene.name)
    for engine in engines:
        if ENGINES[engine].applies(system):
            result.notes[engine] = ENGINES[engine].applies(system)
    engines = tuple(e for e in engines if not ENGINES[e].applies(system))
    event = hybrid_event(scene)
    if event is not None:
        _hybrid(system, scene, event, engines, result, catalogue)
        if constraints.constrained(system) and isinstance(event, structural.LiftOff):
            _constrained(system, scene, engines, result, horizon=result.trajectories["reference"].events[0].time,
                         mapping=lambda tr: structural.in_free_coordinates(system, scene, event, tr, catalogue))
        _pruning(system, scene, result, catalogue)
        return result
    _smooth(system, scene, engines, mujoco_dt, result)
    if constraints.constrained(system):
        _constrained(system, scene, engines, result)
    for event in scene.events:
        if isinstance(event, structural.RollSlip) and simulating(engines, "contact"):
            _roll_slip(system, scene, event, result)
    balance, _ = _energy_balance(system, scene)
    result.add(INVARIANT.check("energy constant" if scene.conservative else "power balance (3.101)", "symbolic",
                               balance))
    _pruning(system, scene, result)
    return result


def _smooth(system: System, scene: Scene, engines, mujoco_dt, result: SceneResult) -> None:
    ref = sim.integrate(system, scene, "symbolic", **{k: v for k, v in sim.REFERENCE.items() if k != "method"})
    result.trajectories["reference"] = ref
    second = sim.integrate(system, scene, "symbolic", method=sim.ODEINT, rtol=CONFIRMATION_RTOL,
                           atol=CONFIRMATION_RTOL)
    result.add(REFERENCE.check(f"reference confirmed ({CONFIRMATION} vs DOP853)", "symbolic", sim.max_error(second, ref)))
    for engine in engines:
        tr = sim.integrate(system, scene, engine, rtol=1e-10, atol=1e-10)
        result.trajectories[engine] = tr
        result.add(ENGINE.check("trajectory (DOP853 1e-10)", engine, sim.max_error(tr, ref)))
    if simulating(engines, "stepping"):
        _mj_step(system, scene, mujoco_dt, ref, result)


RK4_START = 500          # steps of the first, coarse mj_step run
RK4_TARGET = 1e-8        # predicted error of the finer run: ENGINE_TOL / 100, >= 100 x the reference's own error
RK4_FLOOR = 1e-9         # a coarse error below this is coarsened: the pair must stay above the reference's error


def _mj_step(system: System, scene: Scene, mujoco_dt, ref, result: SceneResult) -> None:
    """MuJoCo's own RK4 (module docstring): a coarse run at ``RK4_START`` grid steps predicts, with the method's
    order ``p`` (4; 2 with a midpoint-held input that varies within steps), the step whose error is ``RK4_TARGET``;
    the pair ``dt``, ``dt/2`` there gives the error (``<= ENGINE_TOL``) and the observed order's deficit
    ``p - log2(error(dt) / error(dt/2)) <= 1`` (order >= p - 1 before the asymptotic regime)."""
    held = scene.inputs_vary_within_steps
    order = 2 if held else 4
    try:
        if mujoco_dt:
            dt = mujoco_dt
            coarse = sim.mujoco_native(system, scene, dt)
        else:
            n = sim.grid_steps(scene, RK4_START)
            coarse = sim.mujoco_native(system, scene, scene.horizon / n)
            while sim.max_error(coarse, ref) < RK4_FLOOR and n % 2 == 0 and sim.grid_steps(scene, n // 2) == n // 2:
                n //= 2
                coarse = sim.mujoco_native(system, scene, scene.horizon / n)
            e0 = sim.max_error(coarse, ref)
            k = 0 if held else max(0, int(np.ceil(np.log2(e0 / RK4_TARGET) / order - 1)))
            dt = scene.horizon / (n * 2 ** k)
            if k:
                coarse = sim.mujoco_native(system, scene, dt)
        fine = sim.mujoco_native(system, scene, dt / 2)
    except ValueError as why:
        result.notes["mujoco mj_step"] = str(why)
        return
    e1, e2 = sim.max_error(coarse, ref), sim.max_error(fine, ref)
    result.trajectories["mujoco mj_step"] = fine
    result.notes["mj_step RK4 error ratio dt -> dt/2"] = e1 / e2 if e2 > 0 else np.inf
    result.notes["mj_step RK4 observed order log2(error(dt) / error(dt/2))"] = np.log2(e1 / e2) if e2 > 0 else np.inf
    if held:
        result.notes[f"mj_step RK4 error at dt={dt / 2:g} (midpoint-held input)"] = e2
        result.add(RK4_ORDER.check("mj_step RK4 midpoint-held input: order deficit 2 - log2(error(dt) / error(dt/2))",
                                   "mujoco", _order_gap(e1, e2, order, floor=RK4_FLOOR / 10)))
    else:
        result.add(ENGINE.check("mj_step RK4", "mujoco", e2, detail=f"dt={dt / 2:g}"))
        result.add(RK4_ORDER.check("mj_step RK4 order deficit 4 - log2(error(dt) / error(dt/2))", "mujoco",
                                   _order_gap(e1, e2, order, floor=RK4_FLOOR / 10)))


def _order_gap(e1: float, e2: float, order: float, two_sided: bool = False, floor: float = ROUND_OFF) -> float:
    """How far the observed order ``log2(e1 / e2)`` of a pair ``dt``, ``dt/2`` falls short of ``order`` (or misses
    it either way, ``two_sided``): a lower bound on the order recorded as an upper bound on its deficit, so that
    the margin is measured (0 at the asymptotic order). Errors at round-off have no order: 0."""
    if max(e1, e2) <= floor:
        return 0.0
    if e2 <= 0:
        return 0.0 if not two_sided else np.inf
    gap = order - np.log2(e1 / e2)
    return float(abs(gap) if two_sided else max(0.0, gap))


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
                                "energy": None if tr.energy is None else _digits(np.asarray(tr.energy)[keep])}
        if name != "reference":
            at = np.isin(key, np.round(tr.t[keep], 9))
            diff = np.hstack([tr.q[keep], tr.qd[keep]]) - np.hstack([ref.q[at], ref.qd[at]])
            out["error"][name] = _digits(np.max(np.abs(diff) / scale, axis=1))
    return out


def scene_record(system: System, scene: Scene, catalogue=None) -> tuple[dict, dict]:
    """One scene's checks as a results.json record (its clock values in ``timings``), and its series (written
    to ``series`` by the caller)."""
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
                         for k, v in result.notes.items()},
                  timings={k: float(v) for k, v in result.timings.items()})
    return record, series(system, scene, result)
