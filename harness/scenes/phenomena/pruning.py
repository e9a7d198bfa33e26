"""Pruning: the scene simulated with only what can act of the effects it calls for against the same scene with
every effect of the system present but idle (multiplied by a parameter set to 0, :func:`harness.modeling.scenes.idle`),
by every source in its own terms. What is left out: the effects the scene does not call for, the called-for
effects found idle and the force elements found idle inside an acting effect (:mod:`harness.scenes.effects`,
:meth:`~harness.scenes.effects.Inferred.pruned`: the quarter car's tyre damper at ``d_R = 0`` beside its suspension
damper), and a dry friction proved to stick throughout (:func:`~harness.scenes.effects.sticks_throughout`) is held:
the pruned run looks for no breakaway and integrates nothing (``ẋ ≡ 0``), where the idle one bounds the breakaway's
guard over its stick segment from three forward-dynamics calls (``stick_slip/holds``); the pruned run equal to the idle
one checks that inference.

* **symbolic**: the right-hand side derived and compiled from the pruned model against the one of the idle model,
  both integrated by odeint's LSODA at 1e-10 (:data:`RUN_METHOD`; DOP853 in an event's plug-in); with repeats,
  also both in machine code (:func:`machine_code`: our ẏ and DOP853 stepping compiled together, no call through
  Python);
* **pinocchio**: its forward dynamics (``pin.aba``; through a map with more tree joints than lecture coordinates
  ``pin.crba`` and ``pin.rnea`` at the map's ``J̇ q̇``, projected) of the pruned URDF against the idle one's,
  integrated alike: the pruned tree has no idle spring, damper, input or load to evaluate, and without a tendon or a
  load no frame placements or Jacobians to compute; where the two have the same force elements (gravity alone left out)
  nothing is pruned in this source and no ratio is measured;
* **mujoco**: its own RK4 (``mj_step``), every effect present (its flags cleared) against the left-out effects'
  disable flags set (:class:`~harness.engines.mujoco_engine.Options` ``disable``,
  :func:`~harness.engines.mujoco_engine.effect_flags`) and their force elements not in the pruned MJCF: MuJoCo
  computes an actuator's transmission and a tendon's length and Jacobian at every step whatever the flags. The flags
  are per effect type, so an idle element of an acting effect is removed from the pruned MJCF too. What that saves:
  an input is an actuator less; a point spring or damper is a spatial tendon (one per pair of points, shared by a
  spring and a damper between them) whose length, Jacobian and force MuJoCo no longer computes once every element on
  it is removed; a joint spring or damper of an acting effect, or one of a tendon's two elements, is only a
  coefficient, 0 in the idle model already: the same compiled model, nothing saved (the quarter car's tyre damper).
  The idle model's loads are evaluated and applied at every stage of a step (its inputs held over the step), the
  pruned one's only where called for and not idle; loads of inputs and parameters alone (no state), where every
  input is piecewise constant and each load is a torque, or a force at its body's centre of mass, in world axes,
  are set as MuJoCo's ``xfrc_applied`` at each input change and held
  (:meth:`~harness.engines.mujoco_engine.MujocoModel.hold_loads`), as the actuators' inputs are: MuJoCo steps in its
  own loop, and an idle load of that kind costs what MuJoCo pays for it, not a Python call per step (measured: the
  quarter car's road force at 0 had made the idle run 5 × the pruned one). The pruned MJCF also leaves out the
  visual geoms (:class:`~harness.engines.mujoco_engine.VisualGeomsDropped`), which a run does not read and MuJoCo
  poses at every stage. With repeats, the idle run is also timed against the acting tree's (:func:`acting_tree`:
  the tree with the acting effects' elements alone), which no pruned model steps faster than: the bound of the ratio
  (:func:`attainable`). A scene whose motion switches at events has MuJoCo's own run in its event's plug-in (dry
  friction, contact): not measured here, except a friction held, where that run (MuJoCo's ``frictionloss``) is the
  idle one and the pruned one has nothing to step.

Constraint rows: where the tree's couplings and closures are proved inactive
(:func:`~harness.scenes.effects.constraint_rows_idle`: the governor's mirrored arms), the engines' constrained tree
(:mod:`harness.scenes.phenomena.closures`) is pruned to the open tree, a measurement of its own
(:func:`measure_rows`): Pinocchio's ``pin.aba`` against its KKT forward dynamics, MuJoCo without its equality
constraints; the check's proof is the closures plug-in's (``ROWS_CHECK``). Where the rows act (the toggle press),
the exported open tree :class:`MujocoStepper` steps is not the scene's motion: MuJoCo's runs are then the closures
plug-in's equality-constrained tree, the idle loads MuJoCo's site actuators (:func:`constrained_runs`).

Each source: the same trajectory (``ENGINE``, :mod:`harness.scenes.base`), checked by ``harness check`` from one
run of each (the proof), and the time ratio idle / pruned, measured by ``harness bench --parts pruning`` (the price):
``repeats`` pairs of runs in one process, each pair in turn pruned first and idle first (:func:`alternating`), one
worker on the machine (a single timing, or one taken while the check's other workers run, is noise): the median of
the pairs' ratios with its confidence interval (:func:`ratio_interval`, :data:`CONFIDENCE`). The system pages show
the bench's ratios (``bench.json``) beside the check's proof; a ratio whose whole interval is below 1 is a finding,
a target is met where the whole interval is at or above it. A scene that calls for every effect of its system, each
able to act, has nothing to prune: no ratio is reported.
"""

