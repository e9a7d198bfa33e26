"""Scenes: trajectories of Pinocchio and MuJoCo (scipy-integrated forward dynamics, MuJoCo's own integrator, its
dry friction and contact) against the confirmed symbolic reference, events, invariants and pruning
(harness/scenes/base.py and the plug-ins of harness/scenes/phenomena/ state the tolerances and their reasons).

The default run checks one scene per mechanism of the machinery (conservative swing with MuJoCo's RK4, input
breakpoints, a nonlinear closed-chain map, stick-slip events with MuJoCo's frictionloss, rolling contact and
its threshold, the trebuchet's lift-off); ``harness check`` (the README's main command) and ``pytest -m slow``
run every scene of every system."""

import numpy as np
import pytest

import models
from harness.scenes.trajectories import run_scene

ALL = [(name, scene) for name in models.catalogue() for scene in models.scenes(name)]
DEFAULT = {("pendulum", "swing"), ("quarter_car", "bump"), ("toggle_press", "return"), ("stick_slip", "stick_slip"),
           ("rolling_sphere", "rolls"), ("trebuchet", "throw")}


def _check(name, scene):
    result = run_scene(models.get(name), scene, catalogue=models.CATALOGUE)
    failed = [c for c in result.checks if not c.passed]
    assert not failed, failed
    assert any(c.name.startswith("trajectory") for c in result.checks) or "contact" in scene.effects
    proofs = {c.source for c in result.checks if c.name == "pruned = all effects present but idle"}
    if result.notes.get("pruning", "").startswith("nothing to prune"):  # no proof (and no ratio) "by construction"
        assert not proofs
    else:  # a proof for the symbolic path, unless what is pruned adds no term there (said, not measured)
        assert ("symbolic" in proofs) != ("nothing is pruned in this source" in result.notes.get("pruning, symbolic", ""))
        assert "pinocchio" in proofs
    assert "effects inferred to act" in result.notes
    return result


@pytest.mark.parametrize("name, scene", [(n, s) for n, s in ALL if (n, s.name) in DEFAULT],
                         ids=[f"{n}-{s.name}" for n, s in ALL if (n, s.name) in DEFAULT])
def test_scene(name, scene):
    _check(name, scene)


@pytest.mark.slow
@pytest.mark.parametrize("name, scene", ALL, ids=[f"{n}-{s.name}" for n, s in ALL])
def test_every_scene(name, scene):
    _check(name, scene)


def test_every_system_has_a_scene():
    assert [name for name in models.catalogue() if not models.scenes(name)] == []


def test_default_scenes_exist():
    assert DEFAULT <= {(n, s.name) for n, s in ALL}


def test_stick_slip_switches_at_the_predicted_threshold():
    """(3.80): breakaway exactly where |f_e| = mu_H m g, then stick and slip alternate in both directions."""
    from harness.scenes.phenomena import stick_slip

    system, scene = models.get("stick_slip"), models.scenes("stick_slip")[0]
    event = scene.events[0]
    ref = stick_slip.stick_slip(system, scene, event, "symbolic")
    assert abs(ref.events[0].time - stick_slip.predicted_breakaway(system, scene, event)) < stick_slip.EVENT.value
    assert [e.after for e in ref.events[:4]] == ["slide +", "stick", "slide -", "stick"]


