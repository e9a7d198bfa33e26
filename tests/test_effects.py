"""Effects found, not declared (harness/scenes/effects.py): which effects can act in a scene, inferred from its
parameter values, inputs and the geometry, beside the declared ones; the disagreement is reported."""

from hypothesis import given, settings, strategies as st

import models
from harness.modeling import (WORLD, Constant, Coordinate, Gravity, Input, Joint, JointDamper, JointInput,
                              JointSpring, Link, Parameter, Scene, Sine, Step, System, standard_gravity)
from harness.modeling.scenes import Bump
from harness.scenes.effects import infer, zero_over

m = Parameter("m", 1.0, "kg", "point mass")
l = Parameter("l", 0.5, "m", "rod length")
c = Parameter("c", 3.0, "N m/rad", "torsion spring")
d = Parameter("d", 0.2, "N m s/rad", "joint damper")
g = standard_gravity()
phi = Coordinate("phi", "rad", "angle of the rod")
tau = Input("tau", "N m", "torque on the joint")


def pendulum(axis: str) -> System:
    """A point-mass pendulum turning about ``axis`` under gravity along -z, with a spring, a damper and a torque:
    about x it swings in a vertical plane, about z in a horizontal one."""
    return System(name=f"pendulum_{axis}", title="test pendulum", lecture="test", coordinates=(phi,),
                  links=(Link("bob", m, (0, -l, 0) if axis == "z" else (0, 0, -l)),),
                  joints=(Joint("phi", "revolute", WORLD, "bob", axis=axis),),
                  gravity=Gravity(g, (0, 0, -1)),
                  forces=(JointSpring("spring", "phi", c), JointDamper("damper", "phi", d),
                          JointInput("motor", "phi", tau)))


EVERY = {"gravity", "springs", "dampers", "inputs"}


def test_a_damper_at_zero_is_inferred_idle():
    found = infer(pendulum("x"), Scene("s", "", (0.3,), (0.0,), 1.0, EVERY, inputs={tau: Constant(1.0)},
                                       params={d: 0.0}))
    assert found.acting == {"gravity", "springs", "inputs"}
    assert "d = 0" in found.idle["dampers"]
    assert found.declared_idle == {"dampers"} and not found.agrees
    assert "dampers" in found.notes()["effects disagreement: declared but cannot act"]


def test_an_input_of_zero_is_inferred_idle():
    for signal in (None, Constant(0.0), Step(2.0, 1.0), Sine(0.0, 1.0)):
        inputs = {} if signal is None else {tau: signal}
        found = infer(pendulum("x"), Scene("s", "", (0.3,), (0.0,), 1.0, EVERY - {"inputs"}, inputs=inputs))
        assert found.acting == EVERY - {"inputs"} and found.agrees, signal
        assert "tau ≡ 0" in found.idle["inputs"]


def test_a_pendulum_in_a_horizontal_plane_has_no_gravity():
    """Gravity along the joint axis: ∂V_gravity/∂q ≡ 0 for every motion; about x it acts."""
    flat = infer(pendulum("z"), Scene("s", "", (0.3,), (0.0,), 1.0, EVERY, inputs={tau: Constant(1.0)}))
    assert "gravity" not in flat.acting and "orthogonal" in flat.idle["gravity"]
    assert flat.declared_idle == {"gravity"}
    upright = infer(pendulum("x"), Scene("s", "", (0.3,), (0.0,), 1.0, EVERY, inputs={tau: Constant(1.0)}))
    assert upright.acting == EVERY and upright.agrees and not upright.idle


def test_gravity_of_zero_and_an_undeclared_effect():
    found = infer(pendulum("x"), Scene("s", "", (0.3,), (0.0,), 1.0, {"springs"}, params={g: 0.0}))
    assert "g = 0" in found.idle["gravity"]
    assert found.undeclared_acting == {"dampers"}   # d = 0.2 acts; the scene leaves it out
    assert "dampers" in found.notes()["effects disagreement: can act but not declared"]