from __future__ import annotations

import math
import time

import numpy as np

from harness.engines import ENGINES, SYMBOLIC, steps_itself
from harness.engines.base import load_functions, loads_read_state
from harness.errors import NotApplicable
from harness.modeling.scenes import effects_of, pruned, with_idle_effects
from harness.modeling.system import JointInput
from harness.scenes import native, simulate as sim
from harness.scenes.base import ENGINE, Phenomenon, SceneRun
from harness.scenes.effects import infer

SOURCES = (SYMBOLIC, "pinocchio", "mujoco")
MUJOCO_STEPS = 2000        # RK4 steps of MuJoCo's own runs (at least; on the scene's grid, simulate.grid_steps)
CHECK = "pruned = all effects present but idle"
PRUNING_GOAL = 1.3         # idle / pruned, every source on every scene where something is pruned (issue 17)
RUN_METHOD = sim.ODEINT  # the runs our code integrates (symbolic, Pinocchio), without events: LSODA stepping in
    # Fortran, 0.46 µs of its own work an evaluation, against 5.7 µs for scipy's DOP853 stepping in Python (a linear
    # 8-state right-hand side at rtol 1e-10, 392 and 233 evaluations). That work is the same in the pruned and the idle
    # run, and no pruning saves it: DOP853's drew Pinocchio's tower_crane/swing to 1.16 × against 1.33 × a call
    # (bp31); odeint 1.43 × (bp35)


def run_method(scene, event) -> str:
    """The integrator of a pruning run our code integrates: :data:`RUN_METHOD`; DOP853 in an event's plug-in."""
    return RUN_METHOD if event is None and not scene.events else "DOP853"


# --------------------------------------------------------------------------- MuJoCo's own stepping, idle or pruned
class MujocoStepper:
    """MuJoCo's RK4 on the MJCF of the idle system (``model="idle"``: every effect present, its flags cleared);
    ``"pruned"``: the left-out effects switched off by their disable flags and their force elements not in the
    MJCF (MuJoCo computes an actuator's transmission and a tendon's length and Jacobian at every step whatever the
    flags), nor the idle force elements (``found.idle_elements``: the flags are per effect type), and only the
    called-for loads and inputs evaluated; ``"acting"``: the pruned model stripped to what its acting effects need
    (:class:`~harness.engines.mujoco_engine.ActingTree`), what no pruning of it can step faster than
    (:func:`attainable`). Loads that read no state and are constant ``xfrc_applied``
    (:meth:`~harness.engines.mujoco_engine.MujocoModel.holds`) are held between input changes; others are evaluated
    at every stage at the lecture state, as in :func:`~harness.scenes.simulate.mujoco_native` (both
    :func:`~harness.scenes.simulate.own_rollout`): identity or affine maps ``θ = φ(0) + J q``."""

    MODELS = ("idle", "pruned", "acting")

    def __init__(self, system, scene, model: str, dt: float, found=None):
        from harness.derivation.compile import compiled
        from harness.engines.mujoco_engine import ActingTree, MujocoModel, Options, VisualGeomsDropped, effect_flags
        from harness.export.numeric import instantiate

        if model not in self.MODELS:
            raise ValueError(f"model {model!r}: one of {', '.join(self.MODELS)}")
        found = found or infer(system, scene)
        idle_system, idle_scene = with_idle_effects(system, scene)
        every = effects_of(idle_system) | set(idle_scene.effects)
        left_out = every - found.simulated
        params = {**idle_system.default_parameters(), **idle_scene.params}
        transforms = [Options(timestep=dt, integrator="RK4", enable=effect_flags(every - {"friction", "contact"}))]
        prune = model != "idle"
        if prune:  # and the visual geoms, which no one reads in a run (VisualGeomsDropped)
            transforms += [Options(disable=effect_flags(left_out)), VisualGeomsDropped()]
        if model == "acting":
            transforms.append(ActingTree(found.simulated))
        without = found.idle_elements if prune else ()
        kept = pruned(idle_system, found.simulated, without) if prune else idle_system
        self.model = MujocoModel(instantiate(kept, params), transforms=transforms,
                                 where="MjSpec.compile (pruning" + (", acting tree)" if model == "acting" else ")"))
        self.flags = effect_flags(left_out) if prune else ()
        self.removed = sorted({f.name for f in idle_system.forces} - {f.name for f in kept.forces})
        self.c = compiled(idle_system)
        self.p = np.array([params[p.name] for p in idle_system.parameters])
        self.kept_p = np.array([params[p.name] for p in kept.parameters])
        self.loads = load_functions(kept)
        self.inputs = [f.input for f in kept.forces if isinstance(f, JointInput)]
        self.kept_inputs = [i.name for i in kept.inputs]                             # the loads' arguments
        self.scene, self.dt = idle_scene, dt
        u0 = idle_scene.u(0.0, idle_system)
        theta0, J, _ = self.c.map_at(np.asarray(scene.q0, float), np.asarray(scene.qd0, float), self.p, u0)
        self.theta0, self.theta_dot0 = theta0, J @ np.asarray(scene.qd0, float)
        self.held = sim.loads_held(self.model, self.loads, loads_read_state(kept))   # as xfrc_applied (own_rollout)
        self.at_lecture = None   # (θ, θ̇) -> (q, q̇): the loads MuJoCo does not hold, evaluated at every stage
        if self.loads and not self.c.affine and not self.held:
            raise NotApplicable("MuJoCo's own stepping with external loads needs an affine map θ = φ(0) + J q "
                                "(the loads are evaluated at the lecture state)")
        if self.loads and self.c.affine:
            phi0, _, J_inv = self.c.affine_map(self.p, u0)
            self.at_lecture = sim.lecture_state(phi0, J_inv)

    def run(self) -> sim.Trajectory:
        model, scene, dt = self.model, self.scene, self.dt
        model.reset()
        model.set_state(self.theta0, self.theta_dot0)
        steps = int(round(scene.horizon / dt))
        out, seconds = sim.own_rollout(model, scene, dt, "RK4", steps, self.inputs, self.loads, self.kept_p,
                                       self.kept_inputs, self.held, self.at_lecture,
                                       f"{scene.name} (pruning)")
        disabled = f", disabled {', '.join(self.flags)}" if self.flags else ""
        return sim.Trajectory(f"mujoco (mj_step RK4, dt={dt:g}{disabled})",
                              np.array([x[0] for x in out]), np.array([x[1] for x in out]),
                              np.array([x[2] for x in out]), seconds, steps)