def test_a_stuck_mass_needs_no_integration_and_its_breakaway_is_the_guards_root():
    """At rest the state is held and the guard is a function of time through the inputs alone: with forces affine
    in the inputs a bound over the segment proves sticking without a scan (stick_slip/holds: three forward-dynamics
    calls), and otherwise the scan finds the same breakaway as the guard evaluated call by call; a force already
    beyond the limit where the segment starts breaks away there."""
    from harness.scenes.phenomena import stick_slip

    system = models.get("stick_slip")
    scenes = {s.name: s for s in models.scenes("stick_slip")}
    assert stick_slip.affine_in_inputs(system)
    holds = stick_slip._StickSlipDynamics(system, scenes["holds"], scenes["holds"].events[0], "symbolic")
    assert holds.breakaway(0.0, scenes["holds"].horizon, np.array(scenes["holds"].q0)) == (None, 3)
    scene = scenes["stick_slip"]
    h = stick_slip._StickSlipDynamics(system, scene, scene.events[0], "symbolic")
    q = np.array(scene.q0)
    affine, calls = h.breakaway(0.0, scene.horizon, q)
    h.affine = False
    exact, scanned = h.breakaway(0.0, scene.horizon, q)
    assert calls == 3 and scanned > 40 and abs(affine - exact) < 1e-13   # 40 grid points to 0.31 s, then brentq
    assert abs(affine - stick_slip.predicted_breakaway(system, scene, scene.events[0])) < 1e-12
    phases = stick_slip.sticking_phases(system, scene, scene.events[0], stick_slip.stick_slip(system, scene,
                                                                                             scene.events[0],
                                                                                             "symbolic"))
    assert len(phases) == 4 and all(abs(found - predicted) < 1e-12 for _, found, predicted in phases)
    assert h.breakaway(0.5, scene.horizon, q) == (0.5, 1)   # |f_e(0.5)| = 3.53 N > mu_H f_N = 2.94 N


def _friction_oscillator(cubic: float = 0.0):
    """A block on a spring (k = 100 N/m) sliding on a rough floor (mu_H = 0.3, mu_C = 0.2; Den Hartog 1931's free
    motion), released from rest at x_0 = 0.1 m; ``cubic``: a hardening term ``-k_3 x³`` added to the spring."""
    from sympy import sign

    from harness.modeling import (WORLD, Coordinate, Gravity, Joint, JointSpring, Link, Parameter, Point, PointForce,
                                  Scene, StickSlip, System, standard_gravity)

    m, k = Parameter("m", 1.0, "kg", "block"), Parameter("k", 100.0, "N/m", "spring")
    k_3 = Parameter("k_3", cubic or 1.0, "N/m^3", "hardening of the spring")
    mu_H, mu_C = Parameter("mu_H", 0.3, "1", "static friction"), Parameter("mu_C", 0.2, "1", "sliding friction")
    g, x = standard_gravity(), Coordinate("x", "m", "position of the block")
    contact = Point("block", (0, 0, 0), "contact")
    forces = (JointSpring("spring", "x", k, 0),
              PointForce("sliding_friction", contact, (-mu_C * m * g * sign(x.rate), 0, 0)))
    if cubic:
        forces += (PointForce("hardening", contact, (-k_3 * x**3, 0, 0)),)
    system = System(name="friction_oscillator", title="friction oscillator", lecture="test", parameters=(mu_H,),
                    coordinates=(x,), links=(Link("block", m),), joints=(Joint("x", "prismatic", WORLD, "block",
                                                                                       axis="x"),),
                    gravity=Gravity(g, (0, 0, -1)), forces=forces)
    scene = Scene("decay", "", (0.1,), (0.0,), 1.5, {"springs", "friction", "external"},
                  events=(StickSlip(x, mu_H, mu_C, m * g),))
    return system, scene