@settings(max_examples=25, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.1, 5.0), st.floats(0.0, 3.0))
def test_zero_over_is_a_bound(height, duration, start):
    """A signal said to be 0 over the horizon is 0 at every sampled time of it; one with a nonzero part is not."""
    horizon = 2.0
    bump = Bump(height, start, duration)
    zero = zero_over(bump, horizon)
    values = [bump(t) for t in [horizon * k / 400 for k in range(401)]]
    if zero:
        assert max(map(abs, values)) == 0
    elif height > 0 and start + duration / 2 <= horizon:
        assert max(map(abs, values)) > 0


def test_catalogue_scenes():
    """What the lecture's scenes show: the governor coasts without its torque; the stick-slip block slides in a
    horizontal plane (gravity cannot act); the planar manipulator's free swing leaves out a spring and a damper
    that can act (a disagreement, reported)."""
    coast = infer(models.get("governor"), next(s for s in models.scenes("governor") if s.name == "coast"))
    assert coast.agrees and "inputs" in coast.idle
    block = infer(models.get("stick_slip"), models.scenes("stick_slip")[0])
    assert "gravity" in block.idle and "orthogonal" in block.idle["gravity"]
    swing = infer(models.get("planar_manipulator"),
                  next(s for s in models.scenes("planar_manipulator") if s.name == "swing"))
    assert swing.undeclared_acting == {"springs", "dampers"}


def test_mujoco_disable_flags_are_a_spec_transform():
    """Options(disable=…) sets the pruned effects' flags on the exported spec; enable clears them."""
    import mujoco

    from harness.engines.mujoco_engine import MujocoModel, Options, effect_flags
    from harness.export.numeric import instantiate

    system = pendulum("x")
    tree = instantiate(system, system.default_parameters())
    assert effect_flags({"springs", "dampers", "inputs", "external"}) == ("actuation", "damper", "spring")
    off = MujocoModel(tree, transforms=(Options(disable=effect_flags({"gravity", "springs"})),))
    bits = mujoco.mjtDisableBit
    assert off.model.opt.disableflags & bits.mjDSBL_GRAVITY and off.model.opt.disableflags & bits.mjDSBL_SPRING
    assert not off.model.opt.disableflags & bits.mjDSBL_DAMPER
    on = MujocoModel(tree, transforms=(Options(enable=("gravity",)),))
    assert not on.model.opt.disableflags & bits.mjDSBL_GRAVITY


def test_a_pruned_mjcf_drops_the_visual_geoms_and_moves_the_same_bit_for_bit():
    """VisualGeomsDropped leaves out our export's visual-only geoms (no contact, no mass: the inertia is explicit):
    the same RK4 steps give the same state to the last bit, with no geom left to pose."""
    import mujoco
    import numpy as np

    from harness.engines.mujoco_engine import MujocoModel, Options, VisualGeomsDropped
    from harness.export.numeric import instantiate

    system = models.get("planar_manipulator")
    tree = instantiate(system, system.default_parameters())
    rk4 = Options(timestep=1e-3, integrator="RK4")
    drawn, bare = MujocoModel(tree, transforms=(rk4,)), MujocoModel(tree, transforms=(rk4, VisualGeomsDropped()))
    assert drawn.model.ngeom > 0 and bare.model.ngeom == 0
    for model in (drawn, bare):
        model.reset()
        model.set_state(np.array([0.3, -0.7]), np.array([1.0, 0.5]))
        mujoco.mj_step(model.model, model.data, nstep=200)
    assert np.array_equal(drawn.data.qpos, bare.data.qpos) and np.array_equal(drawn.data.qvel, bare.data.qvel)


def test_pruned_equals_idle_in_every_source_and_nothing_to_prune_has_no_ratio():
    """The per-source measurement (harness/scenes/phenomena/pruning.py) on a small scene: a damper at 0 and an
    input of 0 left out; the pruned trajectory equals the idle one in each source; a scene calling for every
    effect reports no ratio."""
    from harness.scenes.phenomena import motion_of
    from harness.scenes.phenomena.pruning import measure

    system = pendulum("x")
    scene = Scene("s", "", (0.3,), (0.0,), 0.5, {"gravity", "springs"}, params={d: 0.0})
    motion, event = motion_of(scene)
    out = measure(system, scene, motion, event, repeats=1)
    assert out["left_out"] == ["dampers", "inputs"]
    assert set(out["sources"]) == {"symbolic", "pinocchio", "mujoco"}
    for source, m in out["sources"].items():
        assert m["error"] <= 1e-6 and m["ratio"] > 0, source
    assert "disable flags actuation, damper" in out["sources"]["mujoco"]["method"]
    every = Scene("e", "", (0.3,), (0.0,), 0.5, EVERY, inputs={tau: Constant(1.0)})
    assert "nothing" in measure(system, every, motion, event, repeats=1)