# --------------------------------------------------------------------------- the measurement
def measure(system, scene, motion, event, catalogue=None, sources=SOURCES, repeats: int = 1,
            found=None) -> dict:
    """Idle against pruned by each of ``sources``: ``{"left_out": [effect], "left_out_elements": [force element],
    "held": [coordinate whose friction is held, proved never to switch],
    "sources": {source: {"pruned_seconds", "idle_seconds", "ratio", "ratio_low", "ratio_high", "error",
    "evaluations", "method", "pruned_all", "idle_all", "per_call" (a run our code integrates, with repeats:
    :func:`per_call`)} |
    {"skipped": why}}}``, or ``{"nothing": why}`` when the scene calls for every effect of its system and none of
    them, nor any force element, is found idle (``found``: :func:`~harness.scenes.effects.infer`). Runs alternate
    (:func:`alternating`): the seconds are the fastest of each, the ratio the median of the pairs' ratios within
    ``[ratio_low, ratio_high]`` (:func:`ratio_interval`; ``repeats`` 1: the proof alone, its ratio a single timing)."""
    found = found or infer(system, scene)
    idle_system, idle_scene = with_idle_effects(system, scene)
    lean_system, lean_scene = found.pruned(system, scene)
    if idle_scene is scene and lean_scene is scene:
        return {"nothing": "nothing to prune: the scene calls for every effect of the system, each can act"}
    out = {"left_out": sorted(set(idle_scene.effects) - set(lean_scene.effects)),
           "left_out_elements": sorted(found.idle_elements),
           "held": sorted(e.coordinate for e in lean_scene.events if getattr(e, "held", False)), "sources": {}}
    for source in sources:
        try:
            runs = _runs(lean_system, lean_scene, idle_system, idle_scene, motion, event, source, catalogue,
                         (system, scene, found))
        except (NotApplicable, NotImplementedError) as why:
            out["sources"][source] = {"skipped": str(why)}
            continue
        if runs is None:
            continue
        lean_run, full_run, method, acting = runs
        same = source != SYMBOLIC and same_force_elements(pruned(lean_system, lean_scene.effects),
                                                          pruned(idle_system, idle_scene.effects))
        if same:  # the proof, not a price
            lean, full = paired(lean_run, full_run, 1)
            out["sources"][source] = {"skipped": SAME_CALLS, "error": sim.max_error(full[0], lean[0]),
                                      "method": method}
            continue
        out["sources"][source] = timed(lean_run, full_run, repeats, method)
        if repeats > 1 and acting is not None:
            acting_run, what = acting
            out["sources"][source]["acting"] = acting_tree(acting_run(), full_run, repeats) | {"what": what}
        if repeats > 1 and not steps_itself(source) and len(set(out["sources"][source]["evaluations"])) == 1:
            out["sources"][source]["per_call"] = per_call(lean_system, lean_scene, idle_system, idle_scene, repeats,
                                                          source)
        if repeats > 1 and source == SYMBOLIC:
            try:
                out["sources"][source]["machine_code"] = machine_code(lean_system, lean_scene, idle_system,
                                                                      idle_scene, repeats)
            except NotApplicable as why:
                out["sources"][source]["machine_code"] = {"skipped": str(why)}
    return out


MACHINE_CODE = f"{native.METHOD} 1e-10"   # the symbolic runs with no evaluation leaving machine code


def machine_code(system, scene, idle_system, idle_scene, repeats: int) -> dict:
    """The symbolic runs in machine code (:mod:`harness.scenes.native`: our ẏ and DOP853 stepping compiled
    together, 1e-10): the pruned model's against the idle one's, ``repeats`` alternating pairs (:func:`timed`).
    What pruning saves where no call leaves machine code, without the ~3 µs of a call through Python that the
    runs of :data:`RUN_METHOD` pay in both models alike; a scene with events or with inputs that vary within a
    step is not for this path (``NotApplicable``)."""
    if scene.events:
        raise NotApplicable("its motion switches at events: not for the stepping in machine code")

    def run(s, sc):
        dynamics = sim.Dynamics(s, sc, SYMBOLIC)
        y0 = np.concatenate([sc.q0, sc.qd0]).astype(float)
        t_eval, n = sim.sample_times(sc), len(sc.q0)
        native.warm(dynamics.c, y0, dynamics.p, dynamics.inputs(0.0))   # compiled here, not timed

        def once():
            start = time.perf_counter()
            with np.errstate(all="ignore"):
                t, y, evaluations = native.solve_piecewise(dynamics.c, sc, y0, 1e-10, 1e-10, t_eval, dynamics.p,
                                                           dynamics.inputs, dynamics.hold)
            return sim.Trajectory(f"symbolic {native.METHOD}", t, y[:n].T, y[n:].T, time.perf_counter() - start,
                                  evaluations)
        return once

    return timed(run(system, scene), run(idle_system, idle_scene), repeats, MACHINE_CODE)