def test_a_spring_holds_the_block_where_its_pull_is_within_static_friction():
    """Released at 0.1 m, the block slides back (its spring's 10 N beyond mu_H m g = 2.94 N), turns at
    0.1 − 2 mu_C m g / k after half a period π sqrt(m/k), and stops for good a half period later at
    0.1 − 4 mu_C m g / k = 0.0215 m, where the spring's 2.15 N lies between mu_C m g and mu_H m g. MuJoCo's own dry
    friction sees the turn and the stop through the velocity's change of sign and its friction row's state (with
    mu_C m g it crept on and stopped a half period late, at 0.94 s; with a velocity threshold alone, a hardening
    spring's 1e-10 m/s of creep read as sliding) and stays within its derived first-order bound."""
    from harness.scenes import simulate as sim
    from harness.scenes.phenomena import stick_slip

    system, scene = _friction_oscillator()
    event = scene.events[0]
    ref = stick_slip.stick_slip(system, scene, event, "symbolic")
    half = np.pi * np.sqrt(1.0 / 100.0)
    assert [(e.before, e.after) for e in ref.events] == [("slide -", "slide +"), ("slide +", "stick")]
    assert abs(ref.events[0].time - half) < 1e-9 and abs(ref.events[1].time - 2 * half) < 1e-9
    assert abs(ref.q[-1, 0] - (0.1 - 4 * 0.2 * 9.81 / 100.0)) < 1e-9
    assert [(p, f) for _, f, p in stick_slip.sticking_phases(system, scene, event, ref)] == [(np.inf, np.inf)]
    dt = scene.horizon / sim.grid_steps(scene, 4000)
    run = stick_slip.mujoco_stick_slip(system, scene, event, dt)
    assert [(e.before, e.after) for e in run.events] == [("slide", "slide"), ("slide", "stick")]
    late = [(b.time - a.time) / dt for a, b in zip(ref.events, run.events)]
    assert all(0 < d <= 1 for d in late), late
    assert sim.max_error(run, ref) / dt <= stick_slip.frictionloss_bound(system, scene, event, ref)


def test_the_frictionloss_bound_is_not_claimed_for_a_sliding_force_it_does_not_bound():
    """The derived bound covers a sliding force of time alone or of a linear spring and damper, whose offsets never
    grow; a hardening spring's stiffness changes along the motion: no bound, and the scene says why instead of a
    check; MuJoCo's event times are still checked."""
    from harness.scenes.phenomena import stick_slip

    system, scene = _friction_oscillator(cubic=2000.0)
    ref = stick_slip.stick_slip(system, scene, scene.events[0], "symbolic")
    assert stick_slip.frictionloss_bound(system, scene, scene.events[0], ref) is None
    result = run_scene(system, scene)
    assert result.notes["MuJoCo frictionloss first-order constant"] == stick_slip.UNBOUNDED
    names = {c.name for c in result.checks}
    assert "MuJoCo frictionloss event times, s" in names and not any("first-order constant" in n for n in names)
    assert all(c.passed for c in result.checks), [c for c in result.checks if not c.passed]


def test_the_lift_off_is_where_pinocchios_own_constraint_force_vanishes(monkeypatch):
    """The trebuchet's lift-off is located where the normal force of the phase-2 projection vanishes
    (``G^T λ = M₂ (q̈₂ − a₂)``); Pinocchio's constraint force, the multiplier of the ground's row in its KKT forward
    dynamics, is the same force by another method: equal at the start (49.05 N, to round-off) and zero at the
    reference's lift-off (its zero within 1.6e-16 s of it). A normal force 1 N off, in every source, still
    switches consistently across them; only Pinocchio's own force finds it (both checks fail)."""
    from harness.scenes.phenomena import lift_off

    system, scene = models.get("trebuchet"), models.scenes("trebuchet")[0]
    names = ("normal force at the start", "lift-offs where Pinocchio's constraint force")

    def ours(result):
        return [c for c in result.checks if c.name.startswith(names)]

    right = ours(run_scene(system, scene, engines=("pinocchio",), catalogue=models.CATALOGUE))
    assert [c.passed for c in right] == [True, True] and right[0].value < 1e-14 and right[1].value < 1e-12
    normal_force = lift_off._LiftOffDynamics.normal_force
    monkeypatch.setattr(lift_off._LiftOffDynamics, "normal_force", lambda self, t, y: normal_force(self, t, y) - 1.0)
    wrong = ours(run_scene(system, scene, engines=("pinocchio",), catalogue=models.CATALOGUE))
    assert [c.passed for c in wrong] == [False, False]


