"""Trajectory checks of a scene, with their tolerances and reasons (one place).

* **reference**: our symbolic model, DOP853 at ``rtol = atol = 1e-12``, confirmed by LSODA at the same
  tolerance (Adams/BDF multistep: another family than Runge-Kutta; Radau agrees as well but costs 10-30x
  more, measured on pendulum, quarter_car, toggle_press): they must agree to ``REFERENCE_TOL = 1e-8`` of the
  state's scale (global error of both, grown over the horizon; scenes are chosen non-chaotic over it).
* **engines**: Pinocchio's and MuJoCo's forward dynamics integrated by DOP853 at ``rtol = atol = 1e-10``
  must stay within ``ENGINE_TOL = 1e-6`` of the reference: the per-step tolerance 1e-10 grows over a few
  hundred steps and a few periods by at most ~1e4 for the (non-chaotic) scenes.
* **MuJoCo's own RK4** (``mj_step``, where the map is the identity and no external load is applied): its
  global error is O(dt⁴); at ``dt`` and ``dt/2`` the error must fall by at least 8 (order ≥ 3) unless both are
  already at round-off (< 1e-10), and be below ``ENGINE_TOL`` at ``dt/2``. MuJoCo holds ``ctrl`` constant over
  a step (zero-order hold), so with an input that varies within steps the error is O(dt): there the error
  must fall by at least 1.8 (order ≥ 0.85) and is reported, not bounded.
* **invariants**: a conservative scene keeps ``E = T + V`` within ``INVARIANT_TOL = 1e-8`` of its scale;
  otherwise the power balance ``E(t) − E(0) = ∫ q̇ᵀ f_np dt`` (3.101) holds to the same tolerance.
* **pruning**: the scene run with every effect of the system present but idle (multiplied by a parameter
  set to 0, :func:`harness.scenes.idle`) gives the same trajectory (``ENGINE_TOL``); the time ratio
  idle/pruned of our symbolic simulation is reported for every scene.
* **structural changes** (stick-slip, rolling or slipping; :mod:`harness.structural` states their
  tolerances): event times against their prediction and between sources; MuJoCo's own dry friction and
  contact, and its equality constraints for closed chains and couplings (:mod:`harness.constraints`) are
  soft constraints, first order in ``dt``: ``dt`` is divided by 4 (at most three times) until the error is
  within ``MUJOCO_SOFT_TOL = 1e-3`` (the step reached is reported), and the last refinement must show the
  convergence: the error falls by at least 3 when ``dt`` is divided by 4 (order ≥ 0.8; events are quantized
  to the step, so the error is not monotone between neighbouring ``dt``), unless already below 1e-6.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from harness.compile import compiled
from harness.model import System
from harness.scenes import Scene, pruned, with_idle_effects
from harness import constraints, structural
from harness import simulate as sim

REFERENCE_TOL = 1e-8
CONFIRMATION = "LSODA"
ENGINE_TOL = 1e-6
INVARIANT_TOL = 1e-8
MUJOCO_SOFT_TOL = 1e-3


@dataclass
class SceneResult:
    system: str
    scene: str
    checks: list = field(default_factory=list)     # (check, source, error, tolerance)
    notes: dict = field(default_factory=dict)
    trajectories: dict = field(default_factory=dict)

    def add(self, check, source, error, tolerance):
        self.checks.append((check, source, float(error), float(tolerance)))

    @property
    def passed(self) -> bool:
        return all(e <= tol for _, _, e, tol in self.checks)


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


def symbolic_run(system: System, scene: Scene, rtol: float = 1e-10) -> sim.Trajectory:
    """Our symbolic simulation of ``scene`` (DOP853, ``atol = rtol``; events located when it has any)."""
    event = hybrid_event(scene)
    if event is not None:
        return HYBRID[type(event)](system, scene, event, "symbolic", rtol=rtol, atol=rtol)
    return sim.integrate(system, scene, "symbolic", rtol=rtol, atol=rtol)


PRUNING_REPEATS = 3


def _pruning(system: System, scene: Scene, result: "SceneResult") -> None:
    """Idle-but-present against pruned: the same trajectory, and the time ratio (the fastest of
    ``PRUNING_REPEATS`` runs each, as a single timing on a shared machine is noise). A scene that calls for
    every effect of its system has nothing to prune: its ratio is 1 by construction."""
    idle_system, idle_scene = with_idle_effects(system, scene)
    key = "pruning time ratio (idle / pruned), symbolic"
    if idle_scene is scene:
        result.notes[key] = 1.0
        result.notes["pruning"] = "nothing to prune: the scene calls for every effect of the system"
        return
    lean = [symbolic_run(system, scene) for _ in range(PRUNING_REPEATS)]
    full = [symbolic_run(idle_system, idle_scene) for _ in range(PRUNING_REPEATS)]
    result.add("pruned = all effects present but idle", "symbolic", sim.max_error(full[0], lean[0]), ENGINE_TOL)
    result.notes[key] = min(t.seconds for t in full) / max(min(t.seconds for t in lean), 1e-12)
    result.notes["pruning: effects left out"] = ", ".join(sorted(set(idle_scene.effects) - set(scene.effects)))


def _soft_convergence(result: "SceneResult", what: str, run, ref, dt: float) -> tuple[sim.Trajectory, float]:
    """MuJoCo's soft constraints against the reference (see the module docstring): ``dt`` divided by 4 until the
    error is within ``MUJOCO_SOFT_TOL`` (at most three refinements); the last refinement must show first-order
    convergence. The step that reached the tolerance is reported with the check."""
    coarse = run(dt)
    e1 = sim.max_error(coarse, ref)
    for _ in range(3):
        fine = run(dt / 4)
        e2 = sim.max_error(fine, ref)
        dt /= 4
        if e2 <= MUJOCO_SOFT_TOL:
            break
        e1 = e2
    result.add(f"{what} dt={dt:g}", "mujoco", e2, MUJOCO_SOFT_TOL)
    result.add(f"{what} convergence dt -> dt/4 (error ratio >= 3)", "mujoco",
               0.0 if (e2 > 0 and e1 / e2 >= 3) or max(e1, e2) < 1e-6 else 1.0, 0.0)
    result.notes[f"{what} error ratio dt -> dt/4"] = e1 / e2 if e2 > 0 else np.inf
    return fine, dt


def _hybrid(system: System, scene: Scene, event, engines, result: "SceneResult") -> None:
    """A scene whose branches switch at events: reference (DOP853) confirmed by LSODA, trajectories and event
    times of the engines' forward dynamics, the energy across the switch for a conservative scene."""
    def run(source, **kw):
        return HYBRID[type(event)](system, scene, event, source, **kw)

    ref = run("symbolic")
    result.trajectories["reference"] = ref
    second = run("symbolic", method=CONFIRMATION)
    result.add(f"reference confirmed ({CONFIRMATION} vs DOP853)", "symbolic", sim.max_error(second, ref), REFERENCE_TOL)
    result.add(f"events confirmed ({CONFIRMATION} vs DOP853), s", "symbolic", _event_error(second, ref),
               structural.EVENT_TOL)
    result.notes["events (reference)"] = "; ".join(f"{e.time:.6f} s {e.before} -> {e.after}" for e in ref.events)
    for engine in engines:
        tr = run(engine, rtol=1e-10, atol=1e-10)
        result.trajectories[engine] = tr
        result.add("trajectory (DOP853 1e-10, events)", engine, sim.max_error(tr, ref), ENGINE_TOL)
        result.add("event times, s", engine, _event_error(tr, ref), structural.ENGINE_EVENT_TOL)
    if scene.conservative:
        energy = np.asarray(ref.energy)
        scale = max(1e-300, float(np.max(np.abs(energy - energy[0]))), float(np.max(np.abs(energy))))
        result.add("energy constant across the events", "symbolic", float(np.max(np.abs(energy - energy[0]))) / scale,
                   INVARIANT_TOL)
    else:
        result.notes["power balance"] = "not checked across the switching of the branches"
    if isinstance(event, structural.StickSlip):
        _stick_slip(system, scene, event, engines, result)