CLOSURE_STEPS = 4000   # MuJoCo's implicitfast steps of the constrained tree (at least; the closures plug-in's first dt)


def measure_rows(system, scene, found=None, repeats: int = 1) -> dict | None:
    """The constraint rows of the scene's tree proved inactive (:func:`harness.scenes.effects.constraint_rows_idle`)
    left out, by each engine that imposes them (:mod:`harness.scenes.phenomena.closures`): Pinocchio's open tree
    (``pin.aba``, DOP853 1e-10 without the step limit its Baumgarte stabilization needs) against its constrained
    tree (KKT ``pin.forwardDynamics``), MuJoCo's open tree (equality and constraint flags off) against its
    equality-constrained tree (implicitfast, the same ``dt``). ``{"left_out": [row], "proof", "sources": {source:
    :func:`price` with "error", "evaluations", "method"}}`` (with "skipped" and no sources on a scene with
    events); None where the scene's tree has no rows or they are needed."""
    from harness.scenes.phenomena import closures

    found = found or infer(system, scene)
    if not found.rows or not found.rows[0]:
        return None
    out = {"left_out": closures.rows_of(system, scene), "proof": found.rows[1], "sources": {}}
    if scene.events:  # the closures plug-in simulates its tree up to the event only
        return out | {"skipped": "a scene with events: its tree is simulated up to the event, not timed here"}
    dt = scene.horizon / sim.grid_steps(scene, CLOSURE_STEPS)
    runs = {"pinocchio": (lambda: closures.pinocchio_constrained(system, scene, rows=False),
                          lambda: closures.pinocchio_constrained(system, scene),
                          "open tree pin.aba against constrained tree pin.forwardDynamics (KKT, Baumgarte), "
                          "DOP853 1e-10"),
            "mujoco": (lambda: closures.mujoco_constrained(system, scene, dt, rows=False),
                       lambda: closures.mujoco_constrained(system, scene, dt),
                       f"open tree (equality, constraint flags off) against equality-constrained tree, implicitfast "
                       f"dt={dt:g}")}
    for source, (lean_run, full_run, method) in runs.items():
        out["sources"][source] = timed(lean_run, full_run, repeats, method)
    return out


def timed(pruned, idle, repeats: int, method: str) -> dict:
    """``repeats`` alternating pairs of the ``pruned`` and the ``idle`` run (:func:`paired`; more while the ratio is
    undecided against :data:`PRUNING_GOAL`): their :func:`price`, the first pair's trajectories compared (``error``:
    the proof), both runs' ``evaluations`` and ``method``."""
    lean, full = paired(pruned, idle, repeats, undecided(PRUNING_GOAL, runs=True))
    return {**_price_of(lean, full), "error": sim.max_error(full[0], lean[0]),
            "evaluations": [lean[0].evaluations, full[0].evaluations], "method": method}


def _price_of(pruned_runs, idle_runs) -> dict:
    """The :func:`price` of paired runs' trajectories (their ``seconds``)."""
    return price([t.seconds for t in pruned_runs], [t.seconds for t in idle_runs])


CALLS = 500   # right-hand-side calls per timing of :func:`per_call`


def acting_tree(acting, idle, repeats: int) -> dict:
    """Where MuJoCo's own run's time goes: its run of the acting tree (:class:`MujocoStepper` ``"acting"``: bodies,
    joints, inertias and the acting effects' elements alone, every other effect's disable flag set) against the idle
    one, ``repeats`` alternating pairs (more while undecided against :data:`PRUNING_GOAL`, :func:`undecided`): their
    :func:`price`. What no pruning of the tree that simulates the scene can step faster than: the bound of the run's
    ratio (:func:`attainable`)."""
    return _price_of(*paired(acting, idle, repeats, undecided(PRUNING_GOAL, runs=True)))


def per_call(system, scene, idle_system, idle_scene, repeats: int, source: str = SYMBOLIC) -> dict:
    """Where the time of a run our code integrates goes: one call of the right-hand side ``q̈(t, q, q̇)`` of
    ``source`` (:class:`~harness.scenes.simulate.Dynamics`: our compiled model, or the engine's forward dynamics
    with the force elements our adapter evaluates) of the pruned and of the idle model at the scene's initial state,
    :data:`CALLS` calls per timing, ``repeats`` alternating pairs (more while undecided, :func:`undecided`): their
    :func:`price` (seconds per call) and ``calls``. What pruning saves per evaluation, without the integrator's own
    work around it: the bound of the run's ratio (:func:`attainable`)."""
    lean, idle = sim.Dynamics(system, scene, source), sim.Dynamics(idle_system, idle_scene, source)
    q, qd = np.asarray(scene.q0, dtype=float), np.asarray(scene.qd0, dtype=float)

    def timing(dynamics):
        def run():
            start = time.perf_counter()
            for _ in range(CALLS):
                dynamics(0.0, q, qd)
            return (time.perf_counter() - start) / CALLS
        return run

    timing(lean)(), timing(idle)()  # the first calls compile: not timed
    return price(*paired(timing(lean), timing(idle), repeats, undecided(PRUNING_GOAL))) | {"calls": CALLS}