def test_rolling_sphere_rolls_above_and_slips_below_the_threshold():
    """Exercise 3.17: MuJoCo's contact rolls at 1.01 x 2/7 tan(alpha) and slips at 0.99 x."""
    from harness.scenes.phenomena import rolling

    system, scene = models.get("rolling_sphere"), models.scenes("rolling_sphere")[0]
    event = scene.events[0]
    mu = event.predicted(system.default_parameters())
    above = rolling.mujoco_rolling(system, scene, event, 1e-3, 1.01 * mu)
    below = rolling.mujoco_rolling(system, scene, event, 1e-3, 0.99 * mu)
    scale = float(above.qd.max()) * system.default_parameters()["R"]
    assert rolling.rolls(above, scale) and not rolling.rolls(below, scale)


def test_every_kind_of_event_has_its_plug_in():
    """A scene's event is simulated by the plug-in whose ``event`` it is (harness/scenes/phenomena/__init__.py)."""
    import inspect

    from harness.modeling import events
    from harness.scenes.phenomena import BY_EVENT

    kinds = {c for _, c in inspect.getmembers(events, inspect.isclass) if c.__module__ == events.__name__
             and not c.__name__.startswith("_")}
    assert kinds and kinds == set(BY_EVENT)


def test_a_new_phenomenon_plugs_in_without_touching_the_loop(monkeypatch):
    """The loop asks every plug-in of CHECKS after the motion, in order: a plug-in added there records its check
    after the motion's, and one that does not apply is never asked to check."""
    from harness.checks import Bound
    from harness.scenes import phenomena, trajectories
    from harness.scenes.base import Phenomenon

    asked = []

    class Probe(Phenomenon):
        def __init__(self, applies):
            self._applies = applies

        def applies(self, run):
            return self._applies

        def check(self, run):
            asked.append(self._applies)
            assert "reference" in run.result.trajectories  # the motion ran first
            run.result.add(Bound("probe", 1.0, "a test plug-in").check("probe", "symbolic", 0.5))

    monkeypatch.setattr(trajectories, "CHECKS", (Probe(False), Probe(True)))
    result = run_scene(models.get("pendulum"), models.scenes("pendulum")[0], engines=("pinocchio",))
    assert asked == [True] and result.checks[-1].name == "probe"
    assert phenomena.CHECKS != trajectories.CHECKS


def test_our_models_reference_is_kept_bit_for_bit_and_integrated_again_when_it_cannot_be_named(tmp_path, monkeypatch):
    """The symbolic reference (``integrate(..., keep=True)``) is kept on disk and read back with every bit; another
    tolerance is another entry, a damaged entry is integrated again, and a scene with an input of a model's own
    (a function whose text does not say what it computes) is integrated on every run. Engines are never kept."""
    import dataclasses

    import harness.kept
    from harness.scenes import simulate as sim

    monkeypatch.setattr(harness.kept, "cache_dir", lambda: tmp_path / "derivations")
    system = models.get("quarter_car")
    scene = next(s for s in models.scenes("quarter_car") if s.name == "bump")
    solved = []
    solve_piecewise = sim.solve_piecewise
    monkeypatch.setattr(sim, "solve_piecewise", lambda *a, **k: solved.append(1) or solve_piecewise(*a, **k))

    def reference(sc=scene, source="symbolic", rtol=1e-10):
        tr = sim.integrate(system, sc, source, rtol=rtol, atol=rtol, keep=True)
        return tr.t.tobytes(), tr.q.tobytes(), tr.qd.tobytes(), tr.evaluations, tr.energies().tobytes()

    first = reference()
    assert len(solved) == 1 and reference() == first and len(solved) == 1
    assert sim.integrate(system, scene, "symbolic", rtol=1e-10, atol=1e-10).q.tobytes() == first[1]  # as computed
    assert len(solved) == 2
    reference(rtol=1e-9)
    assert len(solved) == 3 and len(list((tmp_path / "trajectories").iterdir())) == 2
    for entry in (tmp_path / "trajectories").iterdir():
        entry.write_text(entry.read_text().replace("[", "[1.5, ", 2))   # damaged: the checksum fails
    assert reference() == first and len(solved) == 4
    reference(source="pinocchio")
    reference(source="pinocchio")
    assert len(solved) == 6                                           # an engine's run: made every time
    own = dataclasses.replace(scene, inputs={name: (lambda t, f=f: f(t)) for name, f in scene.inputs.items()})
    assert sim.scene_identity(own) is None
    assert reference(own) == reference(own) and len(solved) == 8


