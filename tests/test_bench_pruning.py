"""``harness bench --parts pruning``: per-source ratios, findings and goals in bench.md (from a made-up document;
the measurement itself: tests/test_effects.py)."""

import numpy as np
import pytest

from harness.bench import report


def _row(system, scene, ratios):
    return {"system": system, "scene": scene, "declared": ["gravity"], "inferred": ["gravity"],
            "inferred_idle": {"inputs": "drive: input tau ≡ 0 over [0, 3] s"}, "idle_elements": {},
            "declared_idle": [], "undeclared_acting": ["dampers"], "repeats": 5, "left_out": ["inputs"],
            "sources": {s: {"pruned_seconds": 1.0, "idle_seconds": r, "ratio": r, "error": 0.0,
                            "evaluations": [10, 10], "method": "m", "pruned_all": [1.0, 1.0, 1.0],
                            "idle_all": [r * 0.99, r, r * 1.01]} for s, r in ratios.items()}}


def test_pruning_rows_goals_and_findings():
    rows = [_row("governor", "coast", {"symbolic": 0.9, "pinocchio": 1.5, "mujoco": 8.0}),
            {"system": "pendulum", "scene": "swing", "nothing": "nothing to prune", "inferred_idle": {}},
            _row("quarter_car", "smooth_road", {"symbolic": 1.1, "pinocchio": 1.4,
                                                "mujoco": 1.0})]
    rows[2]["sources"]["mujoco"] = {"skipped": "an affine map is needed"}
    text = "\n".join(report._pruning(rows))
    # the interval of the pairs [0.891, 0.909] widened by the bench's resolution (pruning.RESOLUTION, 5 %)
    assert "0.900 × [0.85, 0.95] (900.0 / 1000.0 ms) **finding: slower pruned**" in text
    assert "No effect to prune (no ratio): pendulum/swing." in text
    assert "not measured: an affine map is needed" in text
    assert "can act but not declared: dampers" in text
    goals = {(g["check"].split(":")[0], g["source"]): g for g in report._pruning_goals(rows)}
    assert not goals[("pruning pays", "symbolic")]["passed"]          # 0.9 × < 1.3 ×
    assert goals[("pruning pays", "pinocchio")]["passed"]             # 1.4 × worst, low end 1.32 ≥ 1.3 ×
    assert not goals[("no scene slower pruned", "symbolic")]["passed"]
    assert goals[("no scene slower pruned", "mujoco")]["passed"] and ("pruning pays", "mujoco") in goals
    assert goals[("pruning pays", "symbolic")]["verdict"] == "not met"
    assert goals[("pruning pays", "pinocchio")]["verdict"] == "met"
    contact = {"system": "lightweight_robot", "scene": "fall", "source": "mujoco", "method": "mj_step RK4",
               "collision_geoms": 17, "meshes": 9, "left_out": [], "first_contact": 0.2365,
               "first_contact_pairs": [["a", "b"]], "whole_horizon_error": 1.5, "measured_horizon": 0.235,
               "pruned_seconds": 0.016, "idle_seconds": 0.048, "ratio": 3.0, "error": 0.0, "repeats": 5}
    assert "the arm touches itself at t = 0.2365 s" in "\n".join(report._contact(contact))
    doc = {"pruning": rows, "pruning_contact": contact}
    assert any(g["check"].startswith("contact detection pruned") and g["passed"] for g in report.goals(doc))
    # a ratio whose interval holds the target is undecided, in the goal table too
    contact.update(ratio=3.1, idle_all=[2.9, 3.1, 3.3], pruned_all=[1.0, 1.0, 1.0])
    goal = next(g for g in report.goals(doc) if g["check"].startswith("contact detection pruned"))
    assert goal["verdict"] == "undecided" and not goal["passed"]
    doc.update(goals=report.goals(doc), command="harness bench", generated="2026-11-26", quick=False, seconds=1.0,
               versions={},
               machine={"cpus": 2, "loadavg_start": [0.0, 0.0, 0.0], "loadavg_end": [0.0, 0.0, 0.0]})
    text = report.markdown(doc)
    assert "| **undecided** |" in text
    # shown the way round it is stated: idle / pruned at least 3, the low end of the interval (kept inverted)
    low = 1.0 / goal["value"]
    assert goal["at_least"] == 3.0 and f"| ≥ 3 × | {low:.3g} × | **undecided** |" in text
    assert "slower pruned (the whole interval below 1 ×, a finding) on 1 of 2 scenes" in text
    # what "undecided" means is said only where a scene is: here every pruning ratio is met or not met
    assert "≥ 1.3 × not met on 2 of 2 scenes" in text and "(undecided: the interval holds 1.3" not in text