def _runs(system, scene, idle_system, idle_scene, motion, event, source, catalogue, given):
    """``(pruned run, idle run, method, acting)`` of ``source``, each run a call returning a trajectory, ``acting`` a
    call returning the run of the acting tree (MuJoCo's own stepping, :func:`acting_tree`; compiled only where timed)
    and what that tree is (:data:`ACTING`, :data:`ACTING_ROWS`), or None: ``system``, ``scene`` the pruned ones,
    ``given`` the scene's own ``(system, scene, found)``."""
    if steps_itself(source):  # an engine that steps the scene itself: its flags
        held = next((e for e in scene.events if getattr(e, "held", False)), None)
        if held is not None and motion.mujoco_run is not None:  # its plug-in's own run against nothing to step
            dt = scene.horizon / sim.grid_steps(scene, MUJOCO_STEPS)
            idle_event = next(e for e in idle_scene.events if type(e) is type(held))
            return (lambda: motion.simulate(system, scene, held, source, catalogue=catalogue),
                    lambda: motion.mujoco_run(idle_system, idle_scene, idle_event, dt),
                    f"its own run of the event's plug-in, dt={dt:g}, against the friction held: the joint stays at "
                    "rest, nothing to step", None)
        if event is not None or scene.events:
            raise NotApplicable("its motion switches at events: MuJoCo's own run of it is the event's plug-in's")
        own_system, own_scene, found = given
        if found.rows is not None and not found.rows[0]:  # MujocoStepper steps the exported tree: no equality rows
            return constrained_runs(system, scene, idle_system, idle_scene, found)
        dt = scene.horizon / sim.grid_steps(scene, MUJOCO_STEPS)
        lean = MujocoStepper(own_system, own_scene, "pruned", dt, found)
        full = MujocoStepper(own_system, own_scene, "idle", dt, found)
        how = ([f"disable flags {', '.join(lean.flags)}"] if lean.flags else []) + ["visual geoms dropped"]
        if lean.removed:
            how.append(f"not in the MJCF: {', '.join(lean.removed)}")
        if len(full.loads) > len(lean.loads):
            how.append("idle external loads not evaluated")
        held = [f"{m}'s" for m, stepper in (("idle", full), ("pruned", lean)) if stepper.held]
        if held:
            how.append(f"{' and '.join(held)} loads held as xfrc_applied between input changes")
        return (lean.run, full.run, f"mj_step RK4, dt={dt:g}, pruned: {'; '.join(how) or 'nothing'}",
                (lambda: MujocoStepper(own_system, own_scene, "acting", dt, found).run, ACTING))
    if source != SYMBOLIC and ENGINES[source].applies(system):
        raise NotApplicable(ENGINES[source].applies(system))

    if source == SYMBOLIC and same_right_hand_side(pruned(system, scene.effects),
                                                   pruned(idle_system, idle_scene.effects)):
        raise NotApplicable("the pruned and the idle model derive the same M, C, g, f_np (what is left out adds "
                            "no term, e.g. gravity orthogonal to every motion): nothing is pruned in this source")

    integrator = run_method(scene, event)

    def one(s, sc):
        own = event if event is None else next(e for e in sc.events if type(e) is type(event))  # e.g. held
        return lambda: motion.simulate(s, sc, own, source, method=integrator, rtol=1e-10, atol=1e-10,
                                       catalogue=catalogue)
    method = "our compiled right-hand side" if source == SYMBOLIC else f"{source} forward dynamics"
    if any(getattr(e, "held", False) for e in scene.events):
        method += ("; pruned: the friction held, proved to stick throughout (no breakaway guard to bound, "
                   "ẋ ≡ 0: the state stays the initial one)")
    return one(system, scene), one(idle_system, idle_scene), f"{method}, {integrator} 1e-10", None


def constrained_runs(system, scene, idle_system, idle_scene, found):
    """MuJoCo's own runs of a closed chain whose constraint rows act (``found.rows``, the toggle press): the closures
    plug-in's equality-constrained tree (:func:`~harness.scenes.phenomena.closures.mujoco_constrained`, implicitfast at
    its ``dt``), where :class:`MujocoStepper` steps the open exported tree. The idle system's loads are MuJoCo's site
    actuators (:func:`~harness.scenes.simulate.load_actuators`, idle: zero gears), which MuJoCo computes in its own
    step, as it holds other scenes' loads (``xfrc_applied``) where a load evaluated in Python per step would price our
    call, not MuJoCo; the pruned system has none, its left-out effects' disable flags set and its visual geoms
    dropped. Bound (:func:`attainable`): the constrained tree with the acting effects' elements alone, its rows kept
    (:class:`~harness.engines.mujoco_engine.ActingTree` ``rows``), at the same integrator and ``dt``, which steps
    faster than any model of it that simulates the scene. ``(pruned run, idle run, method, acting)`` as
    :func:`_runs`."""
    from harness.engines.mujoco_engine import ActingTree, Options, VisualGeomsDropped, effect_flags
    from harness.scenes.phenomena.closures import mujoco_constrained

    left_out = (effects_of(idle_system) | set(idle_scene.effects)) - found.simulated
    flags = effect_flags(left_out)
    dt = scene.horizon / sim.grid_steps(scene, CLOSURE_STEPS)
    lean_extra = ([Options(disable=flags)] if flags else []) + [VisualGeomsDropped()]
    # derived once, not at each timed run; refused where the idle loads are not forces MuJoCo can apply as actuators
    actuated = sim.load_actuators(idle_system, {**idle_system.default_parameters(), **idle_scene.params})
    if actuated is None:
        raise NotApplicable("its closed chain's constraint rows act and its external loads are not forces of the "
                            "inputs alone in world axes: MuJoCo's constrained run would evaluate them in Python")
    how = ([f"disable flags {', '.join(flags)}"] if flags else []) + ["visual geoms dropped",
                                                                     "idle loads' site actuators not in the MJCF"]
    return (lambda: mujoco_constrained(system, scene, dt, extra=lean_extra),   # the pruned system has no loads
            lambda: mujoco_constrained(idle_system, idle_scene, dt, load_actuators=actuated),
            f"equality-constrained tree (its rows act: {found.rows[1]}), implicitfast dt={dt:g}, loads as site "
            f"actuators, pruned: {'; '.join(how)}",
            (lambda: lambda: mujoco_constrained(system, scene, dt, extra=[*lean_extra, ActingTree(found.simulated,
                                                                                                    rows=True)]),
             ACTING_ROWS))