def test_an_idle_force_element_is_pruned_in_every_source():
    """Pruning per element: the quarter car on a smooth road has its tyre damper at d_R = 0 beside the acting
    suspension damper; the pruned model has no tyre damper (nor the road force), in the symbolic right-hand side,
    Pinocchio's model and the MJCF, and each source's pruned trajectory equals its idle one."""
    from harness.derivation.derive import derive
    from harness.modeling.scenes import EFFECTS, pruned
    from harness.scenes.base import ENGINE
    from harness.scenes.phenomena import motion_of
    from harness.scenes.phenomena.pruning import measure

    system = models.get("quarter_car")
    scene = next(s for s in models.scenes("quarter_car") if s.name == "smooth_road")
    found = infer(system, scene)
    assert set(found.idle_elements) == {"tyre_damper"} and "d_R = 0" in found.idle_elements["tyre_damper"]
    assert found.simulated == {"gravity", "springs", "dampers"}
    lean_system, lean_scene = found.pruned(system, scene)
    assert [f.name for f in lean_system.forces] == ["tyre_spring", "road", "suspension_spring", "suspension_damper"]
    assert lean_scene.effects == found.simulated
    assert [f.name for f in pruned(system, EFFECTS, without={"road"}).forces if f.name == "road"] == []
    d_R = next(p.symbol for p in system.parameters if p.name == "d_R")
    assert d_R not in derive(pruned(lean_system, lean_scene.effects)).f_np.free_symbols

    motion, event = motion_of(scene)
    out = measure(system, scene, motion, event, repeats=1, found=found)
    assert out["left_out"] == ["external"] and out["left_out_elements"] == ["tyre_damper"]
    assert set(out["sources"]) == {"symbolic", "pinocchio", "mujoco"}
    for source, m in out["sources"].items():
        assert m["error"] <= ENGINE.value and m["ratio"] > 0, source
    assert "not in the MJCF: road, tyre_damper" in out["sources"]["mujoco"]["method"]   # the load left out too


def test_a_declared_effect_found_idle_is_pruned_and_nothing_idle_is_nothing_to_prune():
    """A scene that declares every effect: with the damper at 0 the pruned run leaves the dampers out (the
    pruned = idle check proves the inference); with everything acting there is nothing to prune."""
    from harness.scenes.phenomena import motion_of
    from harness.scenes.phenomena.pruning import measure

    system = pendulum("x")
    scene = Scene("s", "", (0.3,), (0.0,), 0.5, EVERY, inputs={tau: Constant(1.0)}, params={d: 0.0})
    motion, event = motion_of(scene)
    out = measure(system, scene, motion, event, sources=("symbolic", "mujoco"), repeats=1)
    assert out["left_out"] == ["dampers"] and out["left_out_elements"] == []
    assert all(m["error"] <= 1e-6 for m in out["sources"].values())
    assert "disable flags damper" in out["sources"]["mujoco"]["method"]