def test_the_pruning_figure_draws_each_measured_ratio_and_writes_one_off_the_scale(tmp_path):
    """bench/pruning.svg: a row per thing left out that has a ratio, one marker per measured source (the run; its
    bound open), a ratio beyond the axis written at its edge; the bench page shows it in the pruning section."""
    from harness.bench import figures

    rows = [_row("governor", "coast", {"symbolic": 0.9, "pinocchio": 1.5}),
            _row("stick_slip", "holds", {"mujoco": 885.0}),
            {"system": "pendulum", "scene": "swing", "nothing": "nothing to prune", "inferred_idle": {}}]
    rows[0]["sources"]["pinocchio"]["per_call"] = {"pruned_seconds": 1e-6, "idle_seconds": 2e-6, "ratio": 2.0}
    figures.draw_all({"pruning": rows}, tmp_path)
    svg = (tmp_path / "bench" / "pruning.svg").read_text()
    assert "governor/coast" in svg and "stick_slip/holds" in svg and "pendulum/swing" not in svg
    assert "885 ×" in svg and "1.3 × (the goal)" in svg
    assert "](bench/pruning.svg)" in "\n".join(report._pruning(rows))


def test_contact_is_proved_idle_until_just_before_the_arm_touches_itself():
    """The clearance bound along the pruned run (every step, every geom pair MuJoCo considers) ends at or before
    the first contact MuJoCo's own run with contact on finds, and not far before it (the bound is a proof, and a
    tight one); over the proved interval contact on and pruned give the same motion."""
    from harness.bench import contact_pruning
    from harness.catalogue import repository

    c = contact_pruning.task(repository(), repeats=1)
    assert c["first_contact"] is not None and c["collision_pairs"] > 0
    assert 0.9 * c["first_contact"] <= c["certified_contact_free"] <= c["first_contact"]
    assert c["error"] == 0.0 and c["measured_horizon"] <= c["certified_contact_free"]
    assert c["pruned_geoms"] == 0   # the collision geometry and the visual geoms no run reads: dropped


def test_a_ratio_below_one_is_a_finding_only_beyond_the_noise_of_its_pairs():
    """The measured case (two_mass_oscillator/twisted, symbolic, ms): the pruned function is 0.3 % faster per call,
    one idle run was 2 % faster than the others — 0.988 x from the fastest runs, no measurable difference: the
    pairs' median 0.996 x, its interval reaches 1. A pruned run slower in every pair by about the same amount is a
    finding."""
    from harness.scenes.phenomena.pruning import ratio_interval, slower_pruned

    noisy = {"pruned_all": [215.6, 210.0, 209.6, 210.5, 216.9], "idle_all": [214.6, 209.2, 209.5, 211.0, 207.0]}
    noisy["ratio"] = ratio_interval(noisy["idle_all"], noisy["pruned_all"])[0]
    assert round(noisy["ratio"], 3) == 0.996
    assert slower_pruned(noisy) == "≈ 1: no measurable difference"
    slower = {"pruned_all": [220.0, 221.0, 219.5, 220.4, 222.0], "idle_all": [209.0, 210.1, 208.8, 209.5, 210.0]}
    slower["ratio"] = ratio_interval(slower["idle_all"], slower["pruned_all"])[0]
    assert slower_pruned(slower) == "finding: slower pruned"
    # 2 % slower in every one of 21 pairs: within the bench's resolution (pruning.RESOLUTION, from A/A runs that
    # missed 1 by up to 1.5 %), no finding
    close = {"pruned_all": [100.0] * 21, "idle_all": [98.0 + 0.01 * k for k in range(21)]}
    close["ratio"] = ratio_interval(close["idle_all"], close["pruned_all"])[0]
    assert ratio_interval(close["idle_all"], close["pruned_all"])[2] < 1
    assert slower_pruned(close) == "≈ 1: no measurable difference"


