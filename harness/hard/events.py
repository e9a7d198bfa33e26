"""Structural changes, by reference to the lecture's own scenes: stick-slip (3.80) (``models/stick_slip.py``)
and the trebuchet's lift-off (Exercise A.15, ``models/trebuchet.py``). Their event location lives in
their plug-ins (:mod:`harness.scenes.phenomena.stick_slip`, ``lift_off``) and is checked by
:func:`harness.scenes.trajectories.run_scene`; here the same checks are
collected into the catalogue, next to the naive run: the model's smooth branch integrated across the switch
without locating it."""

from __future__ import annotations

import dataclasses

import numpy as np

from harness.scenes import simulate as sim
from harness.scenes.base import ENGINE_EVENT_TOL, ENGINE_TOL, EVENT_TOL, REFERENCE_TOL, event_error
from harness.hard.common import ENGINES, CaseResult

NAIVE_BUDGET = 200_000  # right-hand side evaluations the naive run may spend


class _OverBudget(Exception):
    pass


def _scene(catalogue, system_name: str, kind: str):
    """The first scene of ``system_name`` with an event of class ``kind`` (None if there is none yet)."""
    for scene in catalogue.scenes(system_name):
        if any(type(e).__name__ == kind for e in getattr(scene, "events", ())):
            return scene
    return None


def _by_reference(catalogue, case_id, title, system_name, kind, problem, remedy, quick) -> CaseResult:
    system = catalogue.get(system_name)
    scene = _scene(catalogue, system_name, kind)
    if scene is None:
        r = CaseResult(case_id, title, [system_name], "pending", problem, remedy)
        r.notes.append(f"no scene of {system_name} with a {kind} event in the scenes of {system_name} yet")
        return r
    from harness.scenes.phenomena import BY_EVENT
    r = CaseResult(case_id, f"{title} (scene {system_name}/{scene.name})", [system_name], "event location",
                   problem, remedy)
    event = next(e for e in scene.events if type(e).__name__ == kind)
    motion = BY_EVENT[type(event)]

    def hybrid(*args, **kw):
        return motion.simulate(*args, catalogue=catalogue, **kw)
    ref = hybrid(system, scene, event, "symbolic")                       # DOP853 1e-12, events located
    second = hybrid(system, scene, event, "symbolic", method="LSODA")
    r.check("reference confirmed (LSODA vs DOP853)", "symbolic", sim.max_error(second, ref), REFERENCE_TOL,
            "harness/scenes/base.py")
    r.check("events confirmed (LSODA vs DOP853), s", "symbolic", event_error(second, ref), EVENT_TOL,
            "harness/scenes/base.py")
    for source in ENGINES:
        tr = hybrid(system, scene, event, source, rtol=1e-10, atol=1e-10)
        r.check("trajectory (DOP853 1e-10, events)", source, sim.max_error(tr, ref), ENGINE_TOL,
                "harness/scenes/base.py")
        r.check("event times, s", source, event_error(tr, ref), ENGINE_EVENT_TOL,
                "harness/scenes/base.py")
    r.numbers["events (reference)"] = [(round(e.time, 9), e.before, e.after) for e in getattr(ref, "events", [])]
    r.notes.append(f"the scene's full checks (MuJoCo's own frictionloss / equality constraints, pruning) run in "
                   f"tests/test_scenes.py ({system_name}-{scene.name})")
    # naive: the model's own smooth branch across the switch, no event located, with an evaluation budget
    smooth = dataclasses.replace(scene, events=())
    dyn = sim.Dynamics(system, smooth, "symbolic")
    n = len(dyn.system.coordinates)
    reached = [0.0]

    def rhs(t, y):
        if dyn.evaluations >= NAIVE_BUDGET:
            raise _OverBudget
        reached[0] = max(reached[0], t)
        return np.concatenate([y[n:], dyn(t, y[:n], y[n:])])
    from scipy.integrate import solve_ivp
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(rhs, (0.0, scene.horizon), np.concatenate([scene.q0, scene.qd0]), method="DOP853",
                            rtol=1e-10, atol=1e-10, dense_output=True)
        t_naive = ref.t[ref.t <= sol.t[-1]]
        q_naive = sol.sol(t_naive)[0]
        value = float(np.max(np.abs(q_naive - ref.q[:len(t_naive), 0]))) / max(1.0, float(np.max(np.abs(ref.q[:, 0]))))
        r.numbers["naive"] = {"evaluations": dyn.evaluations, "status": sol.message}
    except _OverBudget:
        t_naive, q_naive, value = np.array([]), np.array([]), float("inf")
        r.numbers["naive"] = {"evaluations": dyn.evaluations,
                              "status": f"gave up after {NAIVE_BUDGET} evaluations at t = {reached[0]:.6g} s "
                                        f"(horizon {scene.horizon:g} s): the step size collapsed at the switch"}
    except Exception as why:  # noqa: BLE001 - the naive run failing is the finding
        t_naive, q_naive, value = np.array([]), np.array([]), float("inf")
        r.numbers["naive"] = {"evaluations": dyn.evaluations, "status": f"{type(why).__name__}: {why}"[:300]}
    r.naive = {"what": "the model's smooth branch integrated across the switch (no event located), DOP853 1e-10",
               "metric": f"largest error of {system.coordinates[0].name} against the reference (relative, scale ≥ 1; "
                         "inf: no result within the evaluation budget)", "value": value}
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(ref.t, ref.q[:, 0], label="with events (reference)")
    if len(t_naive):
        ax.plot(t_naive, q_naive, "r--", label="smooth branch, no event")
    else:
        ax.axvline(reached[0], color="r", ls="--", label=f"naive run stuck at t = {reached[0]:.3g} s")
    for e in getattr(ref, "events", []):
        ax.axvline(e.time, color="k", ls=":", lw=0.8)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(system.coordinates[0].name)
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    r.figure = fig
    return r


def stick_slip(catalogue, quick: bool = False) -> CaseResult:
    return _by_reference(
        catalogue,         "stick_slip_events", "Stick-slip switching (3.80)", "stick_slip", "StickSlip",
        "Coulomb friction f_C = mu_C f_N sgn(x_dot) has no value at x_dot = 0: integrated as a smooth right-hand "
        "side the mass never sticks (the sign flips every step around rest) and the breakaway at "
        "|f_e| = mu_H f_N is missed.",
        "Both events located (breakaway |f_required| = mu_H f_N, sticking x_dot = 0) with the branch switched at "
        "each, in every source (harness/scenes/phenomena/stick_slip.py); MuJoCo's own frictionloss checked for first-order "
        "convergence.", quick)


def trebuchet_lift_off(catalogue, quick: bool = False) -> CaseResult:
    return _by_reference(
        catalogue,         "trebuchet_lift_off", "Trebuchet lift-off (Exercise A.15)", "trebuchet", "LiftOff",
        "Phase 1 keeps the projectile on the ground through the map (A.178); continued past the instant its normal "
        "force vanishes, the ground pulls the projectile down: a wrong motion without any numerical symptom.",
        "The normal force is computed from each source's dynamics and its zero located as an event; the "
        "integration continues in phase 2 (trebuchet_free) from the mapped state (harness/scenes/phenomena/lift_off.py).", quick)