def test_a_friction_that_never_switches_is_proved_by_a_bound():
    """The stick-slip mass (Section 3.5.2) from rest under f_e = 0.8 mu_H m g sin(pi t): the force sticking needs
    is at most 0.8 mu_H f_N over the horizon (a bound, not a sample), so it sticks throughout (3.80a): friction acts
    without switching and the sliding friction, 0 at ẋ = 0, cannot act. The event-located simulation (ours,
    Pinocchio's) has no event and x ≡ 0, and the pruned run equals the idle one. The lecture's scene
    (1.2 mu_H m g) can switch: nothing is inferred."""
    import dataclasses

    from harness.scenes.phenomena import motion_of
    from harness.scenes.phenomena.pruning import measure
    from harness.scenes.phenomena.stick_slip import stick_slip

    system, lecture = models.get("stick_slip"), models.scenes("stick_slip")[0]
    assert not infer(system, lecture).never_switches
    mu_H_f_N = 0.3 * 1.0 * 9.81
    holds = dataclasses.replace(lecture, name="holds", inputs={"f_e": Sine(0.8 * mu_H_f_N, 0.5)})
    found = infer(system, holds)
    assert "never switches" in found.never_switches["friction"] and "friction" in found.acting
    assert "q̇ = 0" in found.idle["external"] and found.declared_idle == {"external"}
    assert "never switches" in found.notes()
    over = dataclasses.replace(holds, inputs={"f_e": Sine(1.001 * mu_H_f_N, 0.5)})
    assert not infer(system, over).never_switches
    motion, event = motion_of(holds)
    for source in ("symbolic", "pinocchio"):
        run = stick_slip(system, holds, event, source)
        assert run.events == [] and abs(run.q).max() == 0, source
    out = measure(system, holds, motion, event, sources=("symbolic", "pinocchio"), repeats=1, found=found)
    assert out["left_out"] == ["external", "gravity"]
    assert all(m["error"] <= 1e-6 for m in out["sources"].values())
    # pruned, the friction is held: no breakaway guard along the horizon, nothing integrated; the idle run looks.
    # MuJoCo: its own frictionloss run (the plug-in's) against nothing to step
    _, lean = found.pruned(system, holds)
    assert [e.held for e in lean.events] == [True] and [e.held for e in holds.events] == [False]
    out["sources"].update(measure(system, holds, motion, event, sources=("mujoco",), repeats=1,
                                  found=found)["sources"])
    assert out["sources"]["mujoco"]["error"] <= 1e-6 and "frictionloss" not in out["sources"]["mujoco"]["method"]
    for m in out["sources"].values():
        pruned_evaluations, idle_evaluations = m["evaluations"]
        assert pruned_evaluations == 0 < idle_evaluations and "friction held" in m["method"]
    assert not any(e.held for e in infer(system, over).pruned(system, over)[1].events)  # it can switch: looked for


@given(st.sampled_from(["constant", "step", "sine", "bump", "rate"]), st.floats(-3.0, 3.0), st.floats(-3.0, 3.0),
       st.floats(0.05, 4.0))
def test_bound_over_bounds_every_signal(kind, a, b, c):
    """``bound_over`` is an upper bound of |u(t)| over the horizon (the sticking proof rests on it)."""
    from harness.scenes.effects import bound_over

    horizon = 2.0
    signal = {"constant": Constant(a), "step": Step(c, a, b), "sine": Sine(a, c, b),
              "bump": Bump(a, b % horizon, c), "rate": Bump(a, b % horizon, c, rate=True)}[kind]
    bound = bound_over(signal, horizon)
    assert max(abs(signal(horizon * k / 2000)) for k in range(2001)) <= bound * (1 + 1e-12) + 1e-15


def test_constraint_rows_are_inactive_only_where_the_open_tree_keeps_them():
    """The governor's coupling (arm 2 the mirror image of arm 1) needs no force: the tree's balance at the motion's
    q̈ is proved 0. Every other constrained tree of the catalogue needs its rows (a rope, a gear, a rolling
    contact, a closed chain): a random state is the counterexample. A governor with arms of unequal length needs
    its coupling (they swing at different rates): the proof rests on the symmetry, not on the model's name. Unequal
    masses alone would not: a point mass on a massless arm swings as its pendulum whatever its mass."""
    import dataclasses

    from harness.scenes.effects import constraint_rows_idle

    for name, system in models.catalogue().items():
        if len(system.joints) <= len(system.coordinates):
            continue
        idle, why = constraint_rows_idle(system, system.default_parameters())
        if name == "governor":
            assert idle and "proved" in why
        else:
            assert not idle and "asks the constraints for" in why, name
    governor = models.get("governor")
    longer = Parameter("l_2", 0.7, "m", "the second arm's length")
    lopsided = dataclasses.replace(governor, name="governor_lopsided", links=tuple(
        dataclasses.replace(link, com=(0, 0, -longer)) if link.name == "arm_2" else link for link in governor.links))
    idle, why = constraint_rows_idle(lopsided, lopsided.default_parameters())
    assert not idle and "asks the constraints for" in why
    coast = infer(governor, next(s for s in models.scenes("governor") if s.name == "coast"))
    assert coast.rows[0] and "constraint rows inferred inactive" in coast.notes()