def test_the_ratio_is_the_median_of_the_pairs_within_its_sign_test_interval():
    """The measured governor/coast (symbolic, ms, five pairs): one idle run the machine sped up to 25.7 ms made the
    fastest-of-each ratio 0.613 x; the pairs' median is 1.00 x, the interval [min, max] of five pairs holds 1. At
    99.5 %, nine pairs give [min, max] (2 P(Bin(9, 1/2) <= 0) = 0.0039 <= 0.005, with k = 2 0.039), fifteen
    [r_(2), r_(14)] (0.00098; with k = 3, 0.0074 > 0.005), and the interval holds the median."""
    from harness.scenes.phenomena.pruning import alternating, ratio_interval

    # each pair in turn pruned first and idle first: an order effect cancels
    assert [alternating(k, "pruned", "idle") for k in range(3)] == [("pruned", "idle"), ("idle", "pruned"),
                                                                    ("pruned", "idle")]
    pruned, idle = [48.3, 41.9, 44.6, 48.3, 46.5], [46.4, 47.0, 44.7, 49.0, 25.7]
    assert round(min(idle) / min(pruned), 3) == 0.613
    ratio, low, high = ratio_interval(idle, pruned)
    assert round(ratio, 2) == 1.00 and low < 1 < high
    assert (low, high) == (min(i / p for i, p in zip(idle, pruned)), max(i / p for i, p in zip(idle, pruned)))
    nine = [float(k) for k in range(1, 10)]
    assert ratio_interval(nine, [1.0] * 9) == (5.0, 1.0, 9.0)
    fifteen = [float(k) for k in range(1, 16)]
    assert ratio_interval(fifteen, [1.0] * 15) == (8.0, 2.0, 14.0)


def test_more_pairs_are_taken_while_the_verdict_is_undecided():
    """bwp12's series_rlc/lc_ring: ours / MuJoCo's RK4 read [0.81, 1.08] over 21 pairs, undecided against 1 ×, where
    four other bench runs read [0.81, 0.87] at most: a burst of noise in a block. Another block of pairs is taken while
    the verdict the pairs are for is undecided, LOOKS blocks at most, and the interval is taken at CONFIDENCE /
    LOOKS (Bonferroni over the looks: at 21 pairs still [r_(4), r_(18)], at 42 [r_(11), r_(32)]). A ratio within the
    resolution of its target stays undecided after every block; one that is decided is not timed again."""
    from harness.scenes.phenomena.pruning import LOOKS, at_most, judged_at_most, paired, ratio_interval

    def runs(seconds):
        it = iter(seconds)
        return lambda: next(it)

    # the first block: 8 pairs of a burst (ratio 1.1) among 13 at 0.85: the 18th of 21 sorted ratios is 1.1
    ours = [0.85] * 13 + [1.1] * 8 + [0.85] * 21 + [0.85] * 21
    undecided = []

    def verdict(a, b):
        undecided.append((len(a), judged_at_most(a, b, 1.0)["verdict"]))
        return undecided[-1][1] == "undecided"

    a, b = paired(runs(ours), runs([1.0] * 63), 21, verdict)
    assert undecided == [(21, "undecided"), (42, "met")] and len(a) == len(b) == 42
    assert at_most(judged_at_most(a, b, 1.0), 1.0) == "met"       # [r_(11), r_(32)] = [0.85, 0.85] widened: 0.89
    assert ratio_interval([float(k) for k in range(1, 43)], [1.0] * 42)[1:] == (11.0, 32.0)
    # within the resolution of the target: every block looked at, then the pairs stop
    undecided.clear()
    a, b = paired(runs([0.98] * 63), runs([1.0] * 63), 21, verdict)
    assert undecided == [(21, "undecided"), (42, "undecided")] and len(a) == 21 * LOOKS
    # decided after the first block, or no verdict asked for, or a single pair (a proof): no more pairs
    assert len(paired(runs([0.5] * 21), runs([1.0] * 21), 21, verdict)[0]) == 21
    assert len(paired(runs([0.98] * 21), runs([1.0] * 21), 21)[0]) == 21
    assert len(paired(runs([0.98]), runs([1.0]), 1, verdict)[0]) == 1
    # the pruning's predicate: idle / pruned against a target, of seconds or of runs' seconds (their bounds too)
    from types import SimpleNamespace
    from harness.scenes.phenomena.pruning import undecided as pruning_undecided
    assert pruning_undecided(1.3)([1.0] * 21, [1.3] * 21) and not pruning_undecided(1.3)([1.0] * 21, [2.0] * 21)
    trajectories = [SimpleNamespace(seconds=1.0)] * 21, [SimpleNamespace(seconds=1.3)] * 21
    assert pruning_undecided(1.3, runs=True)(*trajectories) and not pruning_undecided(1.0, runs=True)(*trajectories)
    # ours / an engine's, which should be small (the duel, the evaluation goals)
    assert pruning_undecided(1.0, at_most=True)([0.98] * 21, [1.0] * 21)
    assert not pruning_undecided(1.0, at_most=True)([0.5] * 21, [1.0] * 21)

