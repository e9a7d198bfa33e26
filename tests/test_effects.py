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