def test_an_input_step_does_not_leak_into_the_piece_before_it():
    """series_rlc/step: u steps to 10 V at 0.1 s. Restarted at the breakpoint, DOP853 and LSODA (odeint) evaluate
    the right-hand side at the piece's end t = 0.1 s or within round-off of it (a last stage, LSODA up to its critical
    time), where the step already says 10 V: with the inputs held over each piece (``Dynamics.hold``) every
    evaluation of the first piece sees 0 V, every one of the second 10 V, and after the run the inputs are u(t)
    again."""
    import numpy as np

    from harness.scenes import simulate as sim

    system = models.CATALOGUE.get("series_rlc")
    scene = next(s for s in models.CATALOGUE.scenes("series_rlc") if s.name == "step")
    (jump,) = scene.breakpoints
    for integrate in (lambda rhs, y0, hold: sim.solve_piecewise(rhs, scene, y0, "DOP853", 1e-10, 1e-10,
                                                                sim.sample_times(scene), on_piece=hold),
                      lambda rhs, y0, hold: sim.odeint_piecewise(rhs, scene, y0, 1e-10, 1e-10,
                                                                 sim.sample_times(scene), on_piece=hold)):
        dyn = sim.Dynamics(system, scene, "symbolic")
        n = len(system.coordinates)
        pieces = []

        def hold(a, b=None):   # the pieces in order, each with the evaluations made in it
            if a is not None:
                pieces.append([])
            dyn.hold(a, b)

        def rhs(t, y):
            pieces[-1].append((t, float(dyn.inputs(t)[0])))
            return np.concatenate([y[n:], dyn(t, y[:n], y[n:])])

        integrate(rhs, np.concatenate([scene.q0, scene.qd0]), hold)
        first, second = pieces
        assert all(u == 0.0 for _, u in first) and all(u == 10.0 for _, u in second)
        assert max(t for t, _ in first) >= jump - 1e-12 and max(t for t, _ in first) <= jump   # up to its end
        assert dyn.held is None and dyn.inputs(0.2)[0] == 10.0 and scene.inputs["u"](jump) == 10.0


def test_an_input_given_as_a_number_is_a_constant_and_anything_else_not_a_signal_is_refused():
    """``inputs={"f": 0.2}`` had failed deep in a simulation with "'float' object is not callable": a number is a
    ``Constant``; what is neither a number nor a signal, or a number that is not finite, is one error naming it."""
    from harness.errors import InputError
    from harness.modeling import Constant, Scene

    scene = Scene("pushed", "a constant push", (0.0,), (0.0,), 1.0, {"inputs"}, inputs={"f": 0.2})
    assert scene.inputs == {"f": Constant(0.2)} and scene.inputs["f"](0.7) == 0.2
    for value, says in (("0.2", "is not a signal"), (float("nan"), "must be finite"), (True, "is not a signal")):
        with pytest.raises(InputError, match=says):
            Scene("pushed", "", (0.0,), (0.0,), 1.0, {"inputs"}, inputs={"f": value})


def _trajectory(error: float):
    """A trajectory of x(t) = sin t off by ``error · t`` (its rate by ``error``), sampled as the scenes sample."""
    from harness.scenes import simulate as sim

    t = np.linspace(0.0, 1.0, 201)
    return sim.Trajectory("synthetic", t, (np.sin(t) + error * t)[:, None], (np.cos(t) + error)[:, None], 0.0, 0)