def test_the_price_of_a_dop853_run_is_also_taken_per_call(monkeypatch):
    """With repeats, the entry of a source integrated by DOP853 (symbolic, Pinocchio) also times one call of the
    right-hand side of the pruned and of the idle model (what pruning saves per evaluation, without the integrator
    around it): per-call seconds, the pairs' median ratio within its interval, and the bench table shows it. The
    symbolic runs are also timed in machine code (``machine_code``: its own test). MuJoCo's own stepping has no
    integrator of ours around it: no per-call entry."""
    from harness.bench import report
    from harness.bench.workprecision import pruning_task
    from harness.catalogue import repository
    from harness.errors import NotApplicable
    from harness.scenes.phenomena import pruning

    def not_here(*args):   # the runs in machine code compile two models (~30 s): their own test, marked slow
        raise NotApplicable("compiled in test_the_runs_in_machine_code_…")

    monkeypatch.setattr(pruning, "machine_code", not_here)
    row = pruning_task(repository(), "quarter_car", "smooth_road", repeats=3)
    for source in ("symbolic", "pinocchio"):
        c = row["sources"][source]["per_call"]
        assert c["calls"] == 500 and 0 < c["pruned_seconds"] < 1e-3 and 0 < c["idle_seconds"] < 1e-3
        assert c["ratio_low"] <= c["ratio"] <= c["ratio_high"]
    assert "per_call" not in row["sources"]["mujoco"]
    acting = row["sources"]["mujoco"]["acting"]   # MuJoCo's bound: its run of the acting tree against the idle one
    assert acting["ratio_low"] <= acting["ratio"] <= acting["ratio_high"]
    # 3 pairs, and 3 more at each look that was undecided against 1.3 × (pruning.paired): [min, max] of 3 often is
    from harness.scenes.phenomena.pruning import LOOKS, undecided
    n = len(acting["idle_all"])
    assert n == len(acting["pruned_all"]) and n in range(3, 3 * LOOKS + 1, 3)
    assert all(undecided(1.3)(acting["pruned_all"][:k], acting["idle_all"][:k]) for k in range(3, n, 3))
    assert n == 3 * LOOKS or not undecided(1.3)(acting["pruned_all"], acting["idle_all"])
    assert row["sources"]["symbolic"]["machine_code"] == {"skipped": "compiled in test_the_runs_in_machine_code_…"}
    assert "machine_code" not in row["sources"]["pinocchio"]
    line = next(x for x in report._pruning([row]) if x.startswith("| quarter_car/smooth_road"))
    assert "; per call " in line and " µs)" in line and "; acting tree " in line
    assert "; in machine code not measured: compiled in test_the_runs_in_machine_code_…" in line


@pytest.mark.slow   # two models compiled to machine code, ~15 s each
def test_the_runs_in_machine_code_take_the_same_steps_pruned_and_idle():
    """The symbolic runs in machine code (our ẏ and DOP853 stepping compiled together, no call through Python):
    the pruned and the idle model take the same steps to the same motion, and their ratio is measured as the
    others are; the bench table shows it beside the runs through Python."""
    import models
    from harness.modeling.scenes import with_idle_effects
    from harness.scenes.effects import infer
    from harness.scenes.phenomena import pruning

    system = models.get("quarter_car")
    scene = next(s for s in models.CATALOGUE.scenes("quarter_car") if s.name == "smooth_road")
    idle_system, idle_scene = with_idle_effects(system, scene)
    native = pruning.machine_code(*infer(system, scene).pruned(system, scene), idle_system, idle_scene, 3)
    assert native["method"] == "DOP853 (machine code) 1e-10" and native["error"] == 0.0
    assert native["evaluations"][0] == native["evaluations"][1] > 0
    assert native["ratio_low"] <= native["ratio"] <= native["ratio_high"] and 0 < native["pruned_seconds"] < 1.0
    row = _row("quarter_car", "smooth_road", {"symbolic": 1.0})
    row["sources"]["symbolic"]["machine_code"] = native
    assert "; in machine code " in next(x for x in report._pruning([row]) if x.startswith("| quarter_car/"))