CONFIDENCE = 0.995  # of the interval of one time ratio (ratio_interval): a goal's verdict over up to 10 scenes
                    # of a source then holds with at least 95 % (Bonferroni: 10 x 0.5 %)
REPEATS = 21        # alternating pairs of runs the bench times: [r_(4), r_(18)] of their ratios, a 99.85 % interval.
                    # This machine's speed changes 2x from one 30 ms run to the next (measured: the same run 33-67 ms,
                    # CPU time as wall time, in phases of ~4 runs); 9 pairs' [min, max] left most targets undecided


LOOKS = 3           # blocks of REPEATS pairs at most (paired's undecided): each interval is taken at a confidence of
                    # 1 - (1 - CONFIDENCE) / LOOKS (Bonferroni over the looks), at 21 pairs the same [r_(4), r_(18)]


def paired(pruned, idle, repeats: int, undecided=None) -> tuple[list, list]:
    """``repeats`` pairs of calls of ``pruned`` and ``idle``, each pair in turn pruned first and idle first
    (:func:`alternating`): what each call returned, in order. With ``undecided`` (a predicate of the two lists so
    far, the verdict the pairs are taken for): another ``repeats`` pairs while it holds, :data:`LOOKS` blocks at most.
    A burst of the machine's noise in one block widens its interval over a target; more pairs outvote it rather
    than publish it as the verdict (ours / MuJoCo on series_rlc/lc_ring: [0.81, 1.08], undecided, in one bench run;
    [0.81, 0.87] at most in four others). A ratio within the resolution of its target stays undecided."""
    lean, full = [], []
    for k in range(repeats * LOOKS):  # one pair (a proof, not a price) is not looked at
        if k and k % repeats == 0 and not (undecided and repeats > 1 and undecided(lean, full)):
            break
        for run, into in alternating(k, (pruned, lean), (idle, full)):
            into.append(run())
    return lean, full


def undecided(target: float, runs: bool = False, at_most: bool = False):
    """The predicate on which :func:`paired` takes more pairs: their :func:`price` (of the runs' ``seconds`` where
    the calls return trajectories, ``runs``) undecided against ``target`` (:func:`against`); ``at_most``: a ratio
    that should be small, the first calls' over the second's (ours / an engine's, :func:`judged_at_most`). A ratio
    and its bounds (:func:`per_call`, :func:`acting_tree`) each, so that a bound too proves a target out of reach."""
    def holds(first, second) -> bool:
        if runs:
            first, second = [t.seconds for t in first], [t.seconds for t in second]
        if at_most:
            return judged_at_most(first, second, target)["verdict"] == "undecided"
        return against(price(first, second), target) == "undecided"
    return holds


def price(pruned_all, idle_all) -> dict:
    """The time ratio of :func:`paired` runs' seconds: ``{"pruned_seconds", "idle_seconds"}`` the fastest of each,
    ``ratio`` the median of the pairs' ratios within ``[ratio_low, ratio_high]`` (:func:`ratio_interval`), and
    every run's seconds (``pruned_all``, ``idle_all``)."""
    ratio, low, high = ratio_interval(idle_all, pruned_all)
    return {"pruned_seconds": min(pruned_all), "idle_seconds": min(idle_all), "ratio": ratio, "ratio_low": low,
            "ratio_high": high, "pruned_all": list(pruned_all), "idle_all": list(idle_all)}


def alternating(k: int, first, second) -> tuple:
    """The order of pair ``k``'s two runs: ``first`` ahead in even pairs, ``second`` in odd ones. A fixed order
    biases the ratio: measured on tower_crane/swing (symbolic), the second run of every pair ~2 % faster (24.4 ms
    pruned first against 24.0 ms idle second; per call the pruned right-hand side is 1.3 % the faster), 0.976 ×."""
    return (first, second) if k % 2 == 0 else (second, first)