@pytest.mark.parametrize("case", ["small K", "large K", "second order"])
def test_soft_constraints_are_extrapolated_past_a_large_second_order_term(case):
    """MuJoCo's soft constraints (first order) are extrapolated to dt → 0: Richardson's from two runs, Romberg's
    once there are three, which cancels the ``dt²`` term too; dt is halved until the extrapolation is within its
    margin and the error first order. Synthetic runs with errors ``K dt + K₂ dt²``: the four-bar's ``K`` = 1500 per
    second with ``K₂`` = 7e6 per second², which reproduces its Richardson residual 1.4e-2 after three halvings from
    dt = 5e-4 (Richardson's alone would need seven); a catalogue-like ``K`` = 10 per second that Richardson
    settles at once; a second-order error, which has no first-order model to extrapolate: a finding."""
    from harness.scenes.base import SOFT_REFINEMENTS, SceneResult, soft_convergence

    K, K2 = {"small K": (10.0, 100.0), "large K": (1500.0, 7e6), "second order": (0.0, 4e4)}[case]
    steps = []

    def run(dt):
        steps.append(round(1.0 / dt))
        return _trajectory(K * dt + K2 * dt**2)

    result = SceneResult("synthetic", "synthetic")
    soft_convergence(result, "soft", run, _trajectory(0.0), 5e-4)
    limit, order = result.checks
    if case == "small K":  # Richardson's residual K₂ dt²/2 = 1.2e-5 at once
        assert steps == [2000, 4000] and limit.passed and order.passed and "Romberg" not in limit.detail
    elif case == "large K":  # halved until first order (K₂ dt / K ≤ 0.35); Romberg's residual is round-off
        assert steps == [2000, 4000, 8000, 16000, 32000]
        assert limit.passed and limit.value < 1e-12 and order.passed and "Romberg" in limit.detail
    else:
        assert limit.passed and not order.passed and len(steps) == SOFT_REFINEMENTS + 2


@pytest.mark.parametrize("case", ["model floor", "not settled", "second order"])
def test_mujocos_rk4_order_is_taken_against_its_own_steps(monkeypatch, case):
    """The order of MuJoCo's RK4 comes from its own runs at dt, dt/2, dt/4, not from the errors against our
    reference: a model difference (our export's stand-in inertia, amplified by an unstable motion: 1.7e-9 on a double
    inverted pendulum) is a floor those errors meet, and read as order 1.6 where the steps converge at order 4. Where
    the order has not settled (a violent motion), dt is halved and the order taken again; a method of order 2 stays
    a finding. Synthetic runs of a 1 s scene (600 grid steps at first): error ``C h⁴`` plus, per case, a constant
    2e-8, a term ``B h²`` that only steps finer than 1/3500 are free of, or ``B h²`` alone."""
    from harness.modeling import Scene
    from harness.scenes import simulate as sim
    from harness.scenes.base import SceneResult, SceneRun
    from harness.scenes.phenomena import smooth

    system = models.get("pendulum")
    scene = Scene("synthetic", "", (0.5,), (0.0,), 1.0, {"gravity"})

    def error(h):
        if case == "model floor":
            return 1e4 * h**4 + 2e-8
        if case == "not settled":
            return 1e4 * h**4 + (0.15 * h**2 if h > 1 / 3500 else 0.0)
        return 1e-2 * h**2
    monkeypatch.setattr(sim, "mujoco_native", lambda system, scene, dt, integrator="RK4": _trajectory(error(dt)))
    result = SceneResult(system.name, scene.name)
    result.trajectories["reference"] = _trajectory(0.0)
    smooth.mj_step(SceneRun(system, scene, ("mujoco",), result))
    order = next(c for c in result.checks if "order deficit" in c.name)
    halved = result.notes.get("mj_step RK4 steps halved: the order had not settled", 0)
    if case == "model floor":
        e1, e2 = result.notes["mj_step RK4 error against the reference at dt, dt/2"]
        assert 4 - np.log2(e1 / e2) > 1                                 # against the reference: a finding
        assert order.passed and order.value < 0.1 and not halved        # against its own steps: order 4
    elif case == "not settled":
        assert order.passed and halved == 1
    else:
        assert not order.passed and halved == smooth.RK4_REFINEMENTS and order.value > 1.9