def test_mujoco_pruned_leaves_out_the_elements_of_left_out_effects_and_the_acting_tree_all_but_what_acts():
    """planar_manipulator/swing leaves out its inputs, springs and dampers: the pruned MJCF has their flags set and
    neither the actuators nor the tendon of the point spring and damper (MuJoCo computes a transmission and a
    tendon's length and Jacobian whatever the flags); its acting tree (gravity alone acts) has its bodies and joints
    alone, every flag of what MuJoCo computes set but gravity's, and the flags of how it computes as the pruned
    model has them; the pruned run is the idle one's motion, and so is the acting tree's."""
    import mujoco

    from harness.bench.workprecision import get_scene
    from harness.catalogue import repository
    from harness.scenes import simulate as sim
    from harness.scenes.effects import infer
    from harness.engines.mujoco_engine import WHAT_FLAGS
    from harness.scenes.phenomena.pruning import MUJOCO_STEPS, MujocoStepper

    system, scene = get_scene(repository(), "planar_manipulator", "swing")
    found, dt = infer(system, scene), scene.horizon / sim.grid_steps(scene, MUJOCO_STEPS)
    idle, lean, acting = (MujocoStepper(system, scene, m, dt, found) for m in ("idle", "pruned", "acting"))
    full, pruned_, tree = idle.model.model, lean.model.model, acting.model.model
    assert full.nu == 2 and full.ntendon == 1 and pruned_.nu == 0 and pruned_.ntendon == 0
    assert {"motor_1", "motor_2", "spring_e", "damper_e"} <= set(lean.removed)
    assert pruned_.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_ACTUATION
    assert (tree.nbody, tree.njnt) == (full.nbody, full.njnt) and tree.ngeom == tree.nsite == tree.nu == 0
    assert found.simulated == {"gravity"}
    what = {int(mujoco.mjtDisableBit.__members__[n]) for n in WHAT_FLAGS}
    gravity = int(mujoco.mjtDisableBit.mjDSBL_GRAVITY)
    assert all(tree.opt.disableflags & b for b in what - {gravity}) and not tree.opt.disableflags & gravity
    how = sum(int(b) for n, b in mujoco.mjtDisableBit.__members__.items() if n != "mjNDISABLE") - sum(what)
    assert tree.opt.disableflags & how == pruned_.opt.disableflags & how
    run = lean.run()
    assert sim.max_error(idle.run(), run) < 1e-12 and sim.max_error(run, acting.run()) < 1e-12
    with pytest.raises(ValueError, match="one of idle, pruned, acting"):
        MujocoStepper(system, scene, "lean", dt, found)


def test_loads_of_inputs_alone_are_held_where_mujoco_applies_them():
    """A load that reads no state, of inputs that are piecewise constant, is MuJoCo's ``xfrc_applied`` held between
    input changes (no Python call per step) where that is exact: a torque in world axes (two_mass_oscillator), a
    force in world axes at its body's centre of mass (the quarter car's road force, the spherical pendulum's f_e);
    not a follower force (cantilever_beam) nor one off the centre of mass (planar_robot). The held run is the motion
    of the loads evaluated at every stage, and ``xfrc_applied`` gives MuJoCo's q̈ of ``qfrc_applied`` at a state."""
    import mujoco

    from harness.bench.workprecision import get_scene
    from harness.catalogue import repository
    from harness.engines.base import Load
    from harness.scenes import simulate as sim
    from harness.scenes.phenomena.pruning import MUJOCO_STEPS, MujocoStepper

    catalogue = repository()
    for name, label in (("two_mass_oscillator", "twisted"), ("quarter_car", "smooth_road"),
                        ("spherical_pendulum", "conical")):
        system, scene = get_scene(catalogue, name, label)
        dt = scene.horizon / sim.grid_steps(scene, MUJOCO_STEPS)
        idle = MujocoStepper(system, scene, "idle", dt)
        assert idle.held and idle.loads
        held = idle.run()
        idle.held = False      # the loads evaluated and applied at every stage instead (MuJoCo's control callback)
        assert sim.max_error(held, idle.run()) < 1e-12, name
    model, ((kind, where, frame),) = idle.model, idle.loads     # the spherical pendulum's f_e at the bob
    theta, theta_dot = np.array([0.7, -1.2]), np.array([0.4, 2.0])
    force = Load(kind, where, frame, np.array([1.5, -0.5, 2.0]))
    qdd_applied = model.forward_dynamics(theta, theta_dot, {}, [force])
    model.reset()
    model.set_state(theta, theta_dot)
    model.hold_loads([force])
    mujoco.mj_forward(model.model, model.data)
    assert np.allclose(model.data.qacc[model.dof_index], qdd_applied, rtol=1e-12, atol=1e-12)
    for name, load in (("cantilever_beam", "follower_force"), ("planar_robot", "f_e")):
        dyn = sim.Dynamics(catalogue.get(name), catalogue.scenes(name)[0], "mujoco")
        kind, where, frame = dyn.load_functions[0]
        assert not dyn.model.holds(kind, where, frame), name
        with pytest.raises(ValueError, match="not a constant xfrc_applied"):
            dyn.model.hold_loads([Load(kind, where, frame, np.ones(3))])