def _stick_slip(system: System, scene: Scene, event, engines, result: "SceneResult") -> None:
    """(3.80): the breakaway where |f_e| = mu_H f_N, and MuJoCo's own dry friction."""
    ref = result.trajectories["reference"]
    predicted = structural.predicted_breakaway(system, scene, event)
    result.add("breakaway where |f_e| = mu_H f_N (3.80), s", "symbolic", abs(ref.events[0].time - predicted),
               structural.EVENT_TOL)
    if "mujoco" in engines:
        dt = scene.horizon / 4000
        fine, dt = _soft_convergence(result, "MuJoCo frictionloss", lambda h: structural.mujoco_stick_slip(
            system, scene, event, h), ref, dt)
        result.trajectories["mujoco frictionloss"] = fine
        result.add("MuJoCo frictionloss event times within 3 dt, s", "mujoco", _event_error(fine, ref, kinds=False),
                   3 * dt)


def _constrained(system: System, scene: Scene, engines, result: "SceneResult", horizon=None,
                 mapping=lambda tr: tr) -> None:
    """The tree with the map's constraints imposed by the engines themselves (:mod:`harness.constraints`);
    up to ``horizon`` (a lift-off ends the constraint), compared in the reference's coordinates (``mapping``)."""
    ref = result.trajectories["reference"]
    if horizon is not None:
        result.notes["constrained tree simulated until"] = f"{horizon:.6f} s (the event that ends the constraint)"
    if "pinocchio" in engines:
        tr = mapping(constraints.pinocchio_constrained(system, scene, horizon=horizon))
        result.trajectories["pinocchio constrained"] = tr
        result.add("constrained tree (pin.forwardDynamics KKT, DOP853 1e-10)", "pinocchio", sim.max_error(tr, ref),
                   ENGINE_TOL)
        result.add("constraint drift max |c|", "pinocchio", tr.notes["drift"], constraints.DRIFT_TOL)
    if "mujoco" in engines:
        dt = scene.horizon / 4000
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
    dt = scene.horizon / 1000
    ref = result.trajectories["reference"]
    tr = mujoco_contact = structural.mujoco_rolling(system, scene, event, dt / 4)
    scale = float(np.max(np.abs(ref.qd))) * params[event.radius]
    expect_roll = event.mu >= predicted
    slip = abs(float(mujoco_contact.notes["slip"][-1])) / scale
    result.notes["MuJoCo contact: slip velocity at the end / rolling velocity scale"] = slip
    result.add(f"MuJoCo contact {'rolls' if expect_roll else 'slips'} at mu = {event.mu / predicted:.2f} x "
               "2/7 tan(alpha)", "mujoco", 0.0 if structural.rolls(tr, scale) == expect_roll else 1.0, 0.0)
    if expect_roll:
        fine, _ = _soft_convergence(result, "MuJoCo contact", lambda h: structural.mujoco_rolling(
            system, scene, event, h), ref, dt)
        result.trajectories["mujoco contact"] = fine
    threshold = structural.mujoco_threshold(system, scene, event, dt)
    result.notes["rolling threshold mu: MuJoCo (bisection) / predicted 2/7 tan(alpha)"] = threshold / predicted
    result.add("MuJoCo's rolling threshold vs 2/7 tan(alpha), relative", "mujoco", abs(threshold / predicted - 1),
               structural.THRESHOLD_TOL)