def ratio_interval(idle_all, pruned_all) -> tuple[float, float, float]:
    """``(ratio, low, high)`` of alternating runs: the median of the pairs' ratios ``idle_k / pruned_k`` and its
    distribution-free confidence interval, the order statistics ``[r_(k), r_(n+1-k)]`` of the ``n`` sorted pair
    ratios with ``k`` the largest for which ``2 P(Bin(n, 1/2) ≤ k - 1) ≤ (1 - CONFIDENCE) / LOOKS`` (sign test:
    the true median ratio lies in it with probability at least :data:`CONFIDENCE` even after :data:`LOOKS` looks
    at growing pairs, :func:`paired`, whatever the timing noise's distribution; fewer pairs than that allows:
    ``[min, max]``; 9 pairs: ``[min, max]``, 99.6 %; 21: ``[r_(4), r_(18)]``, 99.85 %; 42: ``[r_(11), r_(32)]``;
    63: ``[r_(19), r_(45)]``). A pair's two runs share the machine's state (its load, its
    clock), so its ratio cancels what drifts between pairs, and a run the machine stalled or sped up moves one
    pair, not the median. The fastest run of each, the estimate before, is moved by one lucky run: measured
    0.613 × for governor/coast (symbolic), one idle run of five 25.7 ms against 44.7-49.0 ms; the same runs'
    pairs give 1.00 × in [0.55, 1.12]. At 95 % per interval one of the 30 intervals of a bench run (10 scenes,
    3 sources) was below 1 by chance: tower_crane/swing, symbolic, 0.988 × in [0.89, 0.9996]."""
    pairs = sorted(i / p for i, p in zip(idle_all, pruned_all) if p > 0)
    n = len(pairs)
    if not n:
        raise ValueError("no pair of runs to take a ratio of")
    median = float(np.median(pairs))
    k, tail = 0, 0.0
    while True:  # tail = P(Bin(n, 1/2) <= k)
        tail += math.comb(n, k) / 2 ** n
        if 2 * tail > (1 - CONFIDENCE) / LOOKS:
            break
        k += 1
    k = max(k, 1)  # r_(k) with k = 1 is the minimum: fewer than 6 pairs give [min, max]
    return median, pairs[k - 1], pairs[n - k]


RESOLUTION = 0.05
"""The smallest relative difference of two runs' times this bench resolves, added on either side of every ratio's
interval (:func:`interval`). The sign test assumes independent pairs, and this machine's speed drifts in phases
longer than a pair. Measured A/A (each scene's idle run against itself through the same 21 pairs, symbolic and
Pinocchio: ``.venv/bin/python -m harness.bench.resolution``), two runs: 1 interval of 44 and 1 of 48 missed 1 (by
1.5 % and 0.6 %, at a nominal 0.15 % chance each), the medians 0.91-1.13. And tower_crane/swing's symbolic ratio
read 0.967 [0.774, 0.995] in one bench run, 0.96-1.10 in five others, while its pruned right-hand side is 1-3 %
faster per call: without the resolution the "no scene slower" verdict flipped from one run to the next. Since the
runs are odeint's (:data:`RUN_METHOD`, shorter: 3-100 ms), the same A/A twice: 0 of 48 intervals missed 1 in each,
the medians 0.970-1.022."""


def interval(m: dict) -> tuple[float, float]:
    """What the bench can tell of a measured ratio ``m`` (a :func:`price`: :func:`measure`'s per-source entry, its
    ``per_call``, the contact pruning's): the confidence interval of its pairs (:func:`ratio_interval`) widened by
    :data:`RESOLUTION` on either side; ``(ratio, ratio)`` where it has no pairs (a single timing)."""
    if m.get("idle_all") and m.get("pruned_all"):
        return widened(*ratio_interval(m["idle_all"], m["pruned_all"])[1:])
    return m["ratio"], m["ratio"]


def widened(low: float, high: float) -> tuple[float, float]:
    """A confidence interval of alternating pairs (:func:`ratio_interval`) widened by :data:`RESOLUTION` on either
    side: what the bench can tell."""
    return low * (1 - RESOLUTION), high * (1 + RESOLUTION)


def slower_pruned(m: dict) -> str:
    """What a ratio idle / pruned below 1 is: "" at or above 1; no measurable difference where its confidence
    interval (:func:`interval`) reaches 1; else a finding (a pruning that makes a run slower)."""
    if m["ratio"] >= 1:
        return ""
    return "≈ 1: no measurable difference" if interval(m)[1] >= 1 else "finding: slower pruned"


def against(m: dict, target: float) -> str:
    """A measured ratio against a target: "met" (its whole confidence interval at or above it), "not met" (the
    whole interval below it), "undecided" (the interval holds the target: the repeats cannot tell)."""
    low, high = interval(m)
    return "met" if low >= target else "not met" if high < target else "undecided"


def judged_at_most(ours_all, theirs_all, target: float) -> dict:
    """Alternating pairs' seconds of ours and theirs (:func:`paired`) as a ratio that should be small: ``{"ratio":
    the median of ours / theirs, "ratio_low", "ratio_high": its interval (:func:`ratio_interval`), "verdict"}``
    against ``target`` (:func:`at_most`)."""
    ratio, low, high = ratio_interval(ours_all, theirs_all)
    out = {"ratio": ratio, "ratio_low": low, "ratio_high": high}
    return out | {"verdict": at_most(out, target)}


def at_most(m: dict, target: float) -> str:
    """A measured ratio that should be small (``{"ratio_low", "ratio_high"}``, an interval of alternating pairs, as
    ours / an engine's time) against a target, the other way round from :func:`against`: "met" where the whole
    interval, :func:`widened`, is at or below it, "not met" where it is wholly above, else "undecided"."""
    low, high = widened(m["ratio_low"], m["ratio_high"])
    return "met" if high <= target else "not met" if low > target else "undecided"