def test_a_target_above_what_one_evaluation_saves_is_out_of_reach():
    """With the same evaluations in both runs, idle / pruned of a DOP853 run is at most that of one call of its
    right-hand side: a target above the per-call interval's high end is out of reach of that source on that scene
    (said, with the per-call seconds); within it, or with other evaluation counts, nothing is said."""
    from harness.scenes.phenomena.pruning import attainable

    pairs = [1.0 + 0.01 * k for k in range(21)]          # per call 1.0 … 1.2: high end ≤ 1.2 × 1.05 < 1.3
    per_call = {"ratio": 1.1, "idle_seconds": 11e-6, "pruned_seconds": 10e-6, "idle_all": pairs,
                "pruned_all": [1.0] * 21}
    m = {"ratio": 1.05, "evaluations": [1172, 1172], "per_call": per_call}
    why = attainable(m, 1.3)
    assert why.startswith("out of reach") and "1172 evaluations" in why and "11.00 / 10.00 µs" in why
    assert attainable(m, 1.2) == ""                       # within the per-call interval: it may be met
    assert attainable({**m, "evaluations": [1172, 1180]}, 1.3) == ""
    assert attainable({k: v for k, v in m.items() if k != "per_call"}, 1.3) == ""
    # MuJoCo's own stepping: no pruned model steps faster than the acting tree (its run against the idle one)
    acting = {"ratio": 1.1, "idle_seconds": 11e-3, "pruned_seconds": 10e-3, "idle_all": pairs,
              "pruned_all": [1.0] * 21}
    why = attainable({"ratio": 1.05, "evaluations": [2000, 2000], "acting": acting}, 1.3)
    assert why.startswith("out of reach: the run of the acting tree") and "11.00 / 10.00 ms" in why
    more = {**acting, "idle_all": [1.5] * 21}
    assert attainable({"ratio": 1.05, "evaluations": [2000, 2000], "acting": more}, 1.3) == ""


def test_an_undecided_scene_out_of_reach_is_not_met():
    """The goal's verdict of a scene whose run interval holds 1.3 × but whose right-hand side per call cannot reach
    it is "not met" (the bound leaves no room the noise could hide), and it stays "undecided" within reach."""
    from harness.bench.report import _verdict

    wide = [1.1 + 0.02 * k for k in range(21)]                       # runs: 1.10 … 1.50, the interval holds 1.3
    per_call = {"ratio": 1.1, "idle_seconds": 11e-6, "pruned_seconds": 10e-6,
                "idle_all": [1.0 + 0.005 * k for k in range(21)], "pruned_all": [1.0] * 21}   # at most ≈ 1.14
    m = {"ratio": 1.3, "idle_all": wide, "pruned_all": [1.0] * 21, "evaluations": [100, 100], "per_call": per_call}
    assert _verdict({k: v for k, v in m.items() if k != "per_call"}, 1.3) == "undecided"
    assert _verdict(m, 1.3) == "not met"
    reach = {**m, "per_call": {**per_call, "idle_all": [1.5] * 21}}
    assert _verdict(reach, 1.3) == "undecided"