def run_scene(system: System, scene: Scene, engines=("pinocchio", "mujoco"), mujoco_dt: float | None = None) -> SceneResult:
    result = SceneResult(system.name, scene.name)
    engines = tuple(e for e in engines if not system.engine_note(e))
    for engine in {"pinocchio", "mujoco"} - set(engines):
        if system.engine_note(engine):
            result.notes[engine] = system.engine_note(engine)
    event = hybrid_event(scene)
    if event is not None:
        _hybrid(system, scene, event, engines, result)
        if constraints.constrained(system) and isinstance(event, structural.LiftOff):
            _constrained(system, scene, engines, result, horizon=result.trajectories["reference"].events[0].time,
                         mapping=lambda tr: structural.in_free_coordinates(system, scene, event, tr))
        _pruning(system, scene, result)
        return result
    _smooth(system, scene, engines, mujoco_dt, result)
    if constraints.constrained(system):
        _constrained(system, scene, engines, result)
    for event in scene.events:
        if isinstance(event, structural.RollSlip) and "mujoco" in engines:
            _roll_slip(system, scene, event, result)
    balance, _ = _energy_balance(system, scene)
    result.add("energy constant" if scene.conservative else "power balance (3.101)", "symbolic", balance,
               INVARIANT_TOL)
    _pruning(system, scene, result)
    return result