def attainable(m: dict, target: float) -> str:
    """Whether a target can be met at all (``m``: :func:`measure`'s per-source entry): "" where it can or nothing
    bounds it, else why not.

    * A run our code integrates (:data:`RUN_METHOD`), with its ``per_call``: the pruned and the idle run take the
      same steps (the same ``evaluations``: the idle terms are multiplied by 0, the error control sees the same
      state), so each run is ``N (c + o)``: ``N`` evaluations of the right-hand side at ``c`` seconds each and the
      integrator's own work ``o`` per evaluation, the same in both. Then ``idle / pruned = (c_idle + o) / (c_pruned
      + o) ≤ c_idle / c_pruned`` (for ``c_idle ≥ c_pruned``, ``o ≥ 0``): no run can be faster pruned than its
      right-hand side is.
    * MuJoCo's own run, with its ``acting`` (:func:`acting_tree`): the same steps of the same tree, and a pruned
      model that simulates the scene has every element of the acting tree (those of the effects that act), no more
      of the flags of what MuJoCo computes set and the same flags of how it computes, so each of its steps computes
      the acting tree's stages and more: ``idle / pruned ≤ idle / acting``.

    Where the high end of the bound's interval (:func:`interval`) is below ``target``, the target is out of reach of
    this source on this scene: what is pruned is too small a part of the run."""
    label, c = bound(m) or ("", None)
    if c is None or len(set(m.get("evaluations", ()))) != 1:
        return ""
    high = interval(c)[1]
    if high >= target:
        return ""
    if label == "per call":
        return (f"out of reach: one evaluation of the right-hand side is at most {high:.2f} × cheaper pruned "
                f"({c['idle_seconds'] * 1e6:.2f} / {c['pruned_seconds'] * 1e6:.2f} µs), and with the same "
                f"{m['evaluations'][0]} evaluations the run's ratio cannot exceed it")
    return (f"out of reach: the run of the acting tree ({c.get('what', ACTING)}) is at most {high:.2f} × faster "
            f"than the idle run ({c['idle_seconds'] * 1e3:.2f} / "
            f"{c['pruned_seconds'] * 1e3:.2f} ms over the same {m['evaluations'][0]} steps), and no pruned "
            "model that simulates the scene steps faster than the acting tree")


ACTING = ("bodies, joints, inertias and the acting effects' elements alone, every other effect's disable flag "
          "set")                                                   # what an acting tree is (ActingTree)
ACTING_ROWS = ("bodies, joints, inertias, constraint rows (the equalities and the sites they join) and the acting "
               "effects' elements alone, every other effect's disable flag set")   # a closed chain's (ActingTree rows)


def bound(m: dict) -> tuple[str, dict] | None:
    """What bounds a measured ratio (:func:`measure`'s per-source entry) from above, as ``(label, its price)``:
    ``("per call", …)`` for a run our code integrates (:func:`per_call`), ``("acting tree", …)`` for MuJoCo's own
    (:func:`acting_tree`); None without (a single timing, an event's plug-in)."""
    if m.get("per_call"):
        return "per call", m["per_call"]
    if m.get("acting"):
        return "acting tree", m["acting"]
    return None


def same_right_hand_side(pruned_system, idle_system) -> bool:
    """Whether the two models derive the same expressions of ``M``, ``C``, ``g``, ``f_np`` (then their compiled
    right-hand sides are the same function and a time ratio would measure noise)."""
    from harness.derivation.compile import compiled

    a, b = compiled(pruned_system).derivation, compiled(idle_system).derivation
    return all(getattr(a, k) == getattr(b, k) for k in ("M", "C", "g", "f_np"))


SAME_CALLS = ("the pruned and the idle model have the same force elements: the engine makes the same calls on "
              "both (what is left out is a number of its model, e.g. the gravity vector), so a time ratio would "
              "measure noise; the trajectories are compared")


def same_force_elements(pruned_system, idle_system) -> bool:
    """Whether the two models have the same force elements (springs, dampers, inputs, loads): then an engine's
    forward dynamics evaluates the same elements and makes the same calls on both, and a time ratio would measure
    noise (gravity is a vector of the engine's model, the same work whether it is 0 or not)."""
    def elements(system):
        return sorted((type(f).__name__, f.name) for f in system.forces)
    return elements(pruned_system) == elements(idle_system)


class Pruning(Phenomenon):
    name = "pruning"

    def check(self, run: SceneRun) -> None:
        """The effects inferred beside the declared ones (notes; a disagreement is a note, not fixed); idle against
        pruned by every source, one run each: the same trajectory (``ENGINE``). The time ratio is the bench's."""
        system, scene, result = run.system, run.scene, run.result
        found = infer(system, scene)
        result.notes.update(found.notes())
        measured = measure(system, scene, run.motion, run.event, run.catalogue,
                           sources=(SYMBOLIC,) + tuple(e for e in run.engines if e in SOURCES), found=found)
        if "nothing" in measured:
            result.notes["pruning"] = measured["nothing"]
            return
        result.notes["pruning: effects left out"] = ", ".join(measured["left_out"]) or "none"
        if measured["left_out_elements"]:
            result.notes["pruning: force elements left out"] = ", ".join(measured["left_out_elements"])
        if measured["held"]:
            result.notes["pruning: friction held"] = ", ".join(measured["held"])  # it never switches
        for source, m in measured["sources"].items():
            if "skipped" in m:
                result.notes[f"pruning, {source}"] = f"not measured: {m['skipped']}"
                if "error" not in m:
                    continue
            result.add(ENGINE.check(CHECK, source, m["error"], detail=m["method"]))


PLUGIN = Pruning()