def test_constraint_rows_pruned_are_their_own_measurement():
    """A scene whose tree's constraint rows are proved inactive has a second measurement beside its effects': the
    constrained tree / the open tree per engine, in its own table and in the goals as "… (constraint rows)"."""
    row = _row("governor", "coast", {"symbolic": 1.0, "pinocchio": 1.0, "mujoco": 1.3})
    timing = {"pruned_seconds": 1.0, "idle_seconds": 2.0, "ratio": 2.0, "error": 1e-12, "evaluations": [10, 20],
              "method": "m", "pruned_all": [1.0] * 3, "idle_all": [1.9, 2.0, 2.1]}
    row["rows"] = {"left_out": ["coupling alpha_2 = -2 alpha_1"], "proof": "proved",
                   "sources": {"pinocchio": timing, "mujoco": {**timing, "idle_all": [0.9, 1.0, 1.1],
                                                               "ratio": 1.0, "idle_seconds": 0.9}}}
    text = "\n".join(report._pruning([row]))
    assert "### Constraint rows pruned" in text and "coupling alpha_2 = -2 alpha_1" in text
    assert "2.00 × [1.80, 2.21] (2000.0 / 1000.0 ms, 20 / 10 evaluations)" in text
    goals = {(g["check"].split(":")[0], g["source"]): g for g in report._pruning_goals([row])}
    assert "governor/coast (constraint rows) 2.00 ×" in goals[("pruning pays", "pinocchio")]["detail"]
    assert goals[("pruning pays", "mujoco")]["verdict"] == "not met"   # its rows at 1.0 ×, the effects' at 1.3 ×
    assert "symbolic" in {s for _, s in goals}   # the effects' measurement alone
    press = {"system": "toggle_press", "scene": "return", "nothing": "nothing to prune",
             "constraint_rows": {"inactive": False, "why": "at q = [0.1] the tree's balance asks for 2 N m"}}
    text = "\n".join(report._pruning([row, press]))
    assert "Constraint rows needed, kept (a state where the constraints must act): toggle_press/return (at q" in text


def test_only_a_source_that_does_not_apply_is_skipped(monkeypatch):
    """A source whose method does not apply to the scene (:class:`~harness.errors.NotApplicable`) is skipped with
    its reason; any other error, a ``ValueError`` of a bug too, fails the measurement instead of reading as a
    skip (a wrong unpacking in the loads' code had read "skipped: not enough values to unpack")."""
    from harness.catalogue import repository
    from harness.errors import NotApplicable
    from harness.scenes.phenomena import pruning

    catalogue = repository()
    system, scene = catalogue.get("quarter_car"), catalogue.scenes("quarter_car")[1]

    def refuse(why):
        def runs(*args):
            raise why
        return runs
    monkeypatch.setattr(pruning, "_runs", refuse(NotApplicable("needs an affine map")))
    out = pruning.measure(system, scene, None, None, catalogue, sources=("mujoco",))
    assert out["sources"]["mujoco"] == {"skipped": "needs an affine map"}
    monkeypatch.setattr(pruning, "_runs", refuse(ValueError("not enough values to unpack (expected 4, got 3)")))
    with pytest.raises(ValueError, match="not enough values to unpack"):
        pruning.measure(system, scene, None, None, catalogue, sources=("mujoco",))


def test_mujocos_pruning_run_of_a_chain_whose_rows_act_is_its_constrained_tree():
    """MuJoCo's pruning runs step the exported tree, which has no equality rows: where a closed chain's rows act
    (the toggle press) that is not the scene's motion. There MuJoCo steps the closures plug-in's equality-constrained
    tree, its loads as site actuators (the idle ones' gears 0): the pruned run is the scene's motion (within the soft
    constraints' first-order error at this dt, 2.2e-3 against our derivation; the open tree does not keep the slide
    on its axis), equal to the idle one, and the acting tree of its bound keeps the rows, the return spring's tendon
    and the sites they join, and steps the same motion."""
    from harness.catalogue import repository
    from harness.modeling.scenes import with_idle_effects
    from harness.scenes import simulate as sim
    from harness.scenes.effects import infer
    from harness.scenes.phenomena import motion_of
    from harness.scenes.phenomena.pruning import ACTING_ROWS, constrained_runs, measure

    catalogue = repository()
    system = catalogue.get("toggle_press")
    scene = next(s for s in catalogue.scenes("toggle_press") if s.name == "return")
    motion, event = motion_of(scene)
    out = measure(system, scene, motion, event, catalogue, sources=("mujoco",))["sources"]["mujoco"]
    assert out["method"].startswith("equality-constrained tree (its rows act: at q = ")
    assert "loads as site actuators" in out["method"] and out["error"] == 0.0   # pruned = idle, bit for bit
    found = infer(system, scene)
    lean_system, lean_scene = found.pruned(system, scene)
    lean, _, _, (acting, what) = constrained_runs(lean_system, lean_scene, *with_idle_effects(system, scene), found)
    reference = sim.integrate(lean_system, lean_scene, "symbolic", rtol=1e-10, atol=1e-10)
    pruned_run = lean()
    assert sim.max_error(reference, pruned_run) < 1e-2
    run = acting()()
    assert what == ACTING_ROWS and "equality constraints" in run.source and run.evaluations == 4000
    assert found.simulated == {"gravity", "springs"} and sim.max_error(pruned_run, run) < 1e-12