def _smooth(system: System, scene: Scene, engines, mujoco_dt, result: SceneResult) -> None:
    ref = sim.integrate(system, scene, "symbolic", **{k: v for k, v in sim.REFERENCE.items() if k != "method"})
    result.trajectories["reference"] = ref
    second = sim.integrate(system, scene, "symbolic", method=CONFIRMATION, rtol=1e-12, atol=1e-12)
    result.add(f"reference confirmed ({CONFIRMATION} vs DOP853)", "symbolic", sim.max_error(second, ref), REFERENCE_TOL)
    for engine in engines:
        tr = sim.integrate(system, scene, engine, rtol=1e-10, atol=1e-10)
        result.trajectories[engine] = tr
        result.add("trajectory (DOP853 1e-10)", engine, sim.max_error(tr, ref), ENGINE_TOL)
    if "mujoco" in engines:
        dt = mujoco_dt or scene.horizon / 4000
        try:
            coarse, fine = sim.mujoco_native(system, scene, dt), sim.mujoco_native(system, scene, dt / 2)
        except ValueError as why:
            result.notes["mujoco mj_step"] = str(why)
        else:
            e1, e2 = sim.max_error(coarse, ref), sim.max_error(fine, ref)
            result.trajectories["mujoco mj_step"] = fine
            ratio = e1 / e2 if e2 > 0 else np.inf
            result.notes["mj_step RK4 error ratio dt -> dt/2"] = ratio
            if scene.inputs_vary_within_steps:
                result.notes[f"mj_step RK4 error at dt={dt / 2:g} (zero-order-hold input)"] = e2
                result.add("mj_step RK4 convergence, zero-order-hold input (ratio >= 1.8)", "mujoco",
                           0.0 if ratio >= 1.8 else 1.0, 0.0)
            else:
                result.add(f"mj_step RK4 dt={dt / 2:g}", "mujoco", e2, ENGINE_TOL)
                result.add("mj_step RK4 convergence (error ratio >= 8)", "mujoco",
                           0.0 if (ratio >= 8 or max(e1, e2) < 1e-10) else 1.0, 0.0)


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


def scene_record(system: System, scene: Scene) -> tuple[dict, dict]:
    """One scene's checks as a results.json record, and its series (written to ``series`` by the caller)."""
    record = {"scene": scene.name, "description": scene.description, "effects": sorted(scene.effects),
              "horizon": scene.horizon, "series": f"trajectories/{system.name}.{scene.name}.json"}
    try:
        result = run_scene(system, scene)
    except Exception as exc:  # noqa: BLE001 - one scene raising never loses the others
        record.update(passed=False, checks=[], notes={}, failure=f"{type(exc).__name__}: {exc}", series=None)
        return record, {}
    record.update(passed=result.passed, failure=None,
                  checks=[{"check": c, "source": s, "max_error": e, "tolerance": tol, "passed": e <= tol}
                          for c, s, e, tol in result.checks],
                  notes={k: (float(v) if isinstance(v, (float, np.floating)) else str(v))
                         for k, v in result.notes.items()})
    return record, series(system, scene, result)


def scene_records(system: System, series_dir=None) -> list[dict]:
    """The records of every scene of ``system``; with ``series_dir``, each scene's series is written to
    ``series_dir/<record['series']>`` (atomically)."""
    import json
    from pathlib import Path

    import models
    from harness.io import atomic_write_text

    records = []
    for scene in models.scenes(system.name):
        record, data = scene_record(system, scene)
        if series_dir is not None and data:
            atomic_write_text(Path(series_dir) / record["series"], json.dumps(data) + "\n")
        elif series_dir is None:
            record["series"] = None
        records.append(record)
    return records