def test_loads_of_inputs_alone_are_mujocos_site_actuators():
    """The toggle press's knee force (0, −f, 0) and load force (−f_L, 0, 0), forces in world axes linear in the
    inputs, as MuJoCo's site actuators with world-axis gears (``LoadActuators``): at drawn states and inputs the
    generalized force MuJoCo's actuators apply (``qfrc_actuator``) is the one MuJoCo's ``mj_applyFT`` gives for the
    same loads (``MujocoModel.applied``, what a run evaluated in Python applies). A torque, a force that reads the state
    or one not 0 at zero inputs is not such a load."""
    import dataclasses

    import mujoco
    import sympy as sp

    from harness.catalogue import repository
    from harness.engines.mujoco_engine import MujocoModel
    from harness.export.numeric import instantiate
    from harness.modeling.scenes import effects_of
    from harness.modeling.system import PointForce
    from harness.scenes import simulate as sim

    catalogue = repository()
    system = catalogue.get("toggle_press")
    params = system.default_parameters()
    actuators = sim.load_actuators(system, params)
    assert [e[:3] for e in actuators.entries] == [("knee_force:f", "f", "knee"), ("load_force:f_L", "f_L", "e")]
    mm = MujocoModel(instantiate(system, params), transforms=[actuators])
    every = dataclasses.replace(catalogue.scenes("toggle_press")[0], effects=frozenset(effects_of(system)))
    dyn = sim.Dynamics(system, every, "mujoco")    # its loads present
    rng = np.random.default_rng(7)
    largest = 0.0
    for _ in range(5):
        q, qd, u = rng.uniform(-0.3, 0.3, 1), rng.uniform(-1, 1, 1), rng.uniform(-50, 50, 2)
        theta, J, _ = dyn.c.map_at(q, qd, dyn.p, u)
        mm.set_state(theta, J @ qd)
        mm.set_inputs(dict(zip(dyn.input_names, u)))
        mujoco.mj_forward(mm.model, mm.data)
        applied = mm.applied(dyn.loads(q, qd, u))
        assert np.allclose(mm.data.qfrc_actuator[mm.dof_index], applied, rtol=1e-12, atol=1e-12 * np.abs(u).max())
        largest = max(largest, np.abs(applied).max())
    assert largest > 10.0
    assert sim.load_actuators(catalogue.get("two_mass_oscillator"), catalogue.get("two_mass_oscillator")
                              .default_parameters()) is None                       # torques
    q, f = sp.Symbol("q", real=True), sp.Symbol("f", real=True)
    for force in ((0, -f * sp.cos(q), 0), (0, -f - 1, 0)):                           # reads the state; 0 at no input
        other = dataclasses.replace(system, forces=tuple(
            dataclasses.replace(e, force=force) if isinstance(e, PointForce) and e.name == "knee_force" else e
            for e in system.forces))
        assert sim.load_actuators(other, params) is None


def test_every_acting_tree_steps_its_pruned_runs_motion():
    """MuJoCo's bound, the acting tree, is a model that simulates the scene: on every scene with something to prune
    that MuJoCo steps itself, its run is the pruned run's motion bit for bit (what it strips, the collision geoms,
    sensors and sites nothing joins, and the flags of effects that do not act, changes no number). A stripped
    element that acts would show here as a motion apart."""
    from harness.bench import _cases
    from harness.bench.workprecision import get_scene
    from harness.catalogue import repository
    from harness.modeling.scenes import with_idle_effects
    from harness.scenes import simulate as sim
    from harness.scenes.effects import infer
    from harness.scenes.phenomena import motion_of
    from harness.scenes.phenomena.pruning import _runs

    catalogue, compared = repository(), []
    for name, label in _cases(catalogue, None, None, quick=False):
        system, scene = get_scene(catalogue, name, label)
        found = infer(system, scene)
        (idle_system, idle_scene), (lean_system, lean_scene) = with_idle_effects(system, scene), found.pruned(system,
                                                                                                             scene)
        if (idle_scene is scene and lean_scene is scene) or scene.events:
            continue
        lean, _, _, (acting, _) = _runs(lean_system, lean_scene, idle_system, idle_scene, *motion_of(scene), "mujoco",
                                        catalogue, (system, scene, found))
        assert sim.max_error(lean(), acting()()) == 0.0, f"{name}/{label}"
        compared.append(f"{name}/{label}")
    assert len(compared) >= 10 and "toggle_press/return" in compared
